#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Do force_directions and consistent_modes give one answer, across I/(m L^2)?

    python benchmarks/agreement_vs_inertia.py      # writes benchmarks/results/agreement_vs_inertia.json

Two functions answer the same question from two sides: ``force_directions(scene, mode,
exclusive=True)`` gives the directions phi of a pure force at the com that produce
``mode`` and no other mode (intervals with exact breakpoints), and ``consistent_modes``
classifies one wrench (every mode whose cone contains it, with ``CONE_TOLERANCE`` in the
nondimensional metric). Inside an exclusive interval the classification must be
``[mode]``; next to an edge, a wrench within the tolerance of a neighbouring cone may be
classified as both, by design. How far inside an edge that ambiguity reaches, as an
angle, depends on the scene's stiffness I / (m L^2): a wrench's margin to a neighbouring
cone grows with the angle at a rate that shrinks with I / (m L^2).

For every scene (the examples and seeded random scenes of the error study's families)
and every ratio k = I / (m L^2) in 1e-8 .. 1e6 (every decade: the whole range
``load_scene`` accepts, ``ACCEPTED_INERTIA_RATIO``), the inertia is set to k m L^2, and
for every exclusive interval of every valid mode, directions at an angle d inside each
edge (d = 1e-1 .. 1e-12 rad, and the midpoint) are classified. Reported per k:

* ``deepest_disagreement_rad``: the largest d (or half-width, for the midpoint) at which
  the classification is not ``[mode]``: the angular reach of the ambiguity;
* ``midpoint_disagreements``: intervals whose midpoint is classified otherwise (a
  contradiction beyond any tolerance);
* the number of intervals and classified directions.

The verified range ``VERIFIED_INERTIA_RATIO`` (core/tolerances.py) is where this reach
stays below ``AGREEMENT_ANGLE_RAD`` and the error study (error_vs_runtime.py) finds no
classification error outside its band; outside it every function warns.
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from helpers.strategies import random_scene  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    ModeError,
    Scene,
    consistent_modes,
    enumerate_modes,
    force_directions,
    load_scene,
)
from wrenchcone_ros.core.directions import force_basis  # noqa: E402
from wrenchcone_ros.core.geometry import UnverifiedRangeWarning  # noqa: E402
from wrenchcone_ros.core.tolerances import (  # noqa: E402
    ACCEPTED_INERTIA_RATIO,
    AGREEMENT_ANGLE_RAD,
    VERIFIED_INERTIA_RATIO,
)

OUT = harness.RESULTS / "agreement_vs_inertia.json"
EXAMPLES = ["paper_disc", "disc_nest", "pawl_polygon", "pawl_tipped", "pawl_seating",
            "tbar_swing"]
DEPTHS = [10.0 ** -e for e in range(1, 13)]
RATIOS = [10.0 ** e for e in range(round(math.log10(ACCEPTED_INERTIA_RATIO[0])),
                                    round(math.log10(ACCEPTED_INERTIA_RATIO[1])) + 1)]


def with_ratio(data: dict, k: float) -> Scene:
    """The scene of ``data`` with its inertia set to k m L^2."""
    L = load_scene(data).length_scale
    wp = dict(data["workpiece"])
    wp["inertia"] = float(k * wp["mass"] * L * L)
    return load_scene({**data, "workpiece": wp})


def probe(scene: Scene) -> dict:
    """Classify directions inside every exclusive interval of every valid mode."""
    B = np.asarray(force_basis(scene, None), dtype=float)
    deepest, mid_bad, intervals, classified = 0.0, 0, 0, 0
    for mode in enumerate_modes(scene.in_contact):
        try:
            found = force_directions(scene, mode, exclusive=True)
        except ModeError:
            continue
        for iv in found:
            width = iv.hi - iv.lo
            if width <= 0.0:
                continue
            intervals += 1
            probes = [(width / 2.0, iv.lo + width / 2.0, True)]
            probes += [(d, iv.lo + d, False) for d in DEPTHS if d < width / 2.0]
            probes += [(d, iv.hi - d, False) for d in DEPTHS if d < width / 2.0]
            for depth, phi, is_mid in probes:
                g = B @ np.array([math.cos(phi), math.sin(phi)])
                got = [m.mode for m in consistent_modes(scene, g)]
                classified += 1
                if got != [mode]:
                    deepest = max(deepest, depth)
                    mid_bad += int(is_mid)
    return {"deepest": deepest, "midpoint_disagreements": mid_bad, "intervals": intervals,
            "classified": classified}


def scenes(n_random: int, seed: int) -> list[tuple[str, dict]]:
    """The examples and ``n_random`` seeded random scenes, as scene dicts."""
    root = Path(__file__).resolve().parents[1] / "examples"
    out = [(name, load_scene(root / f"{name}.yaml").to_dict()) for name in EXAMPLES]
    rng = np.random.default_rng(seed)
    for i in range(n_random):
        out.append((f"random-{i}", random_scene(rng).data))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=12, help="random scenes (default 12)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore", UnverifiedRangeWarning)
    facts = harness.machine_facts()
    cases = scenes(args.random, args.seed)
    rows = []
    for k in RATIOS:
        per = {name: probe(with_ratio(data, k)) for name, data in cases}
        row = {"ratio": k,
               "deepest_disagreement_rad": max(p["deepest"] for p in per.values()),
               "midpoint_disagreements": sum(p["midpoint_disagreements"] for p in per.values()),
               "intervals": sum(p["intervals"] for p in per.values()),
               "classified": sum(p["classified"] for p in per.values()),
               "worst_scene": max(per, key=lambda n: per[n]["deepest"])}
        rows.append(row)
        print(f"I/(mL^2) = {k:7.0e}: deepest disagreement {row['deepest_disagreement_rad']:.0e} rad"
              f" ({row['worst_scene']}), midpoints contradicted {row['midpoint_disagreements']},"
              f" {row['intervals']} intervals, {row['classified']} directions", flush=True)
    if not args.no_write:
        harness.write_json(OUT, facts, {
            "random_scenes": args.random, "seed": args.seed, "examples": EXAMPLES,
            "depths_rad": DEPTHS, "accepted_ratio": list(ACCEPTED_INERTIA_RATIO),
            "verified_ratio": list(VERIFIED_INERTIA_RATIO),
            "agreement_angle_rad": AGREEMENT_ANGLE_RAD, "rows": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
