# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Pins of unequal radii in one fixture: the plate's ``pin_radii`` (each hole takes any
of them) and fixed pins with their own radius are read and checked; a square part
resting on two pins of different radii and a third against its side has the pose
computed here by hand; each pin of a design is a fixel of its own radius in the scene
the core checks; the table, the terminal summary and the sheet say each pin's radius."""

import math

import numpy as np
import pytest

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.design.enumerate import enumerate_placements
from wrenchcone_ros.design.problem import DesignError, DesignProblem, Plate, plate_from_dict
from wrenchcone_ros.design.stages import design_scene, hold

SIDE = 0.03
SQUARE = [[0.0, 0.0], [SIDE, 0.0], [SIDE, SIDE], [0.0, SIDE]]


def _square_problem(plate) -> DesignProblem:
    d = {"workpiece": {"mass": 0.05, "inertia": 5e-6, "com": [SIDE / 2, SIDE / 2],
                       "shape": {"type": "polygon", "vertices": SQUARE}},
         "friction": 0.3, "fixels": [[1.0, 1.0]]}
    return DesignProblem(load_scene(d), plate, (0.2, 0.4))


def test_a_plate_offers_several_pin_radii_and_fixed_pins_carry_their_own():
    p = plate_from_dict({"pitch": 0.01, "extent": [6, 5], "pin_radii": [0.004, 0.002],
                         "fixed_pins": [[1, 0, 0.0025], [3, 0, 0.004]]})
    assert p.pin_radii == (0.002, 0.004)
    assert p.fixed_pins == ((1, 0), (3, 0)) and p.fixed_radii == (0.0025, 0.004)
    assert p.mixed and p.pin_radius is None
    # the one-size shorthand: one radius, fixed pins of that radius
    q = plate_from_dict({"pitch": 0.01, "extent": [6, 5], "pin_radius": 0.003,
                         "fixed_pins": [[1, 0]]})
    assert q.pin_radii == (0.003,) and q.fixed_radii == (0.003,) and not q.mixed
    assert q.pin_radius == 0.003
    # the dict round trip keeps every radius
    assert plate_from_dict(p.to_dict()) == p and plate_from_dict(q.to_dict()) == q


@pytest.mark.parametrize("plate,words", [
    ({"pin_radii": [0.002, 0.005]}, "pin_radii 2 must be in [0, pitch / 2) = [0, 0.005) m"),
    ({"pin_radii": []}, "pin_radii must be a list of 1 to 4 radii"),
    ({"pin_radii": 0.002}, "pin_radii must be a list of 1 to 4 radii"),
    ({"pin_radii": [0.001, 0.002, 0.003, 0.004, 0.0045]}, "pin_radii must be a list of 1 to 4"),
    ({"pin_radii": [0.002, 0.002]}, "pin_radii must be distinct"),
    ({"pin_radius": 0.002, "pin_radii": [0.002, 0.003]}, "give pin_radius (one size) or pin_radii (several), not both"),
    ({}, "missing required key 'pin_radius' (or 'pin_radii', several sizes)"),
    ({"pin_radii": [0.002, 0.003], "fixed_pins": [[1, 0]]},
     "fixed pin 1 must give its radius [i, j, r]"),
    ({"pin_radius": 0.002, "fixed_pins": [[1, 0, 0.006]]},
     "fixed pin 1's radius must be in [0, pitch / 2) = [0, 0.005) m"),
    ({"pin_radius": 0.002, "fixed_pins": [[1, 0, "big"]]}, "fixed pin 1's radius (m) must be"),
])
def test_bad_radii_are_refused_with_what_is_allowed(plate, words):
    with pytest.raises(DesignError) as exc:
        plate_from_dict({"pitch": 0.01, "extent": [6, 5], **plate})
    assert words in str(exc.value) and "\n" not in str(exc.value), str(exc.value)


