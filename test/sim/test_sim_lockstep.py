# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The loop in lockstep (tray_sim ``lockstep``, tilt_controller ``lockstep``, the Loop's
default): the tray advances only once the command answering its last pose has arrived,
so a closed-loop run is the same on any machine. Checked two ways: the tray alone (no
step without the answer, an answer to an older pose is none, the timeout counted), and
the whole loop run twice on the same models, once on a quiet machine and once beside two
busy processes: the same verdicts, letters, events and final poses, bit for bit; and
the controller's SEATED agrees with the tray's truth on every run."""

import math
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from wrenchcone_msgs.msg import TiltCommand  # noqa: E402

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.core.tilt import STANDARD_GRAVITY  # noqa: E402
from wrenchcone_ros.core.plan import sample_models  # noqa: E402
from wrenchcone_ros.core.simulate import DEFAULT_TILT  # noqa: E402
from wrenchcone_ros.sim.loop import Loop  # noqa: E402
from wrenchcone_ros.sim.tray import TrayPhysics  # noqa: E402
from wrenchcone_ros.sim.tray_sim import TraySimNode  # noqa: E402
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: E402

pytestmark = pytest.mark.slow  # closed-loop runs over DDS

ROOT = Path(__file__).resolve().parents[2]
PAWL = ROOT / "examples" / "pawl_seating.yaml"
FRICTION = (0.2, 0.4)
A10 = STANDARD_GRAVITY * math.sin(DEFAULT_TILT)  # m/s^2: a tray tilted by 10 degrees
SLIDE = math.radians(-58.5)  # the pawl's first segment: slide right on pins 2 and 3


def test_a_lockstep_tray_steps_only_on_the_answer_to_its_last_pose(ros_context):
    tray = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False, parameter_overrides=[
                           Parameter("lockstep", value=True),
                           Parameter("lockstep_timeout", value=0.3)])
    probe = Node("lockstep_probe", context=ros_context)
    poses: list[PoseStamped] = []
    probe.create_subscription(PoseStamped, "workpiece_pose", poses.append, 100)
    pub = probe.create_publisher(TiltCommand, "tilt_command", 10)
    spinner = ExecutorThread(ros_context)
    spinner.add_node(tray)
    spinner.add_node(probe)

    def answer(stamp) -> None:
        msg = TiltCommand(direction=SLIDE, magnitude=A10)
        msg.header.stamp = stamp
        pub.publish(msg)

    def wait(cond, limit: float = 10.0) -> bool:
        end = time.monotonic() + limit
        while not cond() and time.monotonic() < end:
            time.sleep(0.01)
        return cond()

    try:
        tray.lockstep_timeout = 60.0  # no step without the answer in this part
        tray.thread.start()
        assert wait(lambda: len(poses) >= 1)
        first = poses[0]
        clock = tray.physics.clock
        time.sleep(0.3)  # nothing answers: the tray waits
        assert tray.physics.clock == clock and tray.lockstep_timeouts == 0
        answer(first.header.stamp)
        assert wait(lambda: tray.physics.clock > clock)
        assert wait(lambda: any(p.header.stamp != first.header.stamp for p in poses))
        second = [p for p in poses if p.header.stamp != first.header.stamp][0]
        clock = tray.physics.clock
        answer(first.header.stamp)  # an answer to an older pose is not one
        time.sleep(0.3)
        assert tray.physics.clock == clock
        answer(second.header.stamp)
        assert wait(lambda: tray.physics.clock > clock)
        # a controller that stops answering: the tray steps after the timeout, counted
        tray.lockstep_timeout = 0.3
        assert wait(lambda: tray.lockstep_timeouts >= 2)
        assert tray.pause()  # parked between two steps: the clock stands
        clock = tray.physics.clock
        time.sleep(0.5)
        assert tray.physics.clock == clock
    finally:
        tray.stop()
        spinner.stop()
        probe.destroy_node()
        tray.destroy_node()


def _runs(models) -> list:
    with Loop(PAWL, [1, 2, 3], FRICTION, controller_parameters={"reuse_plan": True}) as loop:
        return [loop.run(m, timeout=300.0) for m in models]


def _outcome(r) -> tuple:
    return (r.seated, r.state, r.reason, r.plans, r.modes, r.events, r.letters,
            r.final_pose, r.sim_time)


def test_lockstep_runs_are_the_same_beside_busy_processes():
    scene = load_scene(PAWL)
    models = sample_models(scene, Uncertainty(friction=FRICTION), 2, 0)
    quiet = _runs(models)
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        loaded = _runs(models)
    finally:
        for proc in busy:
            proc.kill()
            proc.wait()
    for r in quiet + loaded:
        assert r.lockstep_timeouts == 0, r.reason
        # the controller's word agrees with the tray's truth
        assert (r.state == "SEATED") == r.seated, (r.state, r.reason, r.letters)
    assert [_outcome(r) for r in quiet] == [_outcome(r) for r in loaded]
    assert all(r.seated for r in quiet), [(r.state, r.reason) for r in quiet]
