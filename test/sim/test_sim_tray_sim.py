# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tray_sim node (wrenchcone_ros.sim.tray_sim). Between two runs: a command computed
for the part of before a reset never moves the part of after it, even when it is in
flight while the reset happens; after a reset the part stays where it was put until the
first command of the new run. Like a vision system: pose noise and latency as asked.
Its /clock drives nodes started with use_sim_time. The physics thread is not started:
the tests step the node themselves (step_once), so that what happens when is the test's
to say."""

import math
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pymunk")

from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from wrenchcone_msgs.msg import PlanarPose, TiltCommand  # noqa: E402
from wrenchcone_msgs.srv import ResetPose  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.tilt import STANDARD_GRAVITY  # noqa: E402
from wrenchcone_ros.core.simulate import DEFAULT_TILT  # noqa: E402
from wrenchcone_ros.sim.tray import TrayPhysics  # noqa: E402
from wrenchcone_ros.sim.tilt_controller import TiltControllerNode  # noqa: E402
from wrenchcone_ros.sim.tray_sim import TraySimNode, _time_msg, stamp_seconds  # noqa: E402
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: E402

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
A10 = STANDARD_GRAVITY * math.sin(DEFAULT_TILT)  # m/s^2: a tray tilted by 10 degrees
SLIDE = math.radians(-58.5)  # the pawl's first segment: slide right on pins 2 and 3


@pytest.fixture
def tray(ros_context):
    node = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False)
    yield node
    node.destroy_node()


def command(direction: float, magnitude: float, stamp) -> TiltCommand:
    msg = TiltCommand(direction=direction, magnitude=magnitude)
    msg.header.stamp = stamp
    return msg


def moved(tray: TraySimNode) -> float:
    """How far (m) the part is from the scene's start pose."""
    return math.dist(tray.physics.readout().pose[:2], tray.physics.start.pose[:2])


def test_a_command_in_flight_during_a_reset_does_not_move_the_new_part(tray):
    """The previous run's last command, computed from a pose of before the reset,
    reaches the tray's callback just before the reset and gets the lock just after it
    (the callback of a loaded executor): it is stale, and the part stays put."""
    tray.step_once()
    old_stamp = _time_msg(tray.physics.clock)  # a pose the previous run saw
    tray.step_once()
    stale = command(SLIDE, A10, old_stamp)
    with tray.lock:
        late = threading.Thread(target=tray._on_command, args=(stale,))
        late.start()
        time.sleep(0.2)  # the callback is waiting for the lock
        tray.physics.reset(None)
        tray.after_reset()
    late.join(5.0)
    for _ in range(40):  # 0.2 s of sim time: the pawl would slide millimetres
        tray.step_once()
    assert moved(tray) <= 1e-9
    assert tray.stale_commands == 1 and tray.physics.command.magnitude == 0.0


def test_a_command_from_the_last_pose_before_the_reset_is_stale(tray):
    """A pose published at the very instant of the reset belongs to the part of before
    it: a command stamped with it is stale too."""
    tray.step_once()
    with tray.lock:
        at_reset = _time_msg(tray.physics.clock)  # the last pose published
        tray.physics.reset(None)
        tray.after_reset()
    tray._on_command(command(SLIDE, A10, at_reset))
    for _ in range(40):
        tray.step_once()
    assert moved(tray) <= 1e-9 and tray.stale_commands == 1


def test_after_a_reset_the_part_is_held_until_the_new_runs_first_command(tray):
    """After a reset the engine is not stepped (the clock runs on) until a command of the
    new run arrives; from then on the part moves under it."""
    tray._on_command(command(SLIDE, A10, _time_msg(0.0)))
    for _ in range(20):
        tray.step_once()
    assert moved(tray) > 1e-4  # the first run moved the part
    with tray.lock:
        tray.physics.reset(None)
        tray.after_reset()
    t_reset = tray.physics.clock
    for _ in range(20):
        tray.step_once()
    assert moved(tray) <= 1e-9 and tray.physics.held
    dt = tray.physics.dt  # the engine's step: a publish period is whole steps of it
    assert tray.physics.clock == pytest.approx(t_reset + 20 * round(tray.period / dt) * dt)
    tray._on_command(command(SLIDE, A10, _time_msg(tray.physics.clock)))
    assert not tray.physics.held
    for _ in range(20):
        tray.step_once()
    assert moved(tray) > 1e-4


