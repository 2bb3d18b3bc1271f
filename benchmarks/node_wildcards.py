# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Heavy requests beside cheap ones against the node program (bounded work).

The node runs in its own process (``python -m wrenchcone_ros.node``) on 8 fixels touching
a disc's rim, every fixel in contact, with ``max_concrete_modes`` raised to 100,000 so
that the wildcards below pass the count limit and meet the time budget
(``max_request_time``, default 0.05 s) instead. One thread sends the heavy requests one
after another (check_wrench "cccccccc", "********", "cccccccn", "******nn", then a
classify_wrench in the slow lane); the main thread meanwhile calls a cheap check_wrench
("nnnnnnnn") in a loop. Reported: each heavy request's status and round trip, the cheap
checks' median and maximum round trip (what the heavy ones cost the others), and the
node's exit code and whether its log has a traceback after Ctrl-C.

Usage (install/setup.bash sourced): python benchmarks/node_wildcards.py [--json FILE]
"""

from __future__ import annotations

import argparse
import math
import os
import threading

import harness
from harness.ros import NodeProcess, call_and_wait, scene_file, spin, wait_for_services

import rclpy
from rclpy.node import Node

from wrenchcone_ros.node.status import STATUS_NAMES
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench

RIM = {"workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.0, 0.0],
                     "shape": {"type": "disc", "radius": 1.0}},
       "friction": 0.3,
       "fixels": [[math.cos(2 * math.pi * k / 8), math.sin(2 * math.pi * k / 8)]
                  for k in range(8)]}
HEAVY = ("cccccccc", "********", "cccccccn", "******nn")
CHEAP = "nnnnnnnn"


def check(mode: str) -> CheckWrench.Request:
    req = CheckWrench.Request()
    req.mode = mode
    req.wrench.force.y = 1.0
    return req


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", default=None, help="also write the results to this file")
    args = ap.parse_args()
    facts = harness.machine_facts()
    ns = f"/wild{os.getpid()}"
    with scene_file(RIM) as path:
        node = NodeProcess(ns, ["-p", f"scene_file:={path}", "-p", "max_concrete_modes:=100000",
                                "-p", "input_timeout:=0.0", "-p", f"modes:=['{CHEAP}']"])
    rclpy.init()
    client = Node("wildcard_client", namespace=ns)
    spinner = spin([client], "wildcard-client")
    chk = client.create_client(CheckWrench, "wrenchcone/check_wrench")
    cls = client.create_client(ClassifyWrench, "wrenchcone/classify_wrench")
    wait_for_services(chk, cls)
    heavy: dict[str, tuple[float, object]] = {}

    def heavy_calls() -> None:
        for mode in HEAVY:
            heavy[mode] = call_and_wait(chk, check(mode), 60.0)
        req = ClassifyWrench.Request()
        req.wrench.force.y = 1.0
        heavy["classify_wrench"] = call_and_wait(cls, req, 60.0)

    thread = threading.Thread(target=heavy_calls)
    thread.start()
    cheap = []
    while thread.is_alive():
        cheap.append(call_and_wait(chk, check(CHEAP), 60.0)[0])
    thread.join()
    spinner.stop()
    client.destroy_node()
    rclpy.shutdown()
    code = node.stop()  # Ctrl-C: the program must end cleanly
    log = node.log_text()
    out = {"heavy": {m: {"status": STATUS_NAMES[r.status], "ms": 1e3 * s,
                         "message": r.message[:120]} for m, (s, r) in heavy.items()},
           "cheap_ms": harness.summary(cheap, 1e3), "node_exit_code": code,
           "traceback": "Traceback" in log}
    print(harness.header_line(facts, harness.loadavg()))
    for m, h in out["heavy"].items():
        print(f"{m}: {h['status']} in {h['ms']:.1f} ms")
    c = out["cheap_ms"]
    print(f"cheap checks beside them: n={c['n']} median {c['median']:.2f} ms "
          f"max {c['max']:.2f} ms")
    print(f"node exit code {code}, traceback in its log: {out['traceback']}")
    harness.write_json(args.json, facts, out)


if __name__ == "__main__":
    main()
