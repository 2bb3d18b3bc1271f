#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The work a seating search needs, unbounded: where the planner's work bounds come from.

    python benchmarks/plan_work.py     # writes benchmarks/results/plan_work.json
    python benchmarks/plan_work.py --quick --no-write

Every task of the planner's test families and documented examples is planned with no
bound at all (``max_candidates=None, max_trials=None, budget=None``): the search ends by
its candidates. Per task: the complete candidates it put to the capture test, the
segments it planned and simulated, the CPU time of the planning thread, and the plan
(guaranteed, modes, directions). Then every task is planned again with the defaults
(DEFAULT_MAX_CANDIDATES, DEFAULT_MAX_TRIALS) and compared with the unbounded plan: a
default that changes an answer shows as a row with ``same`` False. The summary gives the
largest work any task needed, which the defaults must exceed.

Tasks: examples/pawl_seating.yaml, pawl_tipped.yaml, tbar_swing.yaml, disc_nest.yaml
(mu in [0.2, 0.4]); the 8 mm and 12 mm pawls of docs/planning.md section 3 (nominal);
the arrival family (test/helpers/arrival_family.py, 30 tasks, seed 0, mu +- 0.1) and the
seating family (test/helpers/seating_family.py, 8 tasks, seed 0, mu in [0.2, 0.4]).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from helpers.arrival_family import arrival_family  # noqa: E402
from helpers.seating_family import seating_family  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from wrenchcone_ros.core.plan.search import (  # noqa: E402
    DEFAULT_MAX_CANDIDATES,
    DEFAULT_MAX_TRIALS,
)
from wrenchcone_ros.core.scene_yaml import scene_from_dict  # noqa: E402

OUT = harness.RESULTS / "plan_work.json"
EX = harness.ROOT / "examples"


def tasks(quick: bool) -> list[tuple[str, str, object, tuple[int, ...], object]]:
    """(kind, name, scene, target, friction interval or None)."""
    out = []
    for name, target in (("pawl_seating", (1, 2, 3)), ("pawl_tipped", (1, 2, 3)),
                         ("tbar_swing", (1, 2)), ("disc_nest", (1, 2))):
        out.append(("example", name, load_scene(EX / f"{name}.yaml"), target, (0.2, 0.4)))
    polygon = load_scene(EX / "pawl_polygon.yaml")
    for mm, x in ((12, 0.092), (8, 0.096)):
        out.append(("docs", f"pawl_polygon_{mm}mm", polygon.with_pose(x, 0.2, 0.0),
                    (1, 2, 3), None))
    for task in arrival_family(6 if quick else 30, seed=0):
        scene = scene_from_dict(task.scene)
        mu = scene.friction
        out.append((task.kind, task.name, scene, task.target, (max(0.0, mu - 0.1), mu + 0.1)))
    for task in seating_family(2 if quick else 8, seed=0):
        out.append(("seating", task.name, scene_from_dict(task.scene), (1, 2, 3),
                    (0.2, 0.4)))
    return out


def answer(plan) -> dict:
    """What must not move: the plan, its evidence and its search's record."""
    return {"feasible": plan.feasible, "guaranteed": plan.guaranteed,
            "modes": [s.mode for s in plan.segments],
            "scales": [s.scale for s in plan.segments],
            "directions_deg": [math.degrees(s.direction) for s in plan.segments],
            "margins": [s.margin for s in plan.segments],
            "reason": plan.reason, "tried": list(plan.tried)}


def one(kind: str, name: str, scene, target, friction) -> dict:
    cpu = time.thread_time()
    free = plan_seating(scene, list(target), uncertainty=friction, simulate_runs=False,
                        max_candidates=None, max_trials=None, budget=None)
    cpu = time.thread_time() - cpu
    bounded = plan_seating(scene, list(target), uncertainty=friction, simulate_runs=False)
    row = {"kind": kind, "name": name, "candidates": free.candidates,
           "trials": free.trials, "planning_cpu_s": cpu, **answer(free),
           "same_with_defaults": answer(bounded) == answer(free)}
    print(f"{name:>20} {kind:>8} candidates {free.candidates:3d} trials {free.trials:4d} "
          f"cpu {cpu:6.2f} s guaranteed {free.guaranteed!s:5} same "
          f"{row['same_with_defaults']}", flush=True)
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tasks (smoke)")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    facts = harness.machine_facts()
    plan_seating(load_scene(EX / "pawl_seating.yaml"), [1, 2, 3], uncertainty=(0.2, 0.4),
                 simulate_runs=False)  # warm: the kernels load once, outside every row
    rows = [one(*t) for t in tasks(args.quick)]
    summary = {"tasks": len(rows),
               "max_candidates_needed": max(r["candidates"] for r in rows),
               "max_trials_needed": max(r["trials"] for r in rows),
               "max_planning_cpu_s": max(r["planning_cpu_s"] for r in rows),
               "default_max_candidates": DEFAULT_MAX_CANDIDATES,
               "default_max_trials": DEFAULT_MAX_TRIALS,
               "same_with_defaults": sum(r["same_with_defaults"] for r in rows)}
    print(summary)
    if not args.no_write:
        harness.write_json(OUT, facts, {"summary": summary, "tasks": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
