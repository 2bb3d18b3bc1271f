# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Garbage-collector pauses in the node, with and without freezing the start-up objects.

A full (generation 2) collection stops every Python thread of the process while it scans
every tracked object, and the node starts with about 150,000 of them (rclpy, numpy,
numba, the node itself). The program (``python -m wrenchcone_ros.node``) therefore
calls ``gc.freeze()`` once it is ready (``wrenchcone_node.freeze_start_up_objects``):
the start-up objects go to a permanent generation that no collection scans.

This script runs the seeded fuzz workload of test/helpers/node_fuzz.py (parameter sets,
fixel and pose messages, all services) against a node in this process, twice in fresh
processes: as is, and after ``freeze_start_up_objects()``. It times every collection
with ``gc.callbacks`` and reports, per generation, how many ran, their total and their
longest pause.

Usage (install/setup.bash sourced): python benchmarks/node_gc.py [--steps 3000]
       [--seed 3] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import harness


def one_run(steps: int, seed: int, freeze: bool) -> dict:
    """The fuzz workload in this process; collections timed per generation."""
    import gc

    import harness.ros  # noqa: F401  (its own DDS domain)

    import rclpy
    from helpers.node_fuzz import run_fuzz
    from helpers.node_harness import Harness

    from wrenchcone_ros.node.wrenchcone_node import freeze_start_up_objects

    context = rclpy.context.Context()
    rclpy.init(context=context)
    h = Harness(context)
    frozen = freeze_start_up_objects() if freeze else 0
    tracked = len(gc.get_objects())
    pauses: dict[int, list[float]] = {0: [], 1: [], 2: []}
    started = [0.0]

    def timed(phase: str, info: dict) -> None:
        if phase == "start":
            started[0] = time.perf_counter()
        else:
            pauses[info["generation"]].append(time.perf_counter() - started[0])

    gc.callbacks.append(timed)
    t0 = time.perf_counter()
    try:
        run_fuzz(h, steps, seed)
    finally:
        elapsed = time.perf_counter() - t0
        gc.callbacks.remove(timed)
        h.close()
        rclpy.shutdown(context=context)
    return {"freeze": freeze, "frozen_objects": frozen, "tracked_after_start": tracked,
            "seconds": elapsed, "steps": steps, "seed": seed,
            "generations": {g: {"collections": len(p), "total_ms": 1e3 * sum(p),
                                "max_ms": 1e3 * max(p, default=0.0)}
                            for g, p in pauses.items()}}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--json", help="also write the results to this file")
    ap.add_argument("--one", choices=["plain", "frozen"], help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:  # a child run: one line of JSON
        print(json.dumps(one_run(args.steps, args.seed, args.one == "frozen")), flush=True)
        os._exit(0)  # the harness's threads are not joined here
    facts = harness.machine_facts()
    runs = []
    for kind in ("plain", "frozen"):
        out = subprocess.run([sys.executable, os.path.abspath(__file__), "--one", kind,
                              "--steps", str(args.steps), "--seed", str(args.seed)],
                             capture_output=True, text=True, check=True).stdout
        runs.append(json.loads(out.strip().splitlines()[-1]))
    print(harness.header_line(facts, harness.loadavg(),
                              f"fuzz workload, {args.steps} steps, seed {args.seed}"))
    print("| start-up objects | generation | collections | total ms | longest ms |")
    print("| --- | --- | --- | --- | --- |")
    for r in runs:
        what = f"frozen ({r['frozen_objects']})" if r["freeze"] else "not frozen"
        for g, v in r["generations"].items():
            print(f"| {what} | {g} | {v['collections']} | {v['total_ms']:.1f} | "
                  f"{v['max_ms']:.2f} |")
    harness.write_json(args.json, facts, {"runs": runs})
    return 0


if __name__ == "__main__":
    sys.exit(main())
