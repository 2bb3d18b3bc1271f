# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""In-process cost of the node's per-pose work, without DDS traffic: a check_wrench
service callback that meets a new pose (decode, scene, cone, check, stamps), the same
callback on an unchanged pose, and the publishing worker's whole step for a new pose
(decode, scene, every monitored cone, the messages of the subscribed cone topic).

The node is built in-process on the square on two pins (``harness.ros.SQUARE``) with its
16 first feasible modes monitored; its publishing worker is stopped
(``node.worker.stop()``), so this process calls the service callback
(``services.serve``) and the worker's publication of the newest snapshot
(``node.worker.publish``) itself, after storing a new serialized pose each time. One cone
topic has a subscriber, as in node_stream.py. Medians and p90 of ``--calls`` calls after
a warm-up.

Imports the package from the environment (not this checkout's source tree), so that
another build of the package can be compared by putting it first on PYTHONPATH.

With ``--cold``, each timed call comes after a sweep of a 32 MB buffer and a 2 ms sleep,
as a request does in the node that arrives at 100 Hz while other processes run: the
caches are cold and the core may have idled. That is what the live callback looks like
(docs/performance.md: 2-4 times the warm figure).

Usage (install/setup.bash sourced): python benchmarks/node_snapshot_cost.py [--calls N]
       [--cold]
"""

from __future__ import annotations

import argparse
import os
import time

import harness
from harness.ros import CYCLE, SQUARE, STEP, conv, feasible_modes, scene_file

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.parameter import Parameter
from rclpy.serialization import serialize_message

from wrenchcone_msgs.msg import WrenchCone
from wrenchcone_ros.node import CONE_QOS, WrenchConeNode, services
from wrenchcone_msgs.srv import CheckWrench


def pose_bytes(k: int) -> bytes:
    msg = PoseStamped()
    msg.header.frame_id = "world"
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1 + k // 10**9, k % 10**9
    msg.pose.position.x = STEP * (k % CYCLE)
    msg.pose.orientation.w = 1.0
    return serialize_message(msg)


def stats(samples: list[float]) -> str:
    s = harness.summary(samples, 1e3)
    return f"{s['median']:.3f} / {s['p90']:.3f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--cold", action="store_true",
                    help="sweep 32 MB and sleep 2 ms before each timed call")
    args = ap.parse_args()
    sweep = np.ones(4_000_000) if args.cold else None
    modes = sorted(feasible_modes(SQUARE))[:16]
    rclpy.init()
    with scene_file(SQUARE) as path:
        node = WrenchConeNode(parameter_overrides=[
            Parameter("scene_file", value=path), Parameter("modes", value=modes),
            Parameter("input_timeout", value=0.0)])
    node.worker.stop()  # the worker thread ends; this process does its step below
    node.create_subscription(WrenchCone, f"wrenchcone/cone/{modes[-1]}", lambda m: None,
                             CONE_QOS)
    time.sleep(0.5)
    spec = next(s for s in services.SERVICES if s.name == "check_wrench")
    callback = services.serve(node, spec)
    req = CheckWrench.Request()
    req.mode = modes[-1]
    req.wrench = conv.planar_to_wrench((0.0, 1.0, 0.0))
    poses = [pose_bytes(k) for k in range(3 * args.calls + 600)]
    k = 0

    def timed(step, new_pose: bool, n: int) -> list[float]:
        nonlocal k
        out = []
        for _ in range(n):
            if new_pose:
                node.store.set_raw_pose(poses[k], k)
                k += 1
            if sweep is not None:
                sweep.sum()
                time.sleep(0.002)
            t = time.perf_counter()
            step()
            out.append(time.perf_counter() - t)
        return out

    def check() -> None:
        callback(req, CheckWrench.Response())

    def worker_step() -> None:
        node.worker.publish(node.snapshot)

    for step in (check, worker_step):
        timed(step, True, 200)  # warm-up
    print(f"load average at start: {os.getloadavg()}; package "
          f"{os.path.dirname(services.__file__)}; {'cold' if args.cold else 'warm'} calls")
    print("| step | median / p90 ms |")
    print("| --- | --- |")
    print(f"| check_wrench callback, new pose | {stats(timed(check, True, args.calls))} |")
    print(f"| check_wrench callback, same pose | {stats(timed(check, False, args.calls))} |")
    print(f"| worker step, new pose, 16 modes | {stats(timed(worker_step, True, args.calls))} |")
    print(f"load average at end: {os.getloadavg()}")
    os._exit(0)  # the node's worker and executors are not shut down cleanly here


if __name__ == "__main__":
    main()
