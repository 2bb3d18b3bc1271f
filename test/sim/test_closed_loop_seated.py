# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The controller knows when it is done: no run ends TIMEOUT on a part at rest in its
seat. The pawl of examples/pawl_seating.yaml, in the lockstep loop; the wrenchcone node
is started on the same fixture file with every pin 8 um bigger than the tray's. The
tray's fixture message (wrenchcone_msgs/Fixels) then gives the node the true radii: it
sees the part seated and the controller says SEATED. (Before the node took the radii
from the fixture message, it saw the seated part pressed into the stop, refused the
pose, and the controller held at every step until the run ended TIMEOUT with the part
seated; a controller whose node refuses the pose of a part at rest now treats it as a
deviation at once, within its bounds: plans, back-offs, open loop, each step said on
``~/state``.)"""

import threading
from dataclasses import replace
from pathlib import Path

import pytest
import yaml

pytest.importorskip("pymunk")

from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from wrenchcone_ros.core.plan.execution import trace  # noqa: E402
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND  # noqa: E402
from wrenchcone_ros.node.plan_action import segment_message  # noqa: E402
from wrenchcone_ros.sim.loop import Loop, node_parameters  # noqa: E402
from wrenchcone_ros.sim.tilt_controller import Observation, TiltControllerNode  # noqa: E402
from wrenchcone_ros.node.inprocess import NodeFactory  # noqa: E402
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: E402

pytestmark = pytest.mark.slow  # closed-loop runs over DDS

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
BIGGER = 8e-6  # m: the node's pins are this much bigger than the tray's


def test_a_part_at_rest_in_its_seat_never_ends_the_run_timeout(tmp_path):
    data = yaml.safe_load(PAWL.read_text())
    for f in data["fixels"]:
        f["radius"] += BIGGER
    # the file's own pose check at the node's tolerance (the pose comes from the tray)
    data["contact_tolerance"] = 8.35e-6
    node_file = tmp_path / "pawl_pins_bigger.yaml"
    node_file.write_text(yaml.safe_dump(data))
    with Loop(PAWL, [1, 2, 3], node_scene=node_file, sim_timeout=10.0) as loop:
        r = loop.run(timeout=300.0)
        states = list(loop.controller.log.states)
    assert r.lockstep_timeouts == 0
    assert r.seated, (r.state, r.reason, r.letters)  # the tray's truth: at rest, seated
    assert r.state != "TIMEOUT", r.reason
    # the tray publishes its fixture (wrenchcone_msgs/Fixels, the true radii), which
    # replaces the file's bigger pins in the node: it sees the part seated, as the truth
    # (before the node took radii from the fixture message, it refused the pose here and
    # the controller ended FAILED, saying so, instead of TIMEOUT)
    assert r.state == "SEATED", (r.state, r.reason)
    # its replans are bounded and counted in the reasons it published
    assert r.plans <= loop.controller.max_plans
    assert any(s == "PLANNING" and f"of at most {loop.controller.max_plans}" in why
               for s, why in states), states


@pytest.mark.parametrize("where", ["seat", "start"])
def test_the_seat_is_judged_by_the_nodes_contacts_as_the_engine_reads_them(
        ros_context, tmp_path, where):
    """The controller's judgement of the seat (its ``_in_seat``: every target fixel in
    contact by the node's word, the part at rest) against the engine's: at the pose
    where the open loop's run of the pawl ends (every target gap within the engine's
    contact band) it says SEATED; at the start (8 mm off the stop) it does not. The
    node is told the pose by its scene file, as in test_sim_controller_events."""
    scene = load_scene(PAWL)
    plan = plan_seating(scene, [1, 2, 3], "tilt", runs=0)
    result, frames = trace(scene, plan, None, record_every=1)
    assert result.success
    band = SIM_CONTACT_BAND * scene.length_scale
    last = frames[-1].readout
    assert all(g <= band for g in last.gaps)  # the engine's truth: seated
    pose = tuple(last.pose) if where == "seat" else tuple(scene.pose)
    factory = NodeFactory(ros_context.get_domain_id(), tmp_path)
    factory.make(replace(scene, contact_tolerance=band).with_pose(*pose),
                 parameters=node_parameters(scene, None))
    spinner = ExecutorThread(ros_context, SingleThreadedExecutor, name="seat-test")
    ctl = TiltControllerNode(context=ros_context, start=False, parameter_overrides=[
        Parameter("target", value=[1, 2, 3])])
    spinner.add_node(ctl)
    try:
        ctl.thread = threading.current_thread()  # the test runs the step
        ctl.segments, ctl.k = [segment_message(plan, s) for s in plan.segments], 0
        ctl.log.plans = 1
        # as after its first plan (the states allow no step before one)
        ctl.states.enter("PLANNING", "plan 1 of the test")
        ctl.states.enter("EXECUTING", "plan 1 of the test")
        assert ctl.client.wait_for_service(10.0)
        at_rest = [Observation(0.005 * i, pose) for i in range(100)]  # 0.5 s, not moving
        assert ctl._in_seat(at_rest) == (where == "seat"), (ctl.state, ctl.reason)
        assert (ctl.state == "SEATED") == (where == "seat"), (ctl.state, ctl.reason)
        moving = [Observation(0.005 * i, (pose[0] + 1e-4 * i, pose[1], pose[2]))
                  for i in range(100)]
        ctl.state = "HOLDING"
        assert not ctl._in_seat(moving)  # not at rest: no verdict, not even asked
    finally:
        ctl.thread = None
        spinner.stop()
        ctl.destroy_node()
        factory.close()
