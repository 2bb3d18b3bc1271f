#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The fixture design's stage 1 (geometry and location, ``Enumerator.placements``) of this
checkout against another checkout of the package (e.g. the last release), in one run:
child processes alternate between the two trees, each timing the same seeded sample of
pin triples of the pawl and of a 12-edge cross on a 5 mm lattice with 2 mm pins
(benchmarks/design_cost.py's part 1); medians of the rounds, and their ratio.

    python benchmarks/design_stage1_versus.py --baseline ../other_checkout [--rounds 5]

writes benchmarks/results/design_stage1_versus.json (--no-write: print only).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from design_cost import CROSS  # the same 12-edge cross as design_cost's part 1
from harness import RESULTS, ROOT, machine_facts, write_json

OUT = RESULTS / "design_stage1_versus.json"

CHILD = r"""
import json, sys, time
import numpy as np
from wrenchcone_ros.core import Uncertainty, load_scene
from wrenchcone_ros.design.enumerate import Enumerator, pin_triples
from wrenchcone_ros.design.problem import DesignProblem, Plate
CROSS = json.loads(sys.argv[3])
out = {}
for name, part in (("pawl", sys.argv[1]), ("cross", CROSS)):
    prob = DesignProblem(load_scene(part), Plate(0.005, (16, 16), 0.002),
                         Uncertainty(friction=(0.2, 0.4)))
    triples = pin_triples(prob)
    rng = np.random.default_rng(0)
    pick = sorted(rng.choice(len(triples), size=min(int(sys.argv[2]), len(triples)),
                             replace=False))
    en = Enumerator(prob)
    en.placements(triples[pick[0]])  # warm
    t0 = time.process_time()
    n = 0
    for k in pick:
        n += len(en.placements(triples[k])[0])
    out[name] = {"triples_per_cpu_s": len(pick) / (time.process_time() - t0),
                 "placements": n}
print(json.dumps(out))
"""


def rate(tree: Path, sample: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "wrenchcone_ros"))
    out = subprocess.run([sys.executable, "-c", CHILD,
                          str(ROOT / "examples" / "pawl_seating.yaml"), str(sample),
                          json.dumps(CROSS)],
                         capture_output=True, text=True, env=env, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", type=Path, required=True,
                    help="the other checkout (its wrenchcone_ros/ folder is put first)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--sample", type=int, default=300, help="pin triples per part")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    facts = machine_facts()
    rounds = {"this": [], "baseline": []}
    for _ in range(args.rounds):
        for which, tree in (("this", ROOT), ("baseline", args.baseline)):
            rounds[which].append(rate(tree, args.sample))
    res = {}
    for part in ("pawl", "cross"):
        med = {w: statistics.median(r[part]["triples_per_cpu_s"] for r in rounds[w])
               for w in rounds}
        res[part] = {"this_triples_per_cpu_s": med["this"],
                     "baseline_triples_per_cpu_s": med["baseline"],
                     "ratio": med["this"] / med["baseline"],
                     "placements": {w: rounds[w][0][part]["placements"] for w in rounds}}
        print(f"{part}: {med['this']:.1f} triples/CPU s, baseline {med['baseline']:.1f}: "
              f"ratio {med['this'] / med['baseline']:.3f}", flush=True)
    write_json(None if args.no_write else OUT, facts,
               {"baseline": str(args.baseline), "parts": res, "rounds": rounds})


if __name__ == "__main__":
    main()
