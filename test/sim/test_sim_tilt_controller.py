# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller between two runs (wrenchcone_ros.sim.tilt_controller): a run that
is stopped while it waits on the wrenchcone node stops at once, and nothing it was doing
reaches the next run. Real DDS: poses from a plain publisher, the controller's plan
request to a server that is not there (its wait is the longest a run can be in)."""

import threading
import time

import pytest

from geometry_msgs.msg import PoseStamped  # noqa: E402
from rclpy.executors import MultiThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from wrenchcone_msgs.msg import TiltCommand  # noqa: E402

from wrenchcone_ros.sim.tilt_controller import TiltControllerNode  # noqa: E402
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: E402

#: How long stop() may take (s) when the run waits on the node: far below the waits it
#: can be in (10 s for a server to appear, plan_timeout for a plan, 10 s for a reply).
PROMPT_S = 2.0


@pytest.fixture
def waiting_controller(ros_context):
    """A controller whose run has seen the part at rest and waits for a plan server that
    is not there; the commands it sent."""
    spinner = ExecutorThread(ros_context, MultiThreadedExecutor, name="ctl-test")
    ctl = TiltControllerNode(context=ros_context, start=False, parameter_overrides=[
        Parameter("server", value="/nobody_here"), Parameter("stall_time", value=0.1)])
    world = Node("world", context=ros_context)
    pub = world.create_publisher(PoseStamped, "workpiece_pose", 10)
    commands = []
    world.create_subscription(TiltCommand, "tilt_command", commands.append, 10)
    spinner.add_node(ctl)
    spinner.add_node(world)
    stop = threading.Event()

    def publish() -> None:
        k = 0
        while not stop.is_set():
            k += 1
            msg = PoseStamped()
            msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(k * 10_000_000,
                                                                   1_000_000_000)
            msg.pose.position.x, msg.pose.position.y, msg.pose.orientation.w = 0.1, 0.2, 1.0
            pub.publish(msg)
            time.sleep(0.01)

    poses = threading.Thread(target=publish, daemon=True)
    poses.start()
    ctl.restart()
    deadline = time.monotonic() + 20.0
    while ctl.state != "PLANNING" and time.monotonic() < deadline:
        time.sleep(0.01)
    assert ctl.state == "PLANNING", (ctl.state, ctl.reason)
    yield ctl, commands
    stop.set()
    poses.join(5.0)
    spinner.stop()  # before the nodes go: a node destroyed while a thread of the
    ctl.destroy_node()  # executor still waits on it raised InvalidHandle there
    world.destroy_node()


def test_a_run_waiting_for_the_node_stops_at_once(waiting_controller):
    ctl, _ = waiting_controller
    run = ctl.thread
    t0 = time.monotonic()
    ctl.stop()
    assert time.monotonic() - t0 < PROMPT_S
    assert not run.is_alive()  # idle: it can touch nothing any more



def test_a_namespaced_controller_reaches_the_node_of_its_namespace(harness_factory,
                                                                   ros_context):
    """The default ``server`` is relative: a controller started in the node's namespace
    (as a launch file with ``namespace:=...`` starts both) plans with that node."""
    from rclpy.action import ActionClient

    from wrenchcone_msgs.msg import Status

    h = harness_factory()  # the paper's disc, in a namespace of its own
    ctl = TiltControllerNode(context=ros_context, start=False, namespace=h.ns)
    try:
        assert ctl.server == "wrenchcone"
        assert isinstance(ctl.action, ActionClient)
        assert ctl.action.wait_for_server(timeout_sec=30.0)
        reply = ctl.client.check_wrench("na", (0.1, -1.0, 0.0), timeout=30.0)
        assert reply.status == Status.OK and reply.consistent
    finally:
        ctl.destroy_node()