def _hand_pose(c1, r1, c2, r2, c3, r3):
    """The square on pins 1 and 2 under its bottom edge (edge 0) and pin 3 against its
    right side (edge 1), by hand. The bottom edge's direction u = (cos t, sin t) and its
    inward normal m = (-sin t, cos t): every point x of the edge's line has m . (x - O) =
    0 (O the part frame's origin), a pin under it at distance r has m . c = m . O - r, so
    m . c1 + r1 = m . c2 + r2; with c1, c2 on the x axis, d apart, sin t = (r2 - r1) / d.
    The right side is u . (x - O) = SIDE, pin 3 outside it: u . c3 = u . O + SIDE + r3.
    Then O = (m . O) m + (u . O) u."""
    d = c2[0] - c1[0]
    t = math.asin((r2 - r1) / d)
    u, m = np.array([math.cos(t), math.sin(t)]), np.array([-math.sin(t), math.cos(t)])
    mo, uo = m @ c1 + r1, u @ c3 - SIDE - r3
    o = mo * m + uo * u
    return (float(o[0]), float(o[1]), t)


def test_a_square_on_two_pins_of_different_radii_sits_where_the_hand_computation_says():
    plate = Plate(0.01, (6, 4), pin_radii=(0.002, 0.004))
    pr = _square_problem(plate)
    c1, c2, c3 = np.array([0.0, 0.0]), np.array([0.02, 0.0]), np.array([0.03, 0.01])
    r1, r2, r3 = 0.002, 0.004, 0.002
    x, y, t = _hand_pose(c1, r1, c2, r2, c3, r3)
    assert math.degrees(t) == pytest.approx(5.739, abs=1e-3)  # asin(0.1)
    triple = ((2, 0), (3, 1))
    rows = [p for p in enumerate_placements(pr, [triple])
            if p.radii == (r1, r2, r3) and p.holes == ((0, 0), (2, 0), (3, 1))]
    match = [p for p in rows if math.hypot(p.pose[0] - x, p.pose[1] - y) <= 1e-9
             and abs(p.pose[2] - t) <= 1e-9]
    assert len(match) == 1, [(p.pose, p.features) for p in rows]
    p = match[0]
    assert p.features == ("e0", "e0", "e1") and p.located
    assert p.design_id.endswith("@2,4,2#" + p.design_id.split("#")[1])
    # the core sees each pin as a fixel of its own radius, all three touching
    scene = design_scene(pr, p.positions, p.pose, p.radii)
    assert [f.radius for f in scene.fixels] == [r1, r2, r3]
    assert all(scene.in_contact) and max(abs(g) for g in scene.gaps) <= 1e-9
    # with equal radii the same pins give another pose: the radii are not ignored
    flat = [q for q in enumerate_placements(pr, [triple]) if q.radii == (r1, r1, r1)
            and q.features == ("e0", "e0", "e1")]
    assert flat and all(abs(q.pose[2]) <= 1e-12 for q in flat)


def test_every_radius_assignment_of_a_triple_is_enumerated_and_fixed_pins_keep_theirs():
    """Without fixed pins a triple takes every one of the K^3 assignments of the plate's
    K radii; a fixed pin keeps its own radius, a radius no other hole is offered."""
    from wrenchcone_ros.design.enumerate import Enumerator

    pr = _square_problem(Plate(0.01, (6, 4), pin_radii=(0.002, 0.004)))
    en = Enumerator(pr)
    triple = ((2, 0), (3, 1))
    assert en.radius_assignments(triple) == [
        (a, b, c) for a in (0.002, 0.004) for b in (0.002, 0.004) for c in (0.002, 0.004)]
    fixed = _square_problem(Plate(0.01, (6, 4), pin_radii=(0.002, 0.004),
                                  fixed_pins=((0, 0, 0.003),)))
    en = Enumerator(fixed)
    got = en.radius_assignments(triple)
    assert got == [(0.003, b, c) for b in (0.002, 0.004) for c in (0.002, 0.004)]
    for p in enumerate_placements(fixed):
        k = p.holes.index((0, 0))
        assert p.radii[k] == 0.003
        assert all(r in (0.002, 0.004) for j, r in enumerate(p.radii) if j != k)


def test_the_hold_stage_sees_each_pin_with_its_own_radius():
    """The hold of the hand-computed seat: the scene's fixels carry the radii, and the
    hold interval differs from the one on pins of one radius at the same holes (another
    seat, another geometry)."""
    plate = Plate(0.01, (6, 4), pin_radii=(0.002, 0.004))
    pr = _square_problem(plate)
    pos = [(0.0, 0.0), (0.02, 0.0), (0.03, 0.01)]
    x, y, t = _hand_pose(*(np.array(c) for c in pos[:1]), 0.002, np.array(pos[1]), 0.004,
                         np.array(pos[2]), 0.002)
    h = hold(pr, pos, (x, y, t), radii=(0.002, 0.004, 0.002))
    assert "reason" not in h, h
    assert h["hold_lo"] < h["best_tilt"] < h["hold_hi"]


