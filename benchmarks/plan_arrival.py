#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans whose part arrives moving: guarantees against the engine, per kind of task.

    python benchmarks/plan_arrival.py     # writes benchmarks/results/plan_arrival.json
    python benchmarks/plan_arrival.py --quick --no-write

Tasks (wall clock, ``time.perf_counter``; one planner at a time, the Monte Carlo in 2
worker processes):

* ``arrival``: the seeded arrival family (test/helpers/arrival_family.py, ``--arrival`` tasks,
  seed 0): discs rolled onto their nest pin, L parts turned back onto their rear pin,
  L parts sliding 10 to 30 mm to the stop; every fixel's mu in the task's mu +- 0.1;
* ``seating``: the seeded family of test/helpers/seating_family.py (``--seating`` tasks, seed 0),
  mu in [0.2, 0.4];
* ``example``: examples/pawl_seating.yaml, pawl_tipped.yaml, tbar_swing.yaml,
  disc_nest.yaml, mu in [0.2, 0.4].

Per task: the plan (default work bounds), its planning time (wall, and the CPU time of
the planning thread), the work it took (candidates, segments planned), the candidates it
rejected, guaranteed or what is missing, the nominal run; for every guaranteed plan the
success rate over 100 sampled models (every uncertain parameter drawn, seed 0) and the
runs whose contact events differ from the plan's, and the plan run with the impact
parameters at the edges of what the guarantee assumes (restitution 0 and
EDGE_RESTITUTION, each with every fixel's mu at the low end, at the high end, and each
fixel alone low: the failures listed); for every task whose plan does not
seat the part in its nominal run, a scan of constant tilts (every ``--scan-step``
degrees, the check of test/core/test_plan_examples.py: the engine's nominal model, each
tilt run as a one-tilt plan) that says whether one tilt would have seated it. And the
pawl's plan with 100 models (examples/pawl_seating.yaml, mu in [0.2, 0.4]), timed
``REPEATS`` times.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from helpers.arrival_family import arrival_family  # noqa: E402
from helpers.seating_family import seating_family  # noqa: E402
from helpers.tilt_scan import constant_tilt  # noqa: E402

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.core.plan import (  # noqa: E402
    execute,
    plan_seating,
    run_models,
    sample_models,
)
from wrenchcone_ros.core.scene_yaml import scene_from_dict  # noqa: E402

OUT = harness.RESULTS / "plan_arrival.json"
EX = harness.ROOT / "examples"
REPEATS = 3
RUNS = 100
#: The impacts' restitution at the edge of what the guarantee assumes (0: inelastic).
EDGE_RESTITUTION = 0.05


def edge_models(n: int, friction) -> list[tuple[str, list[float]]]:
    """The friction at the impacts at the edges of the interval: every fixel low, every
    fixel high, each fixel alone low (the others high)."""
    lo, hi = friction
    return ([("all low", [lo] * n), ("all high", [hi] * n)]
            + [(f"fixel {i + 1} low", [lo if j == i else hi for j in range(n)])
               for i in range(n)])


def pawl_time(runs: int) -> dict:
    scene = load_scene(EX / "pawl_seating.yaml")
    plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)  # warm
    walls = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), runs=runs, workers=2)
        walls.append(time.perf_counter() - t)
    return {"runs": runs, "wall_s": walls, "median_s": statistics.median(walls),
            "guaranteed": plan.guaranteed, "success_rate": plan.success_rate}


