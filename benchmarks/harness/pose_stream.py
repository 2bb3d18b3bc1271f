# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A pose stream in a process of its own: ``PoseStamped`` on ``<ns>/workpiece_pose`` at a
fixed rate, the square sliding along its pins (x = step * (k % cycle)).

    python benchmarks/harness/pose_stream.py NS RATE_HZ SECONDS STEP_M CYCLE OUT

Prints "go" once the node's subscription is matched, streams, then writes OUT (JSON):
``stamps`` (each pose's header stamp, ns: CLOCK_REALTIME, so that a reply's pose_stamp
can be matched with it), ``stalls`` (publish() calls over ``STALL_MS``: [wall s, ms]) and
``pauses`` (this process held up: ``watch.watch_pauses``). Started by
``harness.ros.start_pose_stream``.
"""

from __future__ import annotations

import json
import os
import sys
import time

# run as a script (``python -P``, see harness.ros.PYTHON): benchmarks/ on the path
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import rclpy  # noqa: E402
from geometry_msgs.msg import PoseStamped  # noqa: E402
from harness.watch import watch_pauses  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.qos import QoSProfile  # noqa: E402

STALL_MS = 15.0  # ms: a publish() this long is recorded: the stream itself stalled


def stream(ns: str, rate: float, seconds: float, step: float, cycle: int) -> dict:
    pauses: list = []
    watch_pauses(pauses)
    rclpy.init()
    node = Node("pose_stream", namespace=ns)
    pub = node.create_publisher(PoseStamped, "workpiece_pose", QoSProfile(depth=10))
    while pub.get_subscription_count() == 0:  # discovery: the node's subscription
        time.sleep(0.05)
    time.sleep(0.5)
    print("go", flush=True)
    stamps, stalls, period = [], [], 1.0 / rate
    t_next = time.perf_counter()
    t_end = t_next + seconds
    i = 0
    while time.perf_counter() < t_end:
        msg = PoseStamped()
        msg.header.frame_id = "world"
        stamp = time.time_ns()
        msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(stamp, 10**9)
        msg.pose.position.x = step * (i % cycle)
        msg.pose.orientation.w = 1.0
        pub.publish(msg)
        stamps.append(stamp)
        took = time.time_ns() - stamp
        if took > STALL_MS * 1e6:
            stalls.append((stamp * 1e-9, took * 1e-6))
        i += 1
        t_next += period
        delay = t_next - time.perf_counter()
        if delay > 0:
            time.sleep(delay)
    return {"stamps": stamps, "stalls": stalls, "pauses": pauses}


if __name__ == "__main__":
    ns, rate, seconds, step, cycle, out = sys.argv[1:7]
    record = stream(ns, float(rate), float(seconds), float(step), int(cycle))
    with open(out, "w") as f:
        json.dump(record, f)
