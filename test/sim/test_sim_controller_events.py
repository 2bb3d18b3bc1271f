# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller never does worse than executing its own plan (the open loop,
wrenchcone_ros.core.plan.execution.trace), over real DDS against a wrenchcone node:

* the plan's contact event switches segments as the open loop switches them, when the
  segment's fixels are reached, also while the impact's bounce has lifted the part off
  other contacts (the engine's own bounce: a pose of the open loop's trace, where the
  stop touches and a pin under the foot is off by more than the contact tolerance). The
  next segment's mode is not allowed there for a moment; the part is pressed home by the
  hold's tilt, not pushed on against the stop;
* under the hold's tilt a part that still moves is settling, for at most hold_limit s
  (pose stamps): then it is a deviation (a part that left the fixture never rests);
* with neither a plan from where the part is nor a back-off, the controller goes on with
  the plan it has, open loop, and says so: OPEN_LOOP on ``~/state`` with its reason, WARN
  in /diagnostics, commands going on (not FAILED with the tray left as it was).
"""

import math
import threading
import time
from dataclasses import replace

import pytest

pytest.importorskip("pymunk")

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from helpers.seating_family import seating_family  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from wrenchcone_msgs.msg import ControllerState, Status  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from wrenchcone_ros.core.plan.execution import trace  # noqa: E402
from wrenchcone_ros.node.plan_action import segment_message  # noqa: E402
from wrenchcone_ros.sim.loop import LOOP_CONTACT_TOLERANCE, node_parameters  # noqa: E402
from wrenchcone_ros.sim.tilt_controller import Observation, TiltControllerNode  # noqa: E402
from wrenchcone_ros.node.inprocess import NodeFactory  # noqa: E402
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: E402

FRICTION = (0.2, 0.4)


@pytest.fixture(scope="module")
def bounce():
    """The seating family's second task (the pawl 2 mm from its stop, mu in [0.2, 0.4]),
    its plan (arr -> nnn, the event: fixel 1 reached) and the first pose of the open
    loop's run (nominal model) after that event where the stop is in contact and pin 2 or
    pin 3 is off the foot by more than the contact tolerance: the impact's bounce."""
    task = seating_family(2)[1]
    scene = load_scene(task.scene)
    plan = plan_seating(scene, [1, 2, 3], "tilt", uncertainty=FRICTION, runs=0)
    assert [s.mode for s in plan.segments] == ["arr", "nnn"]
    result, frames = trace(scene, plan, None, record_every=1)
    assert result.success  # the open loop seats it
    tol = LOOP_CONTACT_TOLERANCE * scene.length_scale
    lifted = [f.readout.pose for f in frames if f.segment == 1
              and abs(f.readout.gaps[0]) <= tol and max(f.readout.gaps[1:]) > tol]
    assert lifted, "the engine shows no bounce after the impact"
    return scene, plan, lifted[0], tol


@pytest.fixture
def rig(ros_context, tmp_path, bounce):
    """A wrenchcone node that sees the part at the bounce pose (its scene at that pose,
    the loop's parameters), a controller in the test's context, a listener of its state
    and diagnostics."""
    scene, plan, pose, _ = bounce
    factory = NodeFactory(ros_context.get_domain_id(), tmp_path)
    # the engine's pose overlaps the stop by a few micrometres: within the loop's
    # tolerance, not the scene file's 1e-9 m (the node is given the loop's anyway)
    scene_at = replace(scene, contact_tolerance=LOOP_CONTACT_TOLERANCE * scene.length_scale)
    factory.make(scene_at.with_pose(*pose), parameters=node_parameters(scene, FRICTION))
    spinner = ExecutorThread(ros_context, SingleThreadedExecutor, name="events-test")
    ctl = TiltControllerNode(context=ros_context, start=False, parameter_overrides=[
        Parameter("target", value=[1, 2, 3]), Parameter("friction", value=list(FRICTION))])
    listener = Node("listener", context=ros_context)
    heard = {"state": [], "diag": []}
    listener.create_subscription(ControllerState, "/tilt_controller/state",
                                 heard["state"].append, 100)
    listener.create_subscription(DiagnosticArray, "/diagnostics", heard["diag"].append, 100)
    spinner.add_node(ctl)
    spinner.add_node(listener)
    ctl.thread = threading.current_thread()  # the test's thread runs the control steps
    ctl.segments, ctl.k = [segment_message(plan, s) for s in plan.segments], 0
    ctl.log.plans = 1
    # as after its first plan (the states allow no step before one)
    ctl.states.enter("PLANNING", "plan 1 of the test")
    ctl.states.enter("EXECUTING", "plan 1 of the test")
    assert ctl.client.wait_for_service(10.0)
    # volatile topics: a message published before the listener is matched is lost, so
    # the listener must be matched on both before the test makes the controller speak
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline and not (
            ctl.state_pub.get_subscription_count() and ctl.diag_pub.get_subscription_count()):
        time.sleep(0.01)
    assert ctl.state_pub.get_subscription_count() and ctl.diag_pub.get_subscription_count()
    yield ctl, heard, pose_message(pose)
    ctl.thread = None
    spinner.stop()
    ctl.destroy_node()
    listener.destroy_node()
    factory.close()


