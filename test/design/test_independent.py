# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The enumeration against an independent one (test/helpers/eee_reference.py: every
edge-edge-edge placement on the lattice in closed form, its own geometry, nothing of the
package) on small plates, for the pawl, the T-bar, a rectangle, an L part and a non-convex hexagon
with no edge on an axis: no located placement missing, none counted twice, each row's
translations on the plate counted right, and every located row's claimed contacts
touching. The same on plates that offer pins of two radii (each pin of a design any of
them, the reference solving every radius of every pin with its own code), among them a
seeded family of generated parts, turned and mirrored."""

import math

import numpy as np
import pytest
from helpers.eee_reference import enumerate_eee, touches

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.design.enumerate import enumerate_placements
from wrenchcone_ros.design.problem import DesignProblem, Plate

PAWL = [[0.0, 0.0], [0.06, 0.0], [0.06, 0.01], [0.015, 0.01], [0.015, 0.035], [0.0, 0.035]]
RECT = [[0.0, 0.0], [0.03, 0.0], [0.03, 0.02], [0.0, 0.02]]
ELL = [[0.0, 0.0], [0.04, 0.0], [0.04, 0.012], [0.012, 0.012], [0.012, 0.03], [0.0, 0.03]]
TBAR = [[0.0, 0.0], [0.12, 0.0], [0.12, 0.008], [0.066, 0.008], [0.066, 0.065],
        [0.054, 0.065], [0.054, 0.008], [0.0, 0.008]]  # examples/tbar_swing.yaml
HEX = [[0.0, 0.0], [0.035, 0.008], [0.03, 0.028], [0.018, 0.016], [0.006, 0.03],
       [-0.004, 0.014]]
SLOW = pytest.mark.slow  # the reference's own loops: 10 to 15 s each
CASES = [pytest.param("pawl", PAWL, 0.02, (5, 4), 0.003, id="pawl", marks=SLOW),
         pytest.param("rectangle", RECT, 0.01, (5, 4), 0.003, id="rectangle"),
         pytest.param("ell", ELL, 0.01, (5, 4), 0.0025, id="ell", marks=SLOW),
         pytest.param("hexagon", HEX, 0.01, (4, 4), 0.003, id="hexagon"),
         pytest.param("tbar", TBAR, 0.025, (6, 4), 0.003, id="tbar", marks=SLOW)]

#: the reference's pose match (m, and m of L theta)
MATCH = 1e-7


def _problem(V, pitch, extent, r, fixed=()):
    """The part on a plate of pin radius r, or of the radii r (a list), with fixed pins
    ([i, j, radius])."""
    com = np.mean(np.asarray(V), axis=0)
    d = {"workpiece": {"mass": 0.05, "inertia": 2e-5, "com": com.tolist(),
                       "shape": {"type": "polygon", "vertices": V}},
         "friction": 0.3, "fixels": [[1.0, 1.0]]}
    fixed = tuple(tuple(f) for f in fixed)
    plate = (Plate(pitch, extent, pin_radii=tuple(r), fixed_pins=fixed) if isinstance(r, list)
             else Plate(pitch, extent, r, fixed_pins=fixed))
    return DesignProblem(load_scene(d), plate)


def _rel(holes, pose, pitch, radii):
    """The pins up to translation, each hole with its pin's radius, and the pose moved
    with them."""
    i0, j0 = min(holes)
    offs = tuple(sorted(((i - i0, j - j0), float(r)) for (i, j), r in zip(holes, radii)))
    return offs, (pose[0] - i0 * pitch, pose[1] - j0 * pitch, pose[2])


def _close(a, b, L):
    return (math.hypot(a[0] - b[0], a[1] - b[1]) <= MATCH
            and abs(math.remainder(a[2] - b[2], 2 * math.pi)) * L <= MATCH)


@pytest.mark.parametrize("name,V,pitch,extent,r", CASES)
def test_the_enumeration_against_an_independent_edge_edge_edge_one(name, V, pitch, extent, r):
    assert _check_against_the_reference(V, pitch, extent, r), \
        "the reference found no located placement: a vacuous case"


def generated_parts(n: int, seed: int, radii: int = 1, mirror: bool = False
                    ) -> list[tuple[list, float, tuple[int, int], float | list]]:
    """A seeded family nobody tuned on: star-shaped polygons of 4 to 6 vertices (convex
    or not, no edge on an axis by design), 15 to 35 mm across, turned by a random angle,
    on plates of pitch 10 to 15 mm whose pins are 1.5 to 5 mm in radius (below half the
    pitch, as a plate requires). With ``radii`` > 1 each plate offers that many radii,
    each sampled so (a list); with ``mirror`` every other part is mirrored (x -> -x, its
    vertices reversed to stay counter-clockwise)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        k = int(rng.integers(4, 7))
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        if np.min(np.diff(np.r_[ang, ang[0] + 2 * np.pi])) < 0.5:
            continue  # a sliver of an edge: not a part anyone machines
        size = rng.uniform(0.0075, 0.0175)
        rad = size * rng.uniform(0.55, 1.0, k)
        V = np.c_[rad * np.cos(ang), rad * np.sin(ang)]
        if mirror and len(out) % 2:
            V = np.c_[-V[:, 0], V[:, 1]][::-1]
        V -= V.min(axis=0)
        pitch = float(rng.choice([0.01, 0.0125, 0.015]))
        rs = [round(float(rng.uniform(0.0015, min(0.005, 0.45 * pitch))), 5)
              for _ in range(radii)]
        if len(set(rs)) < radii:
            continue
        across = float(np.max(np.ptp(V, axis=0)))
        n_holes = int(np.ceil((across + 2 * max(rs)) / pitch)) + 3  # room for placements
        out.append((np.round(V, 6).tolist(), pitch, (n_holes, n_holes),
                    rs[0] if radii == 1 else rs))
    return out


