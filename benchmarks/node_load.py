# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Load run: check_wrench at a fixed request rate (default 1,000/s) for a
fixed time (default 60 s), against the node in its own process, side by side with an
empty std_srvs/Trigger service in a third process at the same rate.

Open loop: for each service, its own client process sends a request every 1/rate s
whatever the replies (``call_async``), so a slow server shows as latency and drops, not
as a slower client. Reported for both: requests sent, replies, drops (no reply within
--grace s after the end), round trip p50 / p99 / max, and the node's CPU and memory.

Usage: python benchmarks/node_load.py [--rate 1000] [--seconds 60] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time

import harness
from harness.ros import (
    PAPER_DISC,
    NodeProcess,
    conv,
    spin,
    start_trigger_server,
    wait_for_services,
)

import numpy as np
import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_srvs.srv import Trigger

from wrenchcone_ros.node.executors import executor_kind
from wrenchcone_msgs.srv import CheckWrench


def drive(kind: str, ns: str, rate: float, seconds: float, grace: float) -> dict:
    """One service's open-loop load from THIS process (each service gets its own client
    process, so the client side is not what limits the rate)."""
    rclpy.init()
    client = Node(f"load_{kind}", namespace=ns)
    qos = QoSProfile(depth=1000)  # the client keeps every reply it gets
    cli = (client.create_client(CheckWrench, "wrenchcone/check_wrench", qos_profile=qos)
           if kind == "check_wrench" else client.create_client(Trigger, "trigger",
                                                                qos_profile=qos))
    # the node's executor kind (executors.py): a MultiThreadedExecutor client could not
    # keep up with 1,000 replies/s on a 2-core machine, even from an empty Trigger
    spinner = spin([client], f"load-{kind}")
    wait_for_services(cli)
    rng = np.random.default_rng(3)
    wrenches = [conv.planar_to_wrench(g) for g in rng.normal(size=(256, 3))]
    sent: list[float] = []
    done_at: dict[int, float] = {}
    statuses: dict[int, int] = {}
    lock = threading.Lock()

    def on_done(i: int, fut) -> None:
        t = time.perf_counter()
        with lock:
            done_at[i] = t
            if kind == "check_wrench":
                st = int(fut.result().status)
                statuses[st] = statuses.get(st, 0) + 1

    period = 1.0 / rate
    t0 = t_next = time.perf_counter()
    i = 0
    while t_next - t0 < seconds:
        req = (CheckWrench.Request(mode="na", wrench=wrenches[i % 256])
               if kind == "check_wrench" else Trigger.Request())
        sent.append(time.perf_counter())
        fut = cli.call_async(req)
        fut.add_done_callback(lambda f, n=i: on_done(n, f))
        i += 1
        t_next += period
        delay = t_next - time.perf_counter()
        if delay > 0:
            time.sleep(delay)
    elapsed = time.perf_counter() - t0
    time.sleep(grace)
    spinner.stop()
    client.destroy_node()
    rclpy.try_shutdown()
    with lock:
        rts = [done_at[n] - sent[n] for n in done_at]
    return {"sent": len(sent), "replies": len(rts), "drops": len(sent) - len(rts),
            "sent_rate": len(sent) / elapsed, "seconds": elapsed, "statuses": statuses,
            **harness.summary(rts, 1e3)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rate", type=float, default=1000.0, help="requests/s per service")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--grace", type=float, default=2.0, help="s to wait for late replies")
    ap.add_argument("--json", help="also write the results to this file")
    ap.add_argument("--drive", nargs=2, metavar=("KIND", "NS"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.drive:  # a child: one service's load, result as JSON on stdout
        print(json.dumps(drive(args.drive[0], args.drive[1], args.rate, args.seconds,
                               args.grace)))
        return 0
    facts = harness.machine_facts()
    ns = f"/load{os.getpid()}"
    node = NodeProcess(ns, ["-p", f"scene_file:={PAPER_DISC}", "-p", "input_timeout:=0.0"])
    trigger_proc = start_trigger_server(ns)
    cpu0, rss0 = node.cpu_s(), node.rss_mb()
    t0 = time.perf_counter()
    kids = {kind: subprocess.Popen(
        [sys.executable, __file__, "--rate", str(args.rate), "--seconds", str(args.seconds),
         "--grace", str(args.grace), "--drive", kind, ns], stdout=subprocess.PIPE, text=True)
        for kind in ("check_wrench", "trigger")}
    res = {kind: json.loads(p.communicate()[0].strip().splitlines()[-1])
           for kind, p in kids.items()}
    elapsed = time.perf_counter() - t0 - args.grace
    cpu1, rss1 = node.cpu_s(), node.rss_mb()
    node.stop()
    trigger_proc.stop(signal.SIGTERM)
    statuses = res["check_wrench"].pop("statuses")
    res["trigger"].pop("statuses")
    out = {"rate": args.rate, "seconds": args.seconds, "services_ms": res,
           "check_statuses": statuses,
           "node_cpu_pct": 100 * (cpu1 - cpu0) / elapsed, "node_rss_mb": [rss0, rss1]}
    print(harness.header_line(facts, harness.loadavg(),
                              f"{args.rate:g} requests/s per service for {args.seconds:g} s",
                              "each service from its own client process",
                              f"executor {executor_kind()}"))
    print()
    print("| service | sent | sent/s | replies | drops | p50 ms | p99 ms | max ms |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for kind, r in res.items():
        print(f"| {kind} | {r['sent']} | {r['sent_rate']:.0f} | {r['replies']} | "
              f"{r['drops']} | {r.get('median', float('nan')):.2f} | "
              f"{r.get('p99', float('nan')):.2f} | {r.get('max', float('nan')):.2f} |")
    print(f"\ncheck_wrench statuses {statuses}; node CPU {out['node_cpu_pct']:.0f} % of a "
          f"core, RSS {rss0:.0f} -> {rss1:.0f} MB")
    harness.write_json(args.json, facts, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