def pose_message(pose, stamp: float = 1.0) -> PoseStamped:
    msg = PoseStamped()
    msg.header.stamp.sec = int(stamp)
    msg.header.stamp.nanosec = int(round((stamp - int(stamp)) * 1e9))
    msg.pose.position.x, msg.pose.position.y = pose[0], pose[1]
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(pose[2] / 2), math.cos(pose[2] / 2)
    return msg


def test_the_fixels_a_segment_reaches_are_read_from_the_plans_modes():
    from wrenchcone_ros.sim.tilt_controller import reached_fixels

    assert reached_fixels("arr", "nnn") == [0]
    assert reached_fixels("na", "nn") == [1]
    assert reached_fixels("rar", "nnn") == [1]
    assert reached_fixels("aas", "ans") == [1]  # fixel 1 still approaching, 3 not a target
    assert reached_fixels("nnn", "nnn") == []


def test_the_plans_event_switches_segments_during_the_impacts_bounce(rig, bounce):
    ctl, _, msg = rig
    _, plan, pose, _ = bounce
    hold = plan.segments[-1]
    # the node agrees that the hold's mode is not possible at this pose (a pin is off)
    assert ctl.client.force_directions("nnn", exclusive=True).status == Status.MODE_NOT_ALLOWED
    why = ctl._step(msg, [Observation(1.0, tuple(pose))])
    assert ctl.k == 1, (ctl.state, ctl.reason)  # the hold, as the open loop
    assert ctl.log.events and ctl.log.events[0][1:] == (1, "nnn")
    assert ctl.last_direction == pytest.approx(hold.direction)
    assert ctl.state == "HOLDING" and why is None, (ctl.state, ctl.reason, why)


def test_the_event_is_answered_before_the_segments_directions_are_asked(rig, bounce):
    """At the impact the controller asks first whether the reached fixel touches (one
    cone) and commands the hold's direction at once: no force_directions call (two of
    them, some 20 ms of the node's time each, when the event was asked last) comes
    between the pose of the event and the hold's command."""
    ctl, _, msg = rig
    _, plan, pose, _ = bounce
    hold = plan.segments[-1]
    seen = []
    call, command = ctl._call, ctl._command

    def logged_call(service, *args, **kwargs):
        seen.append(service)
        return call(service, *args, **kwargs)

    def logged_command(direction, magnitude, stamp):
        seen.append(("command", round(direction, 9)))
        return command(direction, magnitude, stamp)

    ctl._call, ctl._command = logged_call, logged_command
    try:
        ctl._step(msg, [Observation(1.0, tuple(pose))])
    finally:
        ctl._call, ctl._command = call, command
    first = seen.index(("command", round(hold.direction, 9)))
    assert seen[:first] == ["get_cone"], seen
    assert ctl.k == 1 and ctl.log.events[0][1:] == (1, "nnn")


def test_a_hold_that_does_not_settle_is_a_deviation_after_hold_limit(rig, bounce):
    # under the hold's tilt a moving part is settling, not deviating, but only for
    # hold_limit s of pose time: a part that left the fixture never comes to rest
    ctl, _, msg = rig
    _, _, pose, _ = bounce
    ctl.k = 1
    moving = [Observation(0.5 + 0.01 * i, (pose[0] + 1e-3 * i, pose[1], pose[2]))
              for i in range(60)]  # 1 mm per 10 ms: not at rest
    assert ctl._step(msg, moving) is None  # settling
    later = pose_message(pose, stamp=1.0 + ctl.hold_limit + 0.1)
    why = ctl._step(later, moving)
    assert why is not None and why.startswith("unsettled"), why


def test_without_a_plan_or_a_back_off_the_controller_executes_its_plan_open_loop(rig, bounce):
    ctl, heard, msg = rig
    _, plan, pose, _ = bounce
    ctl.max_plans, ctl.max_backoffs = 1, 0  # no plan left to ask for, no back-off
    ctl._pose = msg
    assert ctl._recover(msg) is not None
    assert ctl.state == "OPEN_LOOP", (ctl.state, ctl.reason)
    assert "open loop" in ctl.reason
    n = ctl.log.commands
    assert ctl._step(msg, [Observation(1.0, tuple(pose))]) is None
    assert ctl.log.commands > n and ctl.state == "OPEN_LOOP", (ctl.state, ctl.reason)
    assert ctl.last_direction == pytest.approx(plan.segments[-1].direction)
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline and not any(
            s.state == "OPEN_LOOP" for s in heard["state"]):
        time.sleep(0.05)
    said = [s for s in heard["state"] if s.state == "OPEN_LOOP"]
    assert said and "open loop" in said[-1].reason

    def open_loop_levels():
        return [st.level for d in list(heard["diag"]) for st in d.status
                if st.message.startswith("OPEN_LOOP")]
    while time.monotonic() < deadline and not open_loop_levels():  # a topic of its own
        time.sleep(0.05)
    levels = open_loop_levels()
    assert levels and set(levels) == {DiagnosticStatus.WARN}