@pytest.mark.slow
def test_a_generated_family_of_parts_and_pin_radii_against_the_reference():
    """The same checks on parts and plates the tool was never tuned on
    (:func:`generated_parts`, seed 11): pin radii from 1.5 to 5 mm, convex and
    non-convex outlines at any angle. The reference knows edge contacts only: on a
    part whose every located placement has a pin on a vertex it has nothing to compare
    (then only the claimed contacts are checked); most parts of the family are not."""
    compared = [_check_against_the_reference(V, pitch, extent, r)
                for V, pitch, extent, r in generated_parts(8, seed=11)]
    assert sum(n > 0 for n in compared) >= 5, compared


@pytest.mark.parametrize("name,V,pitch,extent,radii", [
    pytest.param("rectangle", RECT, 0.01, (4, 3), [0.002, 0.0035], id="rectangle"),
    pytest.param("hexagon", HEX, 0.01, (4, 4), [0.0015, 0.004], id="hexagon", marks=SLOW),
    pytest.param("pawl", PAWL, 0.02, (5, 3), [0.002, 0.005], id="pawl", marks=SLOW)])
def test_pins_of_two_radii_against_the_reference(name, V, pitch, extent, radii):
    """Plates that offer two pin radii: every placement of the reference, whatever
    radius each of its pins has, is a row with those radii; some of them with pins of
    unequal radii (the case a plate of one size never has)."""
    unequal = _check_against_the_reference(V, pitch, extent, radii, unequal=True)
    assert unequal > 0, "no located reference placement on unequal pins: a vacuous case"


@pytest.mark.slow
def test_fixed_pins_of_their_own_radius_against_the_reference():
    """A plate of two radii whose fixed pin has a third (2.5 mm): every placement of the
    reference through that pin, with it at its radius and the others at the plate's,
    is a row; no row has another radius there."""
    fixed = [[1, 0, 0.0025]]
    unequal = _check_against_the_reference(RECT, 0.01, (4, 3), [0.002, 0.0035],
                                           unequal=True, fixed=fixed)
    assert unequal > 0, "no located reference placement: a vacuous case"