def test_the_table_the_summary_and_the_sheet_say_each_pins_radius():
    """A run on the square's triple: every row carries its pins' radii (columns and
    name), the terminal summary has a radii column, and the sheet draws each pin at its
    radius with the radii in the panel's title."""
    pytest.importorskip("pyarrow")
    from matplotlib.patches import Circle

    from wrenchcone_ros.cli.design import summary
    from wrenchcone_ros.design.pipeline import design_fixtures
    from wrenchcone_ros.design.plot import design_sheet

    plate = Plate(0.01, (6, 4), pin_radii=(0.002, 0.004))
    pr = _square_problem(plate)
    res = design_fixtures(pr.part, plate, (0.2, 0.4), workers=0, plans=1, runs=0, top=2,
                          triples=[((2, 0), (3, 1))])
    assert len({r["design_id"] for r in res.rows}) == len(res.rows) > 8
    for r in res.rows:
        radii = (r["pin1_r"], r["pin2_r"], r["pin3_r"])
        assert set(radii) <= {0.002, 0.004}
        tag = ",".join(f"{v * 1000:g}" for v in radii)
        assert f"@{tag}#" in r["design_id"]
    assert len({(r["pin1_r"], r["pin2_r"], r["pin3_r"]) for r in res.rows}) > 1
    text = summary(res, 2).splitlines()
    assert "radii mm" in text[1]
    rows_shown = [line for line in text[2:] if not line.startswith("      ")]  # no reasons
    assert len(rows_shown) == 2
    for line, r in zip(rows_shown, res.rows):
        assert ",".join(f"{r[f'pin{k}_r'] * 1000:g}" for k in (1, 2, 3)) in line
    fig = design_sheet(pr, res.rows, 1)
    ax = fig.axes[0]
    assert "r " + "/".join(f"{res.rows[0][f'pin{k}_r'] * 1000:g}" for k in (1, 2, 3)) \
        in ax.get_title()
    drawn = sorted(p.radius for p in ax.patches if isinstance(p, Circle))
    assert drawn == sorted(res.rows[0][f"pin{k}_r"] for k in (1, 2, 3))


@pytest.mark.slow
def test_the_hold_on_unequal_pins_in_the_engine_at_the_friction_box_corners():
    """The hand-computed seat on a 2 mm, a 4 mm and a 2 mm pin, in pymunk with each pin
    at its radius: under a tilt one degree inside either end of the hold interval every
    corner model of the friction box stays; one degree outside, some corner model
    moves."""
    import itertools

    pytest.importorskip("pymunk")
    from wrenchcone_ros.core.simulate import simulate
    from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND

    pr = _square_problem(Plate(0.01, (6, 4), pin_radii=(0.002, 0.004)))
    pos = [(0.0, 0.0), (0.02, 0.0), (0.03, 0.01)]
    radii = (0.002, 0.004, 0.002)
    pose = _hand_pose(np.array(pos[0]), radii[0], np.array(pos[1]), radii[1],
                      np.array(pos[2]), radii[2])
    h = hold(pr, pos, pose, radii=radii)
    scene = design_scene(pr, pos, pose, radii)
    band = SIM_CONTACT_BAND * scene.length_scale
    corners = list(itertools.product((0.2, 0.4), repeat=3))
    one = math.radians(1.0)

    def moved(phi, mus) -> float:
        tr = simulate(scene, phi, "tilt", friction=mus, record_every=10 ** 6)
        p, q = tr.frames[-1].pose, scene.pose
        return math.hypot(p[0] - q[0], p[1] - q[1]) + abs(p[2] - q[2]) * scene.length_scale

    for phi in (h["best_tilt"], h["hold_lo"] + one, h["hold_hi"] - one):
        assert max(moved(phi, c) for c in corners) <= band, phi
    for phi in (h["hold_lo"] - one, h["hold_hi"] + one):
        assert max(moved(phi, c) for c in corners) > 10 * band, phi
