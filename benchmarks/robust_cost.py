#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What robustness to friction intervals costs: robust cones and robust force directions
against the nominal ones, for k = 1..4 uncertain sliding fixels.

    python benchmarks/robust_cost.py                 # writes benchmarks/results/robust_cost.json
    python benchmarks/robust_cost.py --cases 4 --no-write

Cases: random scenes with 4 fixels in contact (``test/strategies.random_scene``), a random
mode with exactly k letters l or r (the others n or s) whose open mode is feasible, every
fixel's mu in [0.2, 0.4] (so 2^k friction vertices). Timed per case, interleaved (nominal,
robust, nominal, ...), each call the median of ``REPEATS`` timings of
``harness.time_per_call`` (wall clock): ``wrench_cone(scene, mode)`` against
``robust_cone(scene, mode, U, "all")`` and ``"any"``, and ``force_directions(scene,
mode)`` against ``force_directions(scene, mode, uncertainty=U)``. Ratios are per case
(same case, same run); the table gives their medians over cases.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)
from harness import fmt_ratio, fmt_time, median, time_per_call  # noqa: E402

from helpers.strategies import random_scene  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    Uncertainty,
    force_directions,
    load_scene,
    robust_cone,
    wrench_cone,
)

OUT = harness.RESULTS / "robust_cost.json"
REPEATS = 5
U = Uncertainty(friction=(0.2, 0.4))


def case(rng: np.random.Generator, k: int):
    """A scene with 4 fixels in contact and a feasible mode with exactly k sliding letters."""
    while True:
        gs = random_scene(rng, n_fixels=4, n_contact=4, per_fixel_friction=False)
        try:
            scene = load_scene(gs.data)
        except Exception:
            continue
        for _ in range(40):
            slide = rng.choice(4, size=k, replace=False)
            mode = "".join(str(rng.choice(["l", "r"])) if i in slide else str(rng.choice(["n", "s"]))
                           for i in range(4))
            if wrench_cone(scene, mode).feasible:
                return scene, mode


def timed(fn) -> float:
    return median(time_per_call(fn, min_time=5e-3, max_loops=2000) for _ in range(REPEATS))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8, help="cases per k (default 8)")
    ap.add_argument("--seed", type=int, default=20)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    facts = harness.machine_facts()
    rng = np.random.default_rng(args.seed)
    rows = []
    for k in (1, 2, 3, 4):
        rec = {"k": k, "vertices": 2 ** k, "nominal_cone": [], "robust_all": [],
               "robust_any": [], "nominal_directions": [], "robust_directions": []}
        for _ in range(args.cases):
            scene, mode = case(rng, k)
            robust_cone(scene, mode, U)  # warm the plan caches as the nominal call has
            force_directions(scene, mode, uncertainty=U)
            t = {"nominal_cone": timed(lambda s=scene, m=mode: wrench_cone(s, m)),
                 "robust_all": timed(lambda s=scene, m=mode: robust_cone(s, m, U, "all")),
                 "robust_any": timed(lambda s=scene, m=mode: robust_cone(s, m, U, "any")),
                 "nominal_directions": timed(lambda s=scene, m=mode: force_directions(s, m)),
                 "robust_directions": timed(lambda s=scene, m=mode: force_directions(
                     s, m, uncertainty=U))}
            for key, v in t.items():
                rec[key].append(v)
        med = {key: median(rec[key]) for key in rec if isinstance(rec[key], list)}
        rec["median"] = med
        rec["ratio_all"] = median(a / b for a, b in zip(rec["robust_all"], rec["nominal_cone"]))
        rec["ratio_any"] = median(a / b for a, b in zip(rec["robust_any"], rec["nominal_cone"]))
        rec["ratio_directions"] = median(a / b for a, b in zip(rec["robust_directions"],
                                                              rec["nominal_directions"]))
        rows.append(rec)
        print(f"k={k} ({2 ** k:2d} vertices): cone {fmt_time(med['nominal_cone'])}, "
              f"all {fmt_time(med['robust_all'])} ({fmt_ratio(rec['ratio_all'])}), "
              f"any {fmt_time(med['robust_any'])} ({fmt_ratio(rec['ratio_any'])}); "
              f"directions {fmt_time(med['nominal_directions'])}, robust "
              f"{fmt_time(med['robust_directions'])} ({fmt_ratio(rec['ratio_directions'])})",
              flush=True)
    if not args.no_write:
        harness.write_json(OUT, facts, {"cases_per_k": args.cases, "seed": args.seed,
                                        "rows": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
