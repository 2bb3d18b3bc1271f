# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Long fuzz run of the live node: >= 10,000 seeded mixed inputs, the same
generator as test/node/test_node_fuzz.py (test/helpers/node_fuzz.py), over real DDS.

Reports: steps, requests answered / unanswered, INTERNAL_ERROR replies, statuses per
service, parameter sets accepted / refused, whether the node and its publishing worker
are still alive, and tracebacks in the node's log (the log is captured at the fd level).

Usage: python benchmarks/node_fuzz.py [--steps 10000] [--seed 1] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time

import harness
import harness.ros  # noqa: F401  (its own DDS domain)


import rclpy  # noqa: E402
from helpers.node_fuzz import run_fuzz  # noqa: E402
from helpers.node_harness import Harness  # noqa: E402

from wrenchcone_ros.node import STATUS_NAMES  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--json", help="also write the results to this file")
    args = ap.parse_args()
    facts = harness.machine_facts()
    log = tempfile.TemporaryFile()
    saved = os.dup(2)
    os.dup2(log.fileno(), 2)  # the node's log (rcutils writes to fd 2)
    context = rclpy.context.Context()
    rclpy.init(context=context)
    t0 = time.perf_counter()
    h = Harness(context)
    try:
        res = run_fuzz(h, args.steps, args.seed)
        alive = h.node.worker.thread.is_alive() and h.check("na").status in STATUS_NAMES
    finally:
        h.close()
        rclpy.shutdown(context=context)
        os.dup2(saved, 2)
    elapsed = time.perf_counter() - t0
    log.seek(0)
    text = log.read().decode(errors="replace")
    answered = sum(res.statuses.values())
    out = {
        "seed": args.seed, "steps": res.steps, "seconds": elapsed,
        "requests_answered": answered, "unanswered": res.unanswered,
        "internal_errors": len(res.internal_errors),
        "internal_error_examples": sorted({str(e)[:300] for e in res.internal_errors})[:5],
        "node_alive": alive,
        "tracebacks": text.count("Traceback"), "refusal_log_lines": text.count("refused"),
        "statuses": {f"{svc} {STATUS_NAMES.get(s, s)}": n
                     for (svc, s), n in sorted(res.statuses.items())},
        "parameter_sets": dict(res.parameter_sets),
    }
    print(json.dumps(out, indent=2))
    harness.write_json(args.json, facts, out)
    return 0 if (alive and not res.unanswered and not res.internal_errors
                 and not out["tracebacks"]) else 1


if __name__ == "__main__":
    sys.exit(main())
