# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A seeded family of seating tasks built from the pawl: for tests and benchmarks.

:func:`seating_family` perturbs the pawl of ``examples/pawl_seating.yaml`` (an L-shaped
part whose foot rests on pins 2 and 3, fixel 1 the stop ahead of it): the two pins' x,
the centre of mass, the stop's height and the start offset (how far left of its seat the
part starts). Every variant is a valid scene whose foot lies flat on both pins at the
start, and the target is all three fixels. ``test/core/test_plan.py`` and
``benchmarks/plan_cost.py`` plan them and check the success rates of the plans whose
every margin is positive.

Not a test module (pytest does not collect it); importable as ``seating_family`` once
``test/`` is on ``sys.path`` (``test/conftest.py``, ``benchmarks/harness``).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "pawl_seating.yaml"

#: Where the foot (0.06 m long) touches the stop (pin of radius 3 mm at x = 0.167 m):
#: the seated pose's x (m).
SEAT_X = 0.167 - 0.003 - 0.06


@dataclass(frozen=True)
class SeatingTask:
    """One variant: its name, the scene (the scene-file schema) and its parameters."""

    name: str
    scene: dict
    params: dict


def seating_family(n: int, seed: int = 0) -> list[SeatingTask]:
    """``n`` seeded variants of the pawl's seating task (module docstring): pin 2 at x
    in [0.105, 0.125] m, pin 3 at x in [0.14, 0.155] m, the com at (x, y) in [0.016,
    0.03] x [0.006, 0.018] m (workpiece frame), the stop's centre at y in [0.202, 0.208]
    m, the start 2 to 10 mm left of the seat."""
    base = yaml.safe_load(BASE.read_text())
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        p2 = float(rng.uniform(0.105, 0.125))
        p3 = float(rng.uniform(0.14, 0.155))
        com = [float(rng.uniform(0.016, 0.03)), float(rng.uniform(0.006, 0.018))]
        stop_y = float(rng.uniform(0.202, 0.208))
        offset = float(rng.uniform(0.002, 0.010))
        d = copy.deepcopy(base)
        d["workpiece"]["com"] = com
        d["workpiece"]["pose"] = [SEAT_X - offset, 0.2, 0.0]
        d["fixels"][0]["position"] = [0.167, stop_y]
        d["fixels"][1]["position"] = [p2, 0.197]
        d["fixels"][2]["position"] = [p3, 0.197]
        out.append(SeatingTask(f"pawl_{seed}_{k}", d, {
            "pin2_x": p2, "pin3_x": p3, "com": com, "stop_y": stop_y, "offset": offset}))
    return out
