# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An idle node (no scene file, no inputs, no requests) wakes only for work or at the
diagnostics rate: the timers it runs while idle are the diagnostics timer and the pose
publishers' QoS check, and its publishing worker takes no step until something changes.
Counted, not timed: what runs is independent of the machine's speed (the CPU figure is
benchmarks/node_idle.py's)."""

from __future__ import annotations

import threading
import time

from rclpy.parameter import Parameter

from helpers.node_harness import DEADLINE_S
from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.node.executors import SpinThread
from wrenchcone_ros.node.inputs import QOS_CHECK_PERIOD_S
from wrenchcone_ros.node.parameters import SPEC

#: How long the idle node is watched (s): the old worker polled 4 times a second here.
WATCH_S = 1.5
_count = iter(range(100_000))


class Steps:
    """The publishing worker's steps (its ``on_step`` hook), counted."""

    def __init__(self) -> None:
        self.n = 0
        self.lock = threading.Lock()

    def __call__(self, _timing) -> None:
        with self.lock:
            self.n += 1


def idle_node(ros_context, **parameters):
    steps = Steps()
    node = WrenchConeNode(namespace=f"/idle{next(_count)}_{id(steps)}", context=ros_context,
                          on_step=steps,
                          parameter_overrides=[Parameter(k, value=v)
                                               for k, v in parameters.items()])
    return node, steps, SpinThread([node], None, "idle", ros_context)


def test_an_idle_node_runs_only_the_diagnostics_and_qos_timers(ros_context):
    """With the defaults (input_timeout 1 s, diagnostics 1 Hz): two timers, at the
    diagnostics rate and the QoS check's period; nothing faster."""
    node, _steps, spinner = idle_node(ros_context)
    try:
        assert node.state_label == "active"
        periods = sorted(t.timer_period_ns for t in node.timers if not t.is_canceled())
        rate = SPEC["diagnostics_rate"].default
        assert periods == sorted([round(1e9 / rate), round(QOS_CHECK_PERIOD_S * 1e9)])
    finally:
        spinner.stop()
        node.destroy_node()


def test_an_idle_worker_takes_no_step_until_an_input_arrives(ros_context):
    from geometry_msgs.msg import PoseStamped
    from rclpy.node import Node

    node, steps, spinner = idle_node(ros_context, input_timeout=1.0)
    tester = Node("tester", namespace=node.get_namespace(), context=ros_context)
    try:
        # the worker's first step (at start, before it knows nothing can go stale)
        deadline = time.monotonic() + DEADLINE_S
        while steps.n == 0 and time.monotonic() < deadline:
            time.sleep(0.05)
        assert node.worker.poll_period() is None  # no input: nothing can go stale
        before = steps.n
        time.sleep(WATCH_S)
        assert steps.n == before, f"{steps.n - before} steps of an idle worker"
        # an input wakes it, and a received pose with a timeout is then watched
        pub = tester.create_publisher(PoseStamped, "workpiece_pose", 10)
        deadline = time.monotonic() + DEADLINE_S
        pose = PoseStamped()
        pose.header.frame_id = "world"  # the fixture frame
        while steps.n == before and time.monotonic() < deadline:
            pub.publish(pose)
            time.sleep(0.05)
        assert steps.n > before
        assert node.worker.poll_period() is not None  # until it goes stale
        deadline = time.monotonic() + DEADLINE_S
        while node.worker.poll_period() is not None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert node.worker.poll_period() is None  # stale: only a new input changes that
    finally:
        spinner.stop()
        tester.destroy_node()
        node.destroy_node()
