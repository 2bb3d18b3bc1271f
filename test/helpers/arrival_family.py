# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A seeded family of seating tasks in which the part reaches its last contact moving.

:func:`arrival_family` makes three kinds of task, in turn:

* ``disc``: a disc (radius 15 to 40 mm) resting on a pin, to be rolled back around it
  onto its nest pin (fixel 2), the start 10 to 30 degrees of arc past the nest;
* ``pivot``: an L part (the pawl of ``examples/pawl_seating.yaml`` with its com and pin
  2 moved) tipped forward on its front pin (fixel 3) and the stop (fixel 1), to be
  turned back onto its rear pin (fixel 2): the seated part lifted 2 to 6 mm off pin 2;
* ``bounce``: the same L part flat on both pins (pin 2 at x in [0.107, 0.113] m, pin 3
  under the foot at the start and at the seat, the com between them all along), 10
  to 20 mm left of the stop: it slides to the stop and may bounce off it.

Every task is a valid scene; the target is every fixel. ``test/core/test_plan_arrival.py``
plans a few of them, ``benchmarks/plan_cost.py`` all of them with 100 sampled models.

Not a test module (pytest does not collect it); importable as ``arrival_family`` once
``test/`` is on ``sys.path`` (``test/conftest.py``, ``benchmarks/harness``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from wrenchcone_ros.core.plan import lifted_scene
from wrenchcone_ros.core.scene_yaml import scene_from_dict

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / "examples" / "pawl_seating.yaml"

#: The seated pawl's x (m): its foot (0.06 m long) against the stop (pin of radius 3 mm
#: at x = 0.167 m).
SEAT_X = 0.167 - 0.003 - 0.06

KINDS = ("disc", "pivot", "bounce")


@dataclass(frozen=True)
class ArrivalTask:
    """One task: its name, kind, the scene (the scene-file schema), the target fixels
    (1-based) and its parameters."""

    name: str
    kind: str
    scene: dict
    target: tuple[int, ...]
    params: dict


def disc_scene(radius: float, spacing: float, past_deg: float, mu: float = 0.3,
               pin: float = 0.003) -> dict:
    """A uniform 50 g disc of ``radius`` (m) on pin 1 at (0.1, 0.2) m, its nest pin 2
    ``spacing`` (m) to the right at the same height: the disc's centre on the circle of
    radius ``radius + pin`` around pin 1, ``past_deg`` degrees beyond the nest (the
    seated pose, touching both pins)."""
    p1, p2 = (0.1, 0.2), (0.1 + spacing, 0.2)
    rr = radius + pin
    nest = math.atan2(math.sqrt(rr * rr - (spacing / 2) ** 2), spacing / 2)
    a = nest + math.radians(past_deg)
    c = (p1[0] + rr * math.cos(a), p1[1] + rr * math.sin(a))
    m = 0.05
    return {"workpiece": {"mass": m, "inertia": 0.5 * m * radius ** 2, "com": [0.0, 0.0],
                          "shape": {"type": "disc", "radius": radius},
                          "pose": [c[0], c[1], 0.0]},
            "friction": mu, "contact_tolerance": 1e-9,
            "fixels": [{"position": list(p1), "radius": pin},
                       {"position": list(p2), "radius": pin}]}


def pawl_scene(com, pin2_x: float) -> dict:
    """The seated pawl of ``examples/pawl_seating.yaml`` (the scene-file schema) with its
    com at ``com`` (workpiece frame, m) and pin 2 at x = ``pin2_x`` m."""
    d = yaml.safe_load(BASE.read_text())
    d["workpiece"]["com"] = [float(v) for v in com]
    d["workpiece"]["pose"] = [SEAT_X, 0.2, 0.0]
    d["fixels"][1]["position"] = [float(pin2_x), 0.197]
    return d


def arrival_family(n: int, seed: int = 0) -> list[ArrivalTask]:
    """``n`` seeded tasks, the kinds in turn (module docstring)."""
    rng = np.random.default_rng(seed)
    out: list[ArrivalTask] = []
    k = 0
    while len(out) < n:
        kind = KINDS[k % len(KINDS)]
        k += 1
        if kind == "disc":
            r = float(rng.uniform(0.015, 0.04))
            spacing = float(rng.uniform(0.6, 1.4)) * r
            past = float(rng.uniform(10.0, 30.0))
            mu = float(rng.uniform(0.2, 0.5))
            d = disc_scene(r, spacing, past, mu)
            out.append(ArrivalTask(f"disc_{seed}_{len(out)}", kind, d, (1, 2), {
                "radius": r, "spacing": spacing, "past_deg": past, "mu": mu}))
            continue
        com = [float(rng.uniform(0.016, 0.035)), float(rng.uniform(0.006, 0.02))]
        p2 = float(rng.uniform(0.105, 0.12))
        d = pawl_scene(com, p2)
        if kind == "pivot":
            lift = float(rng.uniform(0.002, 0.006))
            near = lifted_scene(scene_from_dict(d), 1, [0, 2], lift)
            if near is None:
                continue
            d["workpiece"]["pose"] = [float(v) for v in near.pose]
            params = {"com": com, "pin2_x": p2, "lift": lift}
        else:
            # both pins under the foot at the start and at the seat (pin 3 at most at the
            # foot's right end at the start, 0.164 - offset, minus its radius), the com
            # between the pins all along the slide (else the part tips off one)
            offset = float(rng.uniform(0.01, 0.02))
            p2 = float(rng.uniform(0.107, 0.113))
            p3 = float(rng.uniform(p2 + offset + 0.006, 0.159 - offset))
            x0 = SEAT_X - offset
            com = [float(rng.uniform(p2 - x0 + 0.002, p3 - SEAT_X - 0.002)), com[1]]
            d["workpiece"]["com"] = com
            d["fixels"][1]["position"] = [p2, 0.197]
            d["fixels"][2]["position"] = [p3, 0.197]
            d["workpiece"]["pose"] = [SEAT_X - offset, 0.2, 0.0]
            params = {"com": com, "pin2_x": p2, "pin3_x": p3, "offset": offset}
        out.append(ArrivalTask(f"{kind}_{seed}_{len(out)}", kind, d, (1, 2, 3), params))
    return out
