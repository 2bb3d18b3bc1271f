# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The cost of reading a serialized workpiece pose: rclpy's deserializer against the
node's direct plain-CDR read (conversions.pose_stamped_fields, used by inputs.py).

In-process, no DDS: messages serialized by rclpy, frame_id of several lengths (the only
part of a PoseStamped whose size varies). Medians of ``--repeat`` runs of ``--number``
reads each; the ratio rclpy / direct is the figure to quote (docs/node.md).

Usage (install/setup.bash sourced): python benchmarks/node_decode.py
"""

from __future__ import annotations

import argparse
import os
import timeit

from geometry_msgs.msg import PoseStamped
from harness import median
from harness.ros import conv
from rclpy.serialization import deserialize_message, serialize_message


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--number", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    print("| frame_id length | bytes | rclpy deserialize_message us | direct read us | "
          "rclpy / direct |")
    print("| --- | --- | --- | --- | --- |")
    for length in (5, 40, 200):
        msg = PoseStamped()
        msg.header.frame_id = "f" * length
        msg.header.stamp.sec, msg.header.stamp.nanosec = 12, 345
        msg.pose.position.x, msg.pose.orientation.w = 0.25, 1.0
        data = serialize_message(msg)
        assert conv.pose_stamped_fields(data) is not None

        def per_read(stmt) -> float:
            runs = timeit.repeat(stmt, number=args.number, repeat=args.repeat)
            return 1e6 * median(runs) / args.number

        rclpy_us = per_read(lambda data=data: deserialize_message(data, PoseStamped))
        direct_us = per_read(lambda data=data: conv.pose_stamped_fields(data))
        print(f"| {length} | {len(data)} | {rclpy_us:.2f} | {direct_us:.2f} | "
              f"{rclpy_us / direct_us:.1f} |")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
