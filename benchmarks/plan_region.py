#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans for a box of start poses: the region certified, its cost, and sampled starts.

    python benchmarks/plan_region.py     # writes benchmarks/results/plan_region.json

For each task (the pawl of examples/pawl_seating.yaml, +-2 mm x +-2 mm x +-5 deg; the
disc of examples/disc_nest.yaml, +-1 mm x +-1 mm x +-5 deg; the pawl again, +-6 mm x
+-10 mm x +-10 deg, a box its plan does not hold from; every fixel's mu in [0.2, 0.4]): ``plan_seating(..., start_region=...)`` with the default cover and
bisections, on 2 worker processes, no sampled runs (wall time, and CPU time of the
planning process and of its worker processes); then 1,000 starts drawn uniformly in the
certified box (``sample_starts``, seed 0), each with its own sampled model
(``sample_models``, seed 0), run in the engine: how many seat, and why the others do
not; then the same in the box twice the certified one per axis (dtheta at most pi):
how many fail there, and for a box that was shrunk, in the asked box too (the
certification is not vacuous when some do).
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import (  # noqa: E402
    StartRegion,
    plan_seating,
    run_starts,
    sample_models,
    sample_starts,
)
from wrenchcone_ros.core.uncertainty import as_uncertainty  # noqa: E402

OUT = harness.RESULTS / "plan_region.json"
STARTS = 1000
WORKERS = 2
TASKS = (
    ("pawl", "pawl_seating.yaml", [1, 2, 3], (0.002, 0.002, math.radians(5.0))),
    ("disc", "disc_nest.yaml", [1, 2], (0.001, 0.001, math.radians(5.0))),
    ("pawl_large", "pawl_seating.yaml", [1, 2, 3], (0.006, 0.01, math.radians(10.0))),
)


def sampled(scene, plan, box: StartRegion, unc, seed: int) -> dict:
    """STARTS starts uniform in ``box``, each with a sampled model, run in the engine."""
    starts = sample_starts(scene, box, STARTS, seed)
    runs = run_starts(scene, plan, starts, sample_models(scene, unc, len(starts), seed),
                      workers=WORKERS)
    fails = [r for r in runs if not r.success]
    reasons: dict[str, int] = {}
    for r in fails:
        key = r.reason.split(" (")[0]
        reasons[key] = reasons.get(key, 0) + 1
    return {"box": box.to_dict(), "starts": len(runs),
            "seated": sum(r.success for r in runs),
            "as_planned": sum(r.matches for r in runs),
            "failure_reasons": reasons,
            "failures": [{"start": list(r.start), "friction": list(r.friction),
                          "reason": r.reason} for r in fails[:10]]}


def main() -> int:
    facts = harness.machine_facts()
    out = {}
    for name, path, target, box in TASKS:
        scene = load_scene(harness.ROOT / "examples" / path)
        unc = as_uncertainty((0.2, 0.4), scene)
        t0, c0, k0 = time.perf_counter(), time.process_time(), os.times()
        plan = plan_seating(scene, target, uncertainty=unc, simulate_runs=False,
                            workers=WORKERS, start_region=box)
        k1 = os.times()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        children = (k1.children_user + k1.children_system
                    - k0.children_user - k0.children_system)
        cert = plan.region
        row = {"scene": f"examples/{path}", "target": target, "friction": [0.2, 0.4],
               "asked": StartRegion.of(box).to_dict(), "guaranteed": plan.guaranteed,
               "segments": [{"mode": s.mode, "direction_deg": math.degrees(s.direction),
                             "scale": s.scale} for s in plan.segments],
               "region": cert.to_dict(), "planning_wall_s": wall,
               "planning_cpu_s": cpu, "workers_cpu_s": children}
        certified = plan.start_region
        if certified is not None:
            row["certified_box"] = sampled(scene, plan, certified, unc, 0)
            twice = StartRegion(2 * certified.dx, 2 * certified.dy,
                                min(math.pi, 2 * certified.dtheta))
            row["twice_the_box"] = sampled(scene, plan, twice, unc, 1)
            if not cert.whole:
                row["asked_box"] = sampled(scene, plan, StartRegion.of(box), unc, 2)
        print(name, row)
        out[name] = row
    harness.write_json(OUT, facts, {"tasks": out, "starts": STARTS, "workers": WORKERS})
    return 0


if __name__ == "__main__":
    sys.exit(main())