def test_pose_noise_is_gaussian_with_the_asked_deviations(ros_context):
    """pose_noise (m) and angle_noise (rad): the measured pose of a part at rest differs
    from the engine's by zero-mean noise of those standard deviations (400 samples: the
    sample deviation within 15 %, the mean within 4 standard errors)."""
    node = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False, parameter_overrides=[
                           Parameter("pose_noise", value=1e-3),
                           Parameter("angle_noise", value=2e-3), Parameter("seed", value=3)])
    try:
        true = node.physics.readout().pose
        errors = []
        for _ in range(400):
            pose, _ = node._measure()
            q = pose.pose.orientation
            errors.append((pose.pose.position.x - true[0], pose.pose.position.y - true[1],
                           2.0 * math.atan2(q.z, q.w) - true[2]))
    finally:
        node.destroy_node()
    e = np.array(errors)
    for k, sigma in enumerate((1e-3, 1e-3, 2e-3)):
        assert abs(e[:, k].std() / sigma - 1.0) < 0.15
        assert abs(e[:, k].mean()) < 4.0 * sigma / math.sqrt(len(e))


def test_latency_delays_each_pose_and_keeps_its_measurement_stamp(ros_context):
    """latency L (s): the pose measured at sim time t is published once the clock has
    reached t + L (the tray's own record of what it published when), stamped t; a
    subscriber receives those stamps."""
    L = 0.05
    node = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False, parameter_overrides=[Parameter("latency", value=L)])
    got = []
    listener = Node("listener", context=ros_context)
    listener.create_subscription(PoseStamped, "workpiece_pose",
                                 lambda m: got.append(stamp_seconds(m.header.stamp)), 100)
    spinner = ExecutorThread(ros_context, name="latency-test")
    spinner.add_node(listener)
    try:
        deadline = time.monotonic() + 10.0
        while node.pose_pub.get_subscription_count() < 1 and time.monotonic() < deadline:
            time.sleep(0.02)
        measured = []
        for _ in range(40):
            node.step_once()
            measured.append(node.physics.clock)
            time.sleep(0.005)  # 200 Hz, as in real time
        published = {(sec + 1e-9 * ns): sim for (sec, ns), (_, sim) in node._published.items()}
        deadline = time.monotonic() + 10.0
        while len(got) < len(published) and time.monotonic() < deadline:
            time.sleep(0.02)
    finally:
        spinner.stop()
        listener.destroy_node()
        node.destroy_node()
    dt = node.period
    assert published and len(published) < len(measured)  # the last L s not out yet
    for stamp, sim_at_publish in published.items():
        assert any(abs(stamp - t) < 1e-8 for t in measured)  # stamped when measured
        assert L - 1e-9 <= sim_at_publish - stamp < L + dt  # published L later
    assert got and all(any(abs(g - t) < 1e-8 for t in published) for g in got)


def test_use_sim_time_nodes_follow_the_trays_clock(ros_context, harness_factory):
    """The controller and the wrenchcone node started with use_sim_time read the time
    tray_sim publishes on /clock, not the wall clock."""
    tray = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False)
    ctl = TiltControllerNode(context=ros_context, start=False,
                             parameter_overrides=[Parameter("use_sim_time", value=True)])
    h = harness_factory(scene_file=str(PAWL), use_sim_time=True)
    spinner = ExecutorThread(ros_context, name="sim-time-test")
    spinner.add_node(ctl)
    try:
        time.sleep(0.5)  # matched
        for _ in range(400):  # 2 s of sim time, faster than the wall clock
            tray.step_once()
        sim = tray.physics.clock
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline and not (
                now(ctl) == pytest.approx(sim) and now(h.node) == pytest.approx(sim)):
            tray.clock_pub.publish(Clock(clock=_time_msg(sim)))  # /clock is best effort
            time.sleep(0.05)
        seen = now(ctl), now(h.node)
    finally:
        spinner.stop()
        ctl.destroy_node()
        tray.destroy_node()
    assert seen == pytest.approx((sim, sim), abs=1e-6)
    assert 1.9 < sim < 2.1  # 2 s of sim time, not the wall clock (s since 1970)


