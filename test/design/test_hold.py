# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Hold intervals checked in the physics engine (pymunk) at the corners of the friction
box: the seated part under a tilt inside the interval stays at rest for every corner
model; one degree outside either end, some corner model moves."""

import itertools
import math

import pytest

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.simulate import simulate
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND
from wrenchcone_ros.design import design_fixtures
from wrenchcone_ros.design.problem import DesignProblem, Plate
from wrenchcone_ros.design.stages import design_scene

pytest.importorskip("pymunk")

PLATE = Plate(0.01, (9, 6), 0.003)
FRICTION = (0.2, 0.4)
TRIPLES = [((1, 2), (5, -1)), ((3, 2), (4, -2))]


@pytest.fixture(scope="module")
def designs():
    res = design_fixtures("examples/pawl_seating.yaml", PLATE, FRICTION, workers=0,
                          plans=0, runs=0, triples=TRIPLES)
    rows = [r for r in res.rows if r["hold_margin"] is not None
            and r["hold_hi"] - r["hold_lo"] < 2 * math.pi - 1e-6]
    assert len(rows) >= 2
    return rows[:3]


def _moved(scene, phi, mus) -> float:
    """How far the part moved (m, com travel + L times the turn) in 2 T from rest."""
    tr = simulate(scene, phi, "tilt", friction=mus, record_every=10 ** 6)
    p, q = tr.frames[-1].pose, scene.pose
    return math.hypot(p[0] - q[0], p[1] - q[1]) + abs(p[2] - q[2]) * scene.length_scale


@pytest.mark.slow
def test_hold_intervals_in_the_engine_at_the_friction_box_corners(designs):
    prob = DesignProblem(load_scene("examples/pawl_seating.yaml"), PLATE)
    corners = list(itertools.product(FRICTION, repeat=3))
    one = math.radians(1.0)
    for r in designs:
        pos = [(r[f"pin{k}_x"], r[f"pin{k}_y"]) for k in (1, 2, 3)]
        scene = design_scene(prob, pos, (r["x"], r["y"], r["theta"]))
        band = SIM_CONTACT_BAND * scene.length_scale
        for phi in (r["best_tilt"], r["hold_lo"] + one, r["hold_hi"] - one):
            assert max(_moved(scene, phi, c) for c in corners) <= band, (r["design_id"], phi)
        for phi in (r["hold_lo"] - one, r["hold_hi"] + one):
            assert max(_moved(scene, phi, c) for c in corners) > 10 * band, (
                r["design_id"], phi)


WRAP_PLATE = {"pitch": 0.01, "extent": [12, 12], "pin_radius": 0.003,
              "fixed_pins": [[0, 2], [4, 0], [4, 2]]}


@pytest.mark.slow
def test_the_hold_interval_of_a_placement_at_180_degrees_is_whole_in_the_engine():
    # the pawl upside down, a pin in the foot's inner corner: its hold interval crosses
    # +-180 degrees; one row, one interval, checked in the engine at both ends
    res = design_fixtures("examples/pawl_seating.yaml", WRAP_PLATE, FRICTION, workers=0,
                          plans=0, runs=0)
    (r,) = [r for r in res.rows if abs(abs(r["theta"]) - math.pi) < 1e-9
            and r["hold_margin"] is not None]
    assert "e2+e3" in r["features"].split(",")
    assert r["hold_lo"] < math.pi < r["hold_hi"]  # across the former split at 180 deg
    prob = DesignProblem(load_scene("examples/pawl_seating.yaml"),
                         Plate(0.01, (12, 12), 0.003))
    pos = [(r[f"pin{k}_x"], r[f"pin{k}_y"]) for k in (1, 2, 3)]
    scene = design_scene(prob, pos, (r["x"], r["y"], r["theta"]))
    band = SIM_CONTACT_BAND * scene.length_scale
    corners = list(itertools.product(FRICTION, repeat=3))
    one = math.radians(1.0)
    for phi in (r["best_tilt"], r["hold_lo"] + one, math.pi, r["hold_hi"] - one):
        assert max(_moved(scene, phi, c) for c in corners) <= band, phi
    for phi in (r["hold_lo"] - one, r["hold_hi"] + one):
        assert max(_moved(scene, phi, c) for c in corners) > 10 * band, phi