@pytest.mark.slow
def test_a_generated_family_on_pins_of_unequal_radii_against_the_reference():
    """The family of :func:`generated_parts` (seed 23), every other part mirrored, on
    plates that offer two radii sampled from 1.5 to 5 mm: the checks above on every
    radius assignment, and most parts have located placements on pins of unequal radii
    to compare."""
    compared = [_check_against_the_reference(V, pitch, extent, radii, unequal=True)
                for V, pitch, extent, radii in generated_parts(6, seed=23, radii=2,
                                                               mirror=True)]
    assert sum(n > 0 for n in compared) >= 4, compared


def _check_against_the_reference(V, pitch, extent, r, unequal: bool = False,
                                 fixed=()) -> int:
    """The checks above; returns how many located reference placements were matched
    (``unequal``: only those whose pins differ in radius). With ``fixed`` pins ([i, j,
    radius]) the reference offers every hole the plate's radii and the fixed pins' too,
    and keeps the placements whose pins include every fixed pin with its radius and whose
    other pins have a radius the plate offers."""
    pr = _problem(V, pitch, extent, r, fixed)
    L, com = pr.part.length_scale, pr.part.workpiece.com
    rows = list(enumerate_placements(pr))
    if fixed:
        given = {(i, j): rf for i, j, rf in fixed}
        ref = [q for q in enumerate_eee(V, pitch, extent, sorted({*r, *given.values()}),
                                        com, L)
               if set(given) <= set(q["holes"])
               and all(given.get(h, rq) == rq and (h in given or rq in r)
                       for h, rq in zip(q["holes"], q["radii"]))]
    else:
        ref = enumerate_eee(V, pitch, extent, r, com, L)
    ours: dict[tuple, list] = {}  # the rows by their pins up to translation
    for p in rows:
        offs, rel = _rel(p.holes, p.pose, pitch, p.radii)
        ours.setdefault(offs, []).append((rel, p))
    # no duplicate: no two rows with the same pins (up to translation) and pose
    for same in ours.values():
        for a in range(len(same)):
            for b in range(a + 1, len(same)):
                assert not _close(same[a][0], same[b][0], L), (same[a][1].design_id,
                                                               same[b][1].design_id)
    # every located reference placement that surely fits is a located row, counted once
    # per translation
    per_row: dict[str, int] = {}
    missing = []
    matched_unequal = 0
    for q in ref:
        if q["sigma"] <= 2e-3 or not q["fits_surely"]:
            continue
        offs, rel = _rel(q["holes"], q["pose"], pitch, q["radii"])
        match = [p for pr_, p in ours.get(offs, []) if _close(pr_, rel, L)]
        if not match:
            missing.append((q["holes"], q["pose"]))
            continue
        assert len(match) == 1 and match[0].located, (q["holes"], q["pose"])
        per_row[match[0].design_id] = per_row.get(match[0].design_id, 0) + 1
        matched_unequal += len(set(q["radii"])) > 1
    assert not missing, missing[:5]
    byid = {p.design_id: p for p in rows}
    theirs: dict[tuple, list] = {}  # the reference's placements that may fit, by pins
    for q in ref:
        if q["fits_maybe"]:
            offs, rel = _rel(q["holes"], q["pose"], pitch, q["radii"])
            theirs.setdefault(offs, []).append(rel)
    for k, n in per_row.items():
        assert byid[k].placements >= n, (k, byid[k].placements, n)
    # every located row touches every feature it claims; an all-edge located row is one
    # of the reference's
    for p in rows:
        if not p.located:
            continue
        for pin, label, rp in zip(p.positions, p.features, p.radii):
            for f in label.split("+"):
                assert touches(V, p.pose, np.array(pin), f, rp, 1e-9), (p.design_id, f)
        if all(f.startswith("e") for lab in p.features for f in lab.split("+")):
            offs, rel = _rel(p.holes, p.pose, pitch, p.radii)
            assert any(_close(qrel, rel, L) for qrel in theirs.get(offs, [])), p.design_id
    if isinstance(r, list):  # the radii the plate offers (and its fixed pins'), no other
        assert {v for p in rows for v in p.radii} <= set(r) | {f[2] for f in fixed}
    return matched_unequal if unequal else sum(per_row.values())