def now(node) -> float:
    """The node's ROS time (s)."""
    return node.get_clock().now().nanoseconds * 1e-9


def test_a_late_step_slips_the_schedule_instead_of_sprinting(tray):
    """Real time (factor 1): ten steps that each take 50 ms of wall time put the tray
    10 x (50 ms - period) behind its schedule. Afterwards its sim time runs with the wall
    clock, not faster to catch up (a controller would see the part move further between
    two of its steps than it can in real time); lag is the largest slip, slipped their
    sum. The wall clock is the test's own (each step and wait advances it by what it
    would take), so the figures are exact on any machine, loaded or not."""
    wall = {"now": 100.0, "steps": 0}
    step = tray.step_once
    slow_steps, fast_steps, p = 10, 40, tray.period
    marks = {}

    def timed_step():
        step()
        wall["steps"] += 1
        if wall["steps"] <= slow_steps:
            wall["now"] += 0.05  # a step that takes 50 ms of wall time
        if wall["steps"] == slow_steps:
            marks["after_slow"] = (tray.physics.clock, wall["now"])
        if wall["steps"] == slow_steps + fast_steps:
            marks["end"] = (tray.physics.clock, wall["now"])
            tray._stop.set()

    def waited(seconds: float) -> None:
        wall["now"] += seconds

    tray.step_once = timed_step
    tray.wall_clock = lambda: wall["now"]
    tray.wait_wall = waited
    tray._loop()
    (sim0, wall0), (sim1, wall1) = marks["after_slow"], marks["end"]
    assert tray.lag == pytest.approx(0.05 - p, abs=1e-9)
    assert tray.slipped == pytest.approx(slow_steps * (0.05 - p), abs=1e-9)
    # after the late steps: a wait of one period of wall time after each step (a sprint
    # would not wait), one period of sim time per step (to the engine's whole steps)
    assert wall1 - wall0 == pytest.approx((fast_steps - 1) * p, abs=1e-9)
    assert sim1 - sim0 == pytest.approx(fast_steps * p, rel=0.05)


def test_reset_takes_a_planar_pose_over_dds(ros_context):
    """~/reset (wrenchcone_msgs/ResetPose) takes a wrenchcone_msgs/PlanarPose (x, y m,
    theta rad), not the deprecated geometry_msgs/Pose2D: the part is put there, and a
    pose that is not finite is refused with the reason."""
    node = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False)
    caller = Node("reset_caller", context=ros_context)
    spinner = ExecutorThread(ros_context, name="reset-test")
    spinner.add_node(node)
    spinner.add_node(caller)
    cli = caller.create_client(ResetPose, "tray_sim/reset")

    def reset(x: float, y: float, theta: float) -> ResetPose.Response:
        done = threading.Event()
        future = cli.call_async(ResetPose.Request(pose=PlanarPose(x=x, y=y, theta=theta)))
        future.add_done_callback(lambda _f: done.set())
        assert done.wait(30.0), "no reply from tray_sim/reset"
        return future.result()

    try:
        assert cli.wait_for_service(timeout_sec=30.0)
        x, y, theta = load_scene(PAWL).pose
        want = (x, y + 0.002, theta)  # lifted 2 mm off the pins, not the start pose
        r = reset(*want)
        assert r.success, r.message
        assert tuple(node.physics.readout().pose) == pytest.approx(want, abs=1e-9)
        r = reset(math.nan, 0.195, 0.0)
        assert not r.success and "finite" in r.message, r.message
    finally:
        spinner.stop()
        caller.destroy_node()
        node.destroy_node()
