# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Node latency: check_wrench round trip vs an empty service, and pose -> F published.

Everything runs in one process and one run, over real DDS (own ROS_DOMAIN_ID,
localhost-only discovery):

* server executor thread: the wrenchcone node and a node with empty services
  (std_srvs/Trigger: the floor, what any rclpy service costs here; and CheckWrench);
* client executor thread: a client node (service clients, pose publisher, cone
  subscribers);
* the main thread issues one call at a time and waits for its reply.

Measured (time.perf_counter around each call, on the calling thread):

1. ``trigger``: the empty Trigger service (the target's reference);
   ``empty_check``: a CheckWrench service with an empty callback (the cost of the
   message types alone);
2. ``check_cached``: check_wrench on mode "na" of the default scene, cone cached;
3. ``check_new_pose``: check_wrench after a new pose before every call (the pose is
   published, then the call is made once the node has taken the new snapshot, so the
   call computes the cone; no mode is monitored, so nothing else computes it).
   Calls of 1-3 are interleaved (trigger, cached, empty check, trigger, new pose, ...) so
   that drift of the machine affects all alike.
4. ``pose_to_F``: from publishing a pose to the arrival of F on every monitored
   ~/cone/<mode> topic, with 1, 4 and 16 monitored modes (a square on two pins with
   three free fixels: 17 feasible modes).

Usage: make bench   (or: python benchmarks/node_latency.py [--calls N] [--json FILE])
"""

from __future__ import annotations

import argparse
import sys
import threading
import time

import harness
from harness.ros import PAPER_DISC, SQUARE, call_and_wait, conv, feasible_modes, scene_file, spin
from harness.ros import wait_for_services

import numpy as np
import rclpy
import yaml
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from std_srvs.srv import Trigger

from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.msg import WrenchCone
from wrenchcone_ros.node import CONE_QOS, WrenchConeNode
from wrenchcone_msgs.srv import CheckWrench


#: --param NAME=VALUE: node parameters added to every rig's (e.g. worker_nice=0)
EXTRA_PARAMETERS: dict = {}


class Rig:
    def __init__(self, parameters: dict) -> None:
        parameters = {**parameters, **EXTRA_PARAMETERS}
        self.node = WrenchConeNode(
            namespace="/bench",
            parameter_overrides=[Parameter(k, value=v) for k, v in parameters.items()])
        self.empty = Node("empty", namespace="/bench")
        self.empty.create_service(Trigger, "trigger", lambda req, resp: resp)
        # the same service type as check_wrench with an empty callback: the cost of the
        # message types alone (larger than Trigger's), without any computation
        self.empty.create_service(CheckWrench, "empty_check", lambda req, resp: resp)
        self.client = Node("bench_client", namespace="/bench")
        self.trigger_cli = self.client.create_client(Trigger, "trigger")
        self.check_cli = self.client.create_client(CheckWrench, "wrenchcone/check_wrench")
        self.empty_check_cli = self.client.create_client(CheckWrench, "empty_check")
        self.pose_pub = self.client.create_publisher(PoseStamped, "workpiece_pose",
                                                     QoSProfile(depth=10))
        # the node on the executor main() uses (executors.make_executor), and a client
        # on the same executor kind in its own thread
        self.spinners = [spin([self.node, self.empty], "bench-server"),
                         spin([self.client], "bench-client")]
        wait_for_services(self.trigger_cli, self.check_cli, self.empty_check_cli)

    def close(self) -> None:
        for spinner in self.spinners:
            spinner.stop()
        for n in (self.client, self.empty, self.node):
            n.destroy_node()

    def call(self, cli, req) -> tuple[float, object]:
        return call_and_wait(cli, req)

    def publish_pose(self, x: float, y: float, theta: float) -> None:
        msg = PoseStamped()
        msg.header.frame_id = "world"
        msg.header.stamp = self.client.get_clock().now().to_msg()
        msg.pose.position.x, msg.pose.position.y = x, y
        q = conv.yaw_to_quaternion(theta)
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = q
        self.pose_pub.publish(msg)

    def wait_version(self, above: int) -> int:
        while self.node.snapshot.version <= above:
            time.sleep(20e-6)
        return self.node.snapshot.version


def services_rig() -> Rig:
    """The rig of :func:`bench_services`: the node on the paper's disc (without a scene
    file the node waits for inputs), nothing monitored (only requested modes are
    computed)."""
    return Rig({"scene_file": str(PAPER_DISC), "modes": [""]})


def bench_services(calls: int, warmup: int, rig: Rig | None = None) -> dict:
    """Summaries (ms) of the interleaved service calls 1-3 of the module's docstring, on
    ``rig`` (default: a new :func:`services_rig`, closed afterwards)."""
    own = rig is None
    rig = services_rig() if own else rig
    try:
        rng = np.random.default_rng(1)
        wrenches = rng.normal(size=(calls + warmup, 3))
        trig = Trigger.Request()
        out = {"trigger": [], "empty_check": [], "check_cached": [], "check_new_pose": []}
        statuses = set()
        v = rig.node.snapshot.version  # a fresh pose first: a rig used before holds an old one
        rig.publish_pose(0.0, 0.0, 0.0)
        rig.wait_version(v)
        for i in range(calls + warmup):
            req = CheckWrench.Request(mode="na", wrench=conv.planar_to_wrench(wrenches[i]))
            t_trig, _ = rig.call(rig.trigger_cli, trig)
            t_cached, r = rig.call(rig.check_cli, req)
            statuses.add(r.status)
            t_empty, _ = rig.call(rig.empty_check_cli, req)
            # a new pose (the disc rotates about its centre: contacts unchanged)
            v = rig.node.snapshot.version
            rig.publish_pose(0.0, 0.0, 1e-3 * (i % 2))
            rig.wait_version(v)
            t_trig2, _ = rig.call(rig.trigger_cli, trig)
            t_new, r2 = rig.call(rig.check_cli, req)
            statuses.add(r2.status)
            if i >= warmup:
                out["trigger"] += [t_trig, t_trig2]
                out["check_cached"].append(t_cached)
                out["empty_check"].append(t_empty)
                out["check_new_pose"].append(t_new)
        if statuses != {Status.OK}:
            raise RuntimeError(f"unexpected statuses {statuses}")
        return {k: harness.summary(v, 1e3) for k, v in out.items()}
    finally:
        if own:
            rig.close()


class Arrivals:
    """Arrival times of messages per monitored mode."""

    def __init__(self, modes: list[str]) -> None:
        self.modes = modes
        self.times: dict[str, list[float]] = {m: [] for m in modes}
        self.cond = threading.Condition()

    def callback(self, mode: str):
        def cb(_msg: WrenchCone) -> None:
            t = time.perf_counter()
            with self.cond:
                self.times[mode].append(t)
                self.cond.notify_all()
        return cb

    def counts(self) -> dict[str, int]:
        with self.cond:
            return {m: len(v) for m, v in self.times.items()}

    def wait_all_beyond(self, counts: dict[str, int]) -> float:
        """Wait until every mode got a message beyond ``counts``; the last arrival time."""
        with self.cond:
            if not self.cond.wait_for(
                    lambda: all(len(self.times[m]) > counts[m] for m in self.modes), 30):
                raise RuntimeError("F not published for every monitored mode")
            return max(self.times[m][counts[m]] for m in self.modes)


def _pose_to_f(path: str, modes: list[str], updates: int, warmup: int) -> dict:
    rig = Rig({"scene_file": path, "modes": modes})
    try:
        arr = Arrivals(modes)
        for m in modes:
            rig.client.create_subscription(WrenchCone, f"wrenchcone/cone/{m}",
                                           arr.callback(m), CONE_QOS)
        arr.wait_all_beyond({m: 0 for m in modes})  # the latched initial cones
        samples = []
        for i in range(updates + warmup):
            before = arr.counts()
            t0 = time.perf_counter()
            rig.publish_pose(0.05 * ((i + 1) % 2), 0.0, 0.0)  # slide along the two pins
            t1 = arr.wait_all_beyond(before)
            if i >= warmup:
                samples.append(t1 - t0)
        return harness.summary(samples, 1e3)
    finally:
        rig.close()


def bench_pose_to_f(counts: list[int], updates: int, warmup: int) -> dict:
    feasible = feasible_modes(SQUARE)
    if len(feasible) < max(counts):
        raise RuntimeError(f"only {len(feasible)} feasible modes")
    with scene_file(SQUARE) as path:
        return {str(n): _pose_to_f(path, feasible[:n], updates, warmup) for n in counts}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--calls", type=int, default=2000, help="calls per service scenario")
    ap.add_argument("--updates", type=int, default=300, help="pose updates per mode count")
    ap.add_argument("--warmup", type=int, default=50)
    ap.add_argument("--json", help="also write the results to this file")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                    help="a node parameter for every rig, as YAML (e.g. worker_nice=0, "
                         "publish_markers=false); repeatable")
    args = ap.parse_args()
    for item in args.param:
        name, _, value = item.partition("=")
        EXTRA_PARAMETERS[name] = yaml.safe_load(value)
    facts = harness.machine_facts()
    rclpy.init()
    try:
        svc = bench_services(args.calls, args.warmup)
        pose = bench_pose_to_f([1, 4, 16], args.updates, args.warmup)
    finally:
        rclpy.try_shutdown()
    floor = svc["trigger"]["median"]
    print(harness.header_line(facts, harness.loadavg(), f"commit {facts['git']}"))
    print()
    print("| service call | n | median ms | p99 ms | median / empty |")
    print("| --- | --- | --- | --- | --- |")
    for k in ("trigger", "empty_check", "check_cached", "check_new_pose"):
        s = svc[k]
        print(f"| {k} | {s['n']} | {s['median']:.3f} | {s['p99']:.3f} | "
              f"{s['median'] / floor:.2f} |")
    print()
    print("| monitored modes | updates | median ms | p99 ms |")
    print("| --- | --- | --- | --- |")
    for n, s in pose.items():
        print(f"| {n} | {s['n']} | {s['median']:.3f} | {s['p99']:.3f} |")
    harness.write_json(args.json, facts, {
        "node_parameters": EXTRA_PARAMETERS, "services_ms": svc,
        "ratio_cached_vs_empty": svc["check_cached"]["median"] / floor,
        "ratio_new_pose_vs_empty": svc["check_new_pose"]["median"] / floor,
        "ratio_cached_vs_empty_check": (svc["check_cached"]["median"]
                                        / svc["empty_check"]["median"]),
        "pose_to_F_ms": pose})
    return 0


if __name__ == "__main__":
    sys.exit(main())
