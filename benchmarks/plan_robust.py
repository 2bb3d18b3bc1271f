#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The pawl's plan under mass, centre-of-mass and friction uncertainty: cost and outcome.

    python benchmarks/plan_robust.py     # writes benchmarks/results/plan_robust.json

examples/pawl_seating.yaml, target 1 2 3, every fixel's mu in [0.2, 0.4], the mass in
[0.045, 0.055] kg, the centre of mass anywhere within 1 mm of its nominal place (the
scenario approach, eps = 0.05, beta = 1e-3: N = 220 sampled models per robust cone):
the plan (default work bounds), then 100 sampled models (every parameter drawn, seed
0) in 2 worker processes. Wall and CPU time (``time.perf_counter``,
``time.process_time`` of the planning process), the plan's segments, margins, tilt
accuracy, guarantee or what is missing, the capture test's runs and the success rate.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating, run_models, sample_models  # noqa: E402

OUT = harness.RESULTS / "plan_robust.json"
RUNS = 100


def main() -> int:
    facts = harness.machine_facts()
    scene = load_scene(harness.ROOT / "examples" / "pawl_seating.yaml")
    u = Uncertainty(friction=(0.2, 0.4), mass=(0.045, 0.055), com_radius=0.001)
    wall, cpu = time.perf_counter(), time.process_time()
    plan = plan_seating(scene, [1, 2, 3], uncertainty=u, simulate_runs=False)
    plan_wall, plan_cpu = time.perf_counter() - wall, time.process_time() - cpu
    wall = time.perf_counter()
    runs = run_models(scene, plan, sample_models(scene, u, RUNS, 0), workers=2)
    mc_wall = time.perf_counter() - wall
    plan = replace(plan, runs=tuple(runs))
    results = {
        "uncertainty": u.to_dict(), "scenario_models": u.scenario_size(),
        "planning_wall_s": plan_wall, "planning_cpu_s": plan_cpu, "mc_wall_s": mc_wall,
        "runs": RUNS, "feasible": plan.feasible, "guaranteed": plan.guaranteed,
        "missing": list(plan.missing), "guarantee": plan.guarantee,
        "segments": [{"mode": s.mode, "direction_deg": math.degrees(s.direction),
                      "margin": s.margin, "accuracy_deg": math.degrees(s.accuracy),
                      "scale": s.scale} for s in plan.segments],
        "checks": [[r.label, r.success] for r in plan.checks],
        "success_rate": plan.success_rate, "contradicted": plan.contradicted,
        "tried": list(plan.tried)}
    print(results)
    harness.write_json(OUT, facts, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
