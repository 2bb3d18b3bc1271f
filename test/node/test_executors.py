# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""node/executors.py and what the node puts in an executor's wait set.

A pose stream must not wake the executor that spins the node: the pose is pulled by the
node's publishing worker, and an executor woken per pose (or, worse, whenever a pose is
waiting untaken) rebuilds its wait set in Python each time, holding the GIL that the
worker and the services need. Counted, not timed: how often the spinning thread waits.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
from geometry_msgs.msg import PoseStamped
from helpers.node_harness import DEADLINE_S
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy

from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.node.executors import LaneExecutor, LongRunningGroup

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "examples" / "paper_disc.yaml"
POSES = 400


class CountingWaits:
    """Counts the executor wait-set waits made by one thread (rclpy's WaitSet.wait, the
    one place an executor blocks)."""

    def __init__(self, monkeypatch) -> None:
        import rclpy.executors as executors

        base = executors._rclpy.WaitSet
        counter = self

        class Counted(base):
            def wait(self, timeout):
                if threading.get_ident() == counter.thread:
                    counter.waits += 1
                return super().wait(timeout)

        self.waits, self.thread = 0, None
        monkeypatch.setattr(executors._rclpy, "WaitSet", Counted)


@pytest.mark.parametrize("kind", ["lane", "single"])
def test_a_pose_stream_does_not_wake_the_executor(ros_context, monkeypatch, kind):
    counting = CountingWaits(monkeypatch)
    ns = f"/ex{id(counting)}"
    node = WrenchConeNode(namespace=ns, context=ros_context, parameter_overrides=[
        Parameter("scene_file", value=str(DISC)), Parameter("input_timeout", value=0.0),
        Parameter("publish_markers", value=False), Parameter("diagnostics_rate", value=0.0)])
    tester = Node("tester", namespace=ns, context=ros_context)
    pub = tester.create_publisher(PoseStamped, "workpiece_pose",
                                  QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
    executor = (LaneExecutor(context=ros_context) if kind == "lane"
                else SingleThreadedExecutor(context=ros_context))
    executor.add_node(node)
    stop = threading.Event()

    def spin() -> None:
        counting.thread = threading.get_ident()
        while not stop.is_set():
            executor.spin_once(timeout_sec=0.05)

    thread = threading.Thread(target=spin, daemon=True)
    thread.start()
    try:
        end = time.monotonic() + DEADLINE_S
        while pub.get_subscription_count() == 0 and time.monotonic() < end:
            time.sleep(0.02)
        assert pub.get_subscription_count() == 1
        before = counting.waits
        msg = PoseStamped()
        msg.header.frame_id = "world"
        msg.pose.orientation.w = 1.0
        for k in range(POSES):
            msg.header.stamp.sec = 10 + k
            pub.publish(msg)
            time.sleep(0.001)
        woken = counting.waits - before
    finally:
        stop.set()
        thread.join(5.0)
        executor.shutdown(timeout_sec=2.0)
        tester.destroy_node()
        node.destroy_node()
    # the node's own timers (the publishers' catch-up at 20 Hz) wake it a few dozen
    # times in the stream's ~0.5-1 s; a wake-up per pose, or a busy loop while a pose
    # waits untaken, is hundreds to thousands
    assert woken < POSES / 4, f"{woken} executor waits during {POSES} poses"


def test_the_lane_executor_runs_long_groups_on_its_pool_and_the_rest_inline(ros_context):
    """Which thread runs what: a LongRunningGroup's and a reentrant group's callbacks run
    on the pool while the spinning thread goes on running the others."""
    node = Node("lanes", namespace=f"/lanes{id(object())}", context=ros_context)
    executor = LaneExecutor(context=ros_context)
    executor.add_node(node)
    seen: dict[str, str] = {}
    release = threading.Event()
    fast_ran = threading.Event()

    def long_cb() -> None:
        seen["long"] = threading.current_thread().name
        release.wait(DEADLINE_S)

    def fast_cb() -> None:
        seen["fast"] = threading.current_thread().name
        fast_ran.set()

    def side_cb() -> None:
        seen["side"] = threading.current_thread().name

    long_timer = node.create_timer(0.01, long_cb, callback_group=LongRunningGroup())
    fast_timer = node.create_timer(0.01, fast_cb)
    side_timer = node.create_timer(0.01, side_cb, callback_group=ReentrantCallbackGroup())
    thread = threading.Thread(target=executor.spin, name="spinner", daemon=True)
    thread.start()
    try:
        assert fast_ran.wait(DEADLINE_S)
        fast_ran.clear()
        assert fast_ran.wait(DEADLINE_S)  # again, while the long callback still holds
        assert "long" in seen and not release.is_set()
    finally:
        release.set()
        long_timer.cancel()
        fast_timer.cancel()
        side_timer.cancel()
        executor.shutdown(timeout_sec=2.0)
        thread.join(5.0)
        node.destroy_node()
    assert seen["fast"] == "spinner"
    assert seen["long"].startswith("wrenchcone-long")
    assert seen["side"].startswith("wrenchcone-long")  # a reentrant group's: the pool