def one(kind: str, name: str, scene, target, friction, scan_step: int, runs: int) -> dict:
    t, cpu = time.perf_counter(), time.thread_time()
    plan = plan_seating(scene, list(target), uncertainty=friction, simulate_runs=False)
    planning, planning_cpu = time.perf_counter() - t, time.thread_time() - cpu
    row = {"kind": kind, "name": name, "planning_s": planning,
           "planning_cpu_s": planning_cpu, "feasible": plan.feasible,
           "guaranteed": plan.guaranteed, "missing": list(plan.missing),
           "modes": [s.mode for s in plan.segments],
           "scales": [s.scale for s in plan.segments],
           "directions_deg": [math.degrees(s.direction) for s in plan.segments],
           # the constant-tilt last resort's plan keeps the search's first dead end
           "constant_tilt": "the search's first dead end" in plan.reason,
           "margins": [s.margin for s in plan.segments], "tried": len(plan.tried),
           "nominal_seated": bool(plan.nominal and plan.nominal.success),
           "reason": plan.reason, "candidates": plan.candidates, "trials": plan.trials}
    if plan.guaranteed:  # the Monte Carlo on this very plan
        mc = run_models(scene, plan, sample_models(scene, Uncertainty(friction=friction),
                                                   runs, 0), workers=2)
        row.update(runs=len(mc), success_rate=sum(r.success for r in mc) / len(mc),
                   contradicted=sum(not r.matches for r in mc))
        edges = edge_models(scene.n_fixels, friction)
        failed = [(e, label, r.reason) for e in (0.0, EDGE_RESTITUTION)
                  for (label, mu) in edges
                  if not (r := execute(scene, plan, mu, restitution=e)).success]
        row.update(edge_runs=2 * len(edges), edge_failures=failed)
    if not row["nominal_seated"]:
        seats = [d for d in range(-180, 180, scan_step)
                 if constant_tilt(scene, float(d), tuple(target)).seated]
        row["scan_seating_tilts_deg"] = seats
    print(f"{name:>14} {kind:>8} feasible {plan.feasible!s:5} guaranteed "
          f"{plan.guaranteed!s:5} nominal {row['nominal_seated']!s:5} "
          f"{planning:5.1f} s  rate {row.get('success_rate')}  "
          f"scan {row.get('scan_seating_tilts_deg')}", flush=True)
    return row


def summary(rows: list[dict]) -> dict:
    out = {}
    for kind in sorted({r["kind"] for r in rows}):
        rs = [r for r in rows if r["kind"] == kind]
        g = [r for r in rs if r["guaranteed"]]
        scanned = [r for r in rs if r.get("scan_seating_tilts_deg")]
        out[kind] = {
            "tasks": len(rs), "feasible": sum(r["feasible"] for r in rs),
            "guaranteed": len(g),
            "guaranteed_refuted_nominal": sum(not r["nominal_seated"] for r in g),
            "guaranteed_below_99": sum(r["success_rate"] < 0.99 for r in g),
            "edge_runs": sum(r["edge_runs"] for r in g),
            "edge_failures": sum(len(r["edge_failures"]) for r in g),
            "guaranteed_with_an_edge_failure": sum(bool(r["edge_failures"]) for r in g),
            "smallest_guaranteed_rate": min((r["success_rate"] for r in g), default=None),
            "nominal_seated": sum(r["nominal_seated"] for r in rs),
            "one_tilt_seats_but_plan_does_not": len(scanned),
            "planning_s_median": statistics.median(r["planning_s"] for r in rs),
            "planning_s_max": max(r["planning_s"] for r in rs),
            "planning_cpu_s_median": statistics.median(r["planning_cpu_s"] for r in rs),
            "planning_cpu_s_max": max(r["planning_cpu_s"] for r in rs),
            "bound_reached": sum("limit" in r["reason"] for r in rs)}
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer tasks and runs (smoke)")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--arrival", type=int, default=30)
    ap.add_argument("--seating", type=int, default=8)
    ap.add_argument("--scan-step", type=int, default=6)
    args = ap.parse_args()
    facts = harness.machine_facts()
    runs = 10 if args.quick else RUNS
    plan_seating(load_scene(EX / "pawl_seating.yaml"), [1, 2, 3], uncertainty=(0.2, 0.4),
                 simulate_runs=False)  # warm: the kernels load once, outside every row
    rows = []
    for name, target in (("pawl_seating", (1, 2, 3)), ("pawl_tipped", (1, 2, 3)),
                         ("tbar_swing", (1, 2)), ("disc_nest", (1, 2))):
        rows.append(one("example", name, load_scene(EX / f"{name}.yaml"), target,
                        (0.2, 0.4), args.scan_step, runs))
    for task in arrival_family(6 if args.quick else args.arrival, seed=0):
        scene = scene_from_dict(task.scene)
        mu = scene.friction
        rows.append(one(task.kind, task.name, scene, task.target,
                        (max(0.0, mu - 0.1), mu + 0.1), args.scan_step, runs))
    for task in seating_family(2 if args.quick else args.seating, seed=0):
        rows.append(one("seating", task.name, scene_from_dict(task.scene), (1, 2, 3),
                        (0.2, 0.4), args.scan_step, runs))
    results = {"pawl_plan_100_models": pawl_time(runs), "summary": summary(rows),
               "tasks": rows}
    print(results["summary"], results["pawl_plan_100_models"])
    if not args.no_write:
        harness.write_json(OUT, facts, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
