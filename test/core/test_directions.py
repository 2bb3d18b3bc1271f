# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Force directions, force regions, sweeps and the tray-tilt convention (core/directions.py).

References, none of them the code under test: dense sampling of directions classified by
``consistent_modes`` and by the LP check (lp_check.py, Newton-Euler and Table 2 written
directly), exact rational arithmetic, a hand derivation on the pawl, and rotation
matrices for the tray tilt. Sampled directions closer than ENDPOINT_GUARD to an interval
endpoint are skipped (float endpoints are accurate to about CONE_TOLERANCE, 1e-9 rad; the
LP decides with a relative slack of 1e-7, hence its wider guard).
"""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

from helpers.strategies import random_mode, random_scene
from wrenchcone_ros.core import (
    ModeError,
    force_directions,
    force_region,
    load_scene,
    sweep,
    tilt_directions,
    tilt_gravity_force,
    wrench_cone,
)
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.core.tilt import STANDARD_GRAVITY
from wrenchcone_ros.core.lp_check import lp_consistent, lp_mode_feasible
from wrenchcone_ros.core.modes import expand_mode
from wrenchcone_ros.core.scene_yaml import scene_from_dict

#: Radians: sampled directions this close to an endpoint are not compared.
ENDPOINT_GUARD = 1e-6
#: Radians: the same for the LP oracle (relative slack tolerance 1e-7).
LP_ENDPOINT_GUARD = 1e-4

PAWL = "examples/pawl_polygon.yaml"


def wrench_at(scene, point, phi):
    """The wrench about the com of a unit force along phi at a workpiece point, written
    out here (not with the module's basis)."""
    x, y, th = scene.pose
    px, py = scene.workpiece.com if point is None else point
    cx, cy = scene.workpiece.com
    c, s = math.cos(th), math.sin(th)
    rx, ry = c * (px - cx) - s * (py - cy), s * (px - cx) + c * (py - cy)
    fx, fy = math.cos(phi), math.sin(phi)
    return np.array([fx, fy, rx * fy - ry * fx])


def near_endpoint(phi, intervals, guard):
    for iv in intervals:
        for e in (iv.lo, iv.hi):
            if abs((phi - e + math.pi) % (2 * math.pi) - math.pi) < guard:
                return True
    return False


def inside(phi, intervals):
    return any(iv.contains(phi) for iv in intervals)


def check_well_formed(ivs):
    for iv in ivs:
        assert -math.pi <= iv.lo < math.pi and iv.lo <= iv.hi <= iv.lo + 2 * math.pi
        assert iv.contains(iv.best)
    los = [iv.lo for iv in ivs]
    assert los == sorted(los)
    for a, b in zip(ivs, ivs[1:]):  # disjoint (the last may wrap onto the first)
        assert a.hi < b.lo
    if len(ivs) > 1:
        assert ivs[-1].hi < ivs[0].lo + 2 * math.pi


def _case(seed):
    """A random scene, mode (concrete or with wildcards), point and exclusive flag; the
    mode is usually taken from the classification of a random direction so that the
    answer is rarely empty."""
    rng = np.random.default_rng(seed)
    gs = random_scene(rng, n_fixels=int(rng.integers(1, 4)))
    scene = load_scene(gs.data)
    point = None if rng.uniform() < 0.4 else tuple(rng.uniform(-1, 1, 2) * gs.size)
    clf = ModeClassifier(scene)
    mode = random_mode(rng, scene.in_contact)
    if rng.uniform() < 0.7:
        found = clf.consistent_modes(wrench_at(scene, point, rng.uniform(-math.pi, math.pi)))
        if found:
            mode = found[int(rng.integers(len(found)))].mode
    if rng.uniform() < 0.3:
        mode = "".join("*" if rng.uniform() < 0.5 else ch for ch in mode)
    exclusive = bool(rng.uniform() < 0.35)
    return scene, mode, point, exclusive, clf


@pytest.mark.parametrize("seed", range(24))
def test_intervals_agree_with_sampled_classification(seed):
    scene, mode, point, exclusive, clf = _case(seed)
    ivs = force_directions(scene, mode, point=point, exclusive=exclusive)
    check_well_formed(ivs)
    mine = set(expand_mode(mode, scene.in_contact))
    n = 240
    for k in range(n):
        phi = -math.pi + 2 * math.pi * (k + 0.37) / n
        if near_endpoint(phi, ivs, ENDPOINT_GUARD):
            continue
        found = {m.mode for m in clf.consistent_modes(wrench_at(scene, point, phi))}
        truth = bool(found & mine) and (not exclusive or found <= mine)
        assert inside(phi, ivs) == truth, (mode, exclusive, point, math.degrees(phi), found)


@pytest.mark.parametrize("seed", range(100, 112))
def test_intervals_agree_with_the_lp_check(seed):
    scene, mode, point, _, _ = _case(seed)
    concrete = expand_mode(mode, scene.in_contact)
    feas = {m: lp_mode_feasible(scene, m) for m in concrete}
    ivs = force_directions(scene, mode, point=point)
    checked = 0
    for k in range(48):
        phi = -math.pi + 2 * math.pi * (k + 0.61) / 48
        if near_endpoint(phi, ivs, LP_ENDPOINT_GUARD):
            continue
        g = wrench_at(scene, point, phi)
        res = [lp_consistent(scene, m, g, feasibility=feas[m]) for m in concrete]
        if not all(r.decided for r in res):
            continue
        checked += 1
        assert inside(phi, ivs) == any(r.consistent for r in res), (mode, math.degrees(phi))
    assert checked > 0


#: Radians: float endpoints agree with the exact ones to this (module docstring of
#: directions.py: ~1e-9 rad from CONE_TOLERANCE; measured max 3.1e-15 on these cases).
ENDPOINT_ACCURACY = 1e-9
#: Cases (a seed of _case, or a pawl case) whose answer has proper intervals: neither
#: empty nor the whole circle; exclusive ones with 2 and 3 fixels among them.
PROPER_CASES = [222, 224, 225, 229, 235, 242, 245, 257, 265, 299,
                ("arr", None), ("s**", (0.06, 0.0))]


def _proper_case(case):
    if isinstance(case, tuple):  # the pawl (3 fixels), exclusive
        return load_scene(PAWL), case[0], case[1], True
    scene, mode, point, exclusive, _ = _case(case)
    return scene, mode, point, exclusive


@pytest.mark.parametrize("case", PROPER_CASES, ids=str)
def test_float_endpoints_agree_with_exact_ones(case):
    scene, mode, point, exclusive = _proper_case(case)
    fl = force_directions(scene, mode, point=point, exclusive=exclusive)
    ex = force_directions(scene, mode, point=point, exclusive=exclusive, exact=True)
    assert fl and not any(iv.whole_circle for iv in fl)  # a proper answer to compare
    assert len(fl) == len(ex)
    for a, b in zip(fl, ex):
        assert abs(a.lo - b.lo) < ENDPOINT_ACCURACY and abs(a.hi - b.hi) < ENDPOINT_ACCURACY
        assert all(isinstance(x, Fraction) for x in b.lo_direction + b.hi_direction)
        for angle, vec in ((b.lo, b.lo_direction), (b.hi, b.hi_direction)):
            # the angle is the exact vector's, rounded once
            a_vec = math.atan2(float(vec[1]), float(vec[0]))
            assert (angle - a_vec + math.pi) % (2 * math.pi) - math.pi == pytest.approx(
                0.0, abs=1e-15)


@pytest.mark.slow
@pytest.mark.parametrize("case", [242, 299, ("arr", None), ("s**", (0.06, 0.0))], ids=str)
def test_exclusive_agrees_with_the_lp_check(case):
    """Exclusive = consistent with the mode by the LP and with no other feasible mode of
    the scene by the LP (3 fixels: every one of the scene's modes is checked)."""
    scene, mode, point, exclusive = _proper_case(case)
    assert exclusive and scene.n_fixels == 3
    mine = set(expand_mode(mode, scene.in_contact))
    every = expand_mode("*" * scene.n_fixels, scene.in_contact)
    feas = {m: lp_mode_feasible(scene, m) for m in every}
    ivs = force_directions(scene, mode, point=point, exclusive=True)
    checked = inside_count = 0
    for k in range(24):
        phi = -math.pi + 2 * math.pi * (k + 0.61) / 24
        if near_endpoint(phi, ivs, LP_ENDPOINT_GUARD):
            continue
        g = wrench_at(scene, point, phi)
        res = {m: lp_consistent(scene, m, g, feasibility=feas[m]) for m in every
               if feas[m].consistent}
        if not all(r.decided for r in res.values()):
            continue
        found = {m for m, r in res.items() if r.consistent}
        truth = bool(found & mine) and found <= mine
        checked += 1
        inside_count += truth
        assert inside(phi, ivs) == truth, (mode, math.degrees(phi), found)
    assert checked >= 12 and 0 < inside_count < checked  # both answers were compared


def test_contact_wildcard_c():
    """c = contact kept with l, r or n: "acc" on the pawl is the union of its nine modes,
    checked against sampled classification and against the union of the concrete modes'
    intervals; "*" adds s and so is a superset."""
    scene = load_scene(PAWL)
    clf = ModeClassifier(scene)
    mine = set(expand_mode("acc", scene.in_contact))
    assert mine == {"a" + x + y for x in "lrn" for y in "lrn"}
    for point in (None, (0.05, 0.005)):
        ivs = force_directions(scene, "acc", point=point)
        check_well_formed(ivs)
        parts = [force_directions(scene, m, point=point) for m in sorted(mine)]
        wider = force_directions(scene, "a**", point=point)
        n_in = 0
        for k in range(240):
            phi = -math.pi + 2 * math.pi * (k + 0.37) / 240
            if near_endpoint(phi, ivs + [iv for p in parts for iv in p], ENDPOINT_GUARD):
                continue
            found = {m.mode for m in clf.consistent_modes(wrench_at(scene, point, phi))}
            assert inside(phi, ivs) == bool(found & mine), (point, math.degrees(phi), found)
            assert inside(phi, ivs) == any(inside(phi, p) for p in parts)
            assert not inside(phi, ivs) or inside(phi, wider)
            n_in += inside(phi, ivs)
        assert 0 < n_in < 240


def test_pawl_arr_at_the_com_by_hand():
    """Sliding right (+x) on the two pins under the foot (normals +y, mu = 0.3): the
    contact forces lie on the friction edge c_n (-mu, 1); a pure force at the com stops
    accelerating the pawl right when it balances them, f ~ (mu, -1) = (1, -10/3); it lifts
    the foot above the horizontal. So arr is exactly [atan2(-10/3, 1), 0], and the exact
    endpoints are those rational vectors."""
    scene = load_scene(PAWL)
    (iv,) = force_directions(scene, "arr", exact=True)
    assert iv.lo_direction == (Fraction(1), Fraction(-10, 3))
    assert iv.hi_direction == (Fraction(1), Fraction(0))
    assert iv.lo == pytest.approx(math.atan2(-10 / 3, 1), abs=1e-15) and iv.hi == 0.0
    (only,) = force_directions(scene, "arr", exclusive=True)
    assert only.lo == pytest.approx(iv.lo, abs=1e-12) and only.hi == pytest.approx(0, abs=1e-12)


@pytest.mark.parametrize("seed", [3, 7, 11, 300, 301, 302])
def test_best_beats_dense_sampling(seed):
    scene, mode, point, exclusive, _ = _case(seed)
    ivs = force_directions(scene, mode, point=point, exclusive=exclusive)
    clf = ModeClassifier(scene)
    cones = [clf.cone(m) for m in expand_mode(mode, scene.in_contact)]
    others = [clf.cone(m) for m in expand_mode("*" * scene.n_fixels, scene.in_contact)
              if m not in {c.mode for c in cones}]

    def margin(phi):
        g = wrench_at(scene, point, phi)
        m = max(c.margin(g) for c in cones)
        if exclusive:
            m = min([m] + [-c.margin(g) for c in others if c.feasible])
        return m

    for iv in ivs:
        assert iv.margin == pytest.approx(margin(iv.best), abs=1e-12)
        sampled = max(margin(p) for p in np.linspace(iv.lo, iv.hi, 2001))
        assert iv.margin >= sampled - 1e-9


# --- degenerate cases ------------------------------------------------------------------
def _disc(mu, fixels, com=(0.0, 0.0)):
    return scene_from_dict({
        "workpiece": {"mass": 1.0, "inertia": 0.5, "com": list(com),
                      "shape": {"type": "disc", "radius": 1.0}},
        "friction": mu, "fixels": fixels})


def test_empty_set_for_an_impossible_mode():
    scene = load_scene(PAWL)
    assert not wrench_cone(scene, "ann").feasible  # two rolling pins fix the pawl
    assert force_directions(scene, "ann") == []
    assert force_directions(scene, "ann", exclusive=True) == []
    assert force_region(scene, "ann") == []


def test_single_direction_rolling_without_friction():
    """mu = 0, one fixel under a disc, rolling: contact force along +y only, and a pure
    force at the centre cannot spin the disc about the contact point, so only the push
    straight down works (a single direction; the cone has an empty interior)."""
    scene = _disc(0.0, [[0.0, -1.0]])
    cone = wrench_cone(scene, "n")
    assert cone.equalities.shape[0] > 0
    (iv,) = force_directions(scene, "n")
    assert iv.lo == iv.hi == iv.best == pytest.approx(-math.pi / 2, abs=1e-12)
    assert iv.margin == 0.0
    (ex,) = force_directions(scene, "n", exact=True)
    assert ex.lo_direction[0] == 0 and ex.lo_direction[1] < 0 and ex.lo == ex.hi


def test_empty_interior_cone_gives_margin_zero_and_the_middle():
    """A point off the centre of a frictionless disc: rolling admits a whole arc of force
    directions, but the cone still has an empty interior: margin 0, best in the middle."""
    scene = _disc(0.0, [[0.0, -1.0]])
    ivs = force_directions(scene, "n", point=(0.5, 0.0))
    for iv in ivs:
        assert iv.margin == 0.0
        assert iv.best == pytest.approx(0.5 * (iv.lo + iv.hi), abs=2 * math.pi / 64)


def test_centre_of_percussion_half_circle_and_a_line():
    """Frictionless rolling on a disc (m = 1, I = 0.5, R = 1) about the contact point
    (0, -1): the cone is the half-plane {I f_x + m R tau = 0, f_y <= 0}. A force at
    (x, y) has tau = x f_y - y f_x, so the equality reads (I - m R y) f_x + m R x f_y = 0.
    At the centre of percussion (0, I / (m R)) it vanishes: every downward force works,
    the half circle [-pi, 0]. At (0.3, 0.5) it says f_y = 0: the line of horizontal forces,
    two single directions."""
    scene = _disc(0.0, [[0.0, -1.0]])
    (half,) = force_directions(scene, "n", point=(0.0, 0.5), exact=True)
    assert (half.lo, half.hi) == (-math.pi, 0.0)
    assert half.lo_direction == (-1, 0) and half.hi_direction == (1, 0)
    left, right = force_directions(scene, "n", point=(0.3, 0.5), exact=True)
    assert left.lo == left.hi == -math.pi and right.lo == right.hi == 0.0
    assert left.lo_direction == (-1, 0) and right.lo_direction == (1, 0)
    assert [(iv.lo, iv.hi) for iv in force_directions(scene, "n", point=(0.3, 0.5))] == [
        (-math.pi, -math.pi), (0.0, 0.0)]


def test_whole_circle():
    scene = _disc(0.3, [[0.0, -1.5]])  # one free fixel: a or s, anything goes
    (iv,) = force_directions(scene, "*")
    assert iv.whole_circle and iv.lo == -math.pi and iv.hi == math.pi
    assert iv.margin == 1.0 and -math.pi <= iv.best < math.pi


@pytest.mark.slow
def test_point_on_a_contacts_line_of_action():
    """Fixel 2's normal passes through the pawl's com (both at workpiece x = 0.02); a point
    higher up on the same line and one on fixel 3's line (x = 0.05) agree with sampling."""
    scene = load_scene(PAWL)
    clf = ModeClassifier(scene)
    for point in [None, (0.02, 0.03), (0.05, 0.005), (0.05, 0.0)]:
        for mode in ["arr", "snn", "s**"]:
            ivs = force_directions(scene, mode, point=point)
            mine = set(expand_mode(mode, scene.in_contact))
            for k in range(180):
                phi = -math.pi + 2 * math.pi * (k + 0.5) / 180
                if near_endpoint(phi, ivs, ENDPOINT_GUARD):
                    continue
                found = {m.mode for m in clf.consistent_modes(wrench_at(scene, point, phi))}
                assert inside(phi, ivs) == bool(found & mine), (point, mode, phi)


def test_frictionless_pawl():
    """mu = 0: sliding right on the pins needs only a rightward push (any downward part is
    taken by the pins), arr = [-90 deg, 0] at the com."""
    d = load_scene(PAWL).to_dict()
    d["friction"] = 0.0
    scene = scene_from_dict(d)
    (iv,) = force_directions(scene, "arr", exact=True)
    assert iv.lo_direction[0] == 0 and iv.lo_direction[1] < 0
    assert iv.hi_direction[1] == 0 and iv.hi_direction[0] > 0


def test_bad_input():
    scene = load_scene(PAWL)
    with pytest.raises(ModeError, match="fixel 1 is not in contact"):
        force_directions(scene, "nrr")
    with pytest.raises(ValueError, match="point"):
        force_directions(scene, "arr", point=(0.0, float("nan")))
    with pytest.raises(ValueError, match="point"):
        force_directions(scene, "arr", point=(0.0,))
    with pytest.raises(ValueError, match="offset"):
        force_region(scene, "arr", offset=(0, 0, float("inf")))
    with pytest.raises(ValueError, match="pose 1"):
        sweep(scene, [[0.1, 0.2, 0.0], [0.1, 0.2]], "arr")
    with pytest.raises(ValueError, match="pose 1.*penetrates"):
        sweep(scene, [[0.1, 0.2, 0.0], [0.1, 0.199, 0.0]], "arr")


# --- force regions -----------------------------------------------------------------------
def _in_hull(x, V, R, Lines):
    """x in conv(V) + cone(R) + span(Lines), by an LP feasibility problem."""
    nv, nr, nl = len(V), len(R), len(Lines)
    A_eq = np.hstack([np.asarray(V).T.reshape(2, nv), np.asarray(R).T.reshape(2, nr),
                      np.asarray(Lines).T.reshape(2, nl)])
    A_eq = np.vstack([A_eq, [1.0] * nv + [0.0] * (nr + nl)])
    b_eq = np.array([x[0], x[1], 1.0])
    bounds = [(0, None)] * (nv + nr) + [(None, None)] * nl
    return linprog(np.zeros(nv + nr + nl), A_eq=A_eq, b_eq=b_eq, bounds=bounds,
                   method="highs").status == 0


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(400, 412))
def test_force_region_agrees_with_contains_and_its_vertices(seed):
    rng = np.random.default_rng(seed)
    scene, mode, point, _, _ = _case(seed)
    o = rng.normal(size=3) * [1.0, 1.0, scene.length_scale]
    if seed % 3 == 0:
        o = np.zeros(3)
    regions = force_region(scene, mode, point=point, offset=o)
    cones = wrench_cone(scene, mode)
    pieces = getattr(cones, "pieces", [cones])
    assert {r.mode for r in regions} <= {c.mode for c in pieces if c.feasible}
    B = np.array([wrench_at(scene, point, 0.0), wrench_at(scene, point, math.pi / 2)]).T
    for f in rng.normal(size=(300, 2)) * 3.0:
        g = o + B @ f
        margins = [c.margin(g) for c in pieces if c.feasible]
        if margins and min(abs(m) for m in margins) < 1e-6:
            continue
        truth = cones.contains(g)
        assert any(r.contains(f) for r in regions) == truth, (mode, f)
        for r in regions:
            if r.contains(f) and r.A_eq.shape[0] == 0:
                assert _in_hull(f, r.vertices, r.rays, r.lines)
    for r in regions:
        for v in r.vertices:
            assert r.contains(v, tol=1e-7)


def test_force_region_with_a_preload_on_the_pawl():
    """The pawl's own weight on a tray tilted 5 degrees straight down (-y) presses it onto
    the pins; a spring at the top of the upright then needs enough rightward pull to
    slide it: the region for arr is bounded away from f = 0 and f = 0 itself is not in."""
    scene = load_scene(PAWL)
    fx, fy = tilt_gravity_force(scene.workpiece.mass, math.radians(5), -math.pi / 2)
    (reg,) = force_region(scene, "arr", point=(0.0075, 0.035), offset=(fx, fy, 0.0))
    assert not reg.contains((0.0, 0.0))
    assert reg.vertices.shape[0] >= 1
    assert all(float(v[0]) > 0 for v in reg.vertices)


def test_force_region_bounded_on_the_pawl():
    """A force at the foot's corner (0, 0) with the offset (0.05 N, -0.1 N, 0) about the
    com: the region of arr is a bounded polygon; sampled forces agree with the cone's
    contains, and its vertices lie in it."""
    scene = load_scene(PAWL)
    o = np.array([0.05, -0.1, 0.0])
    (reg,) = force_region(scene, "arr", point=(0.0, 0.0), offset=o)
    assert reg.bounded and reg.vertices.shape[0] >= 3
    cone = wrench_cone(scene, "arr")
    B = np.array([wrench_at(scene, (0.0, 0.0), 0.0), wrench_at(scene, (0.0, 0.0),
                                                                 math.pi / 2)]).T
    lo, hi = reg.vertices.min(axis=0), reg.vertices.max(axis=0)
    span = hi - lo
    rng = np.random.default_rng(7)
    n_in = 0
    for f in lo - span + rng.uniform(size=(600, 2)) * 3 * span:
        g = o + B @ f
        if abs(cone.margin(g)) < 1e-6:
            continue
        truth = cone.contains(g)
        assert reg.contains(f) == truth, f
        n_in += truth
    assert n_in > 20
    for v in reg.vertices:
        assert cone.contains(o + B @ v, tol=1e-7)


def test_force_region_with_an_equality_frictionless_disc():
    """Frictionless rolling on the disc of test_centre_of_percussion: the cone is
    {I f_x + m R tau = 0, f_y <= 0} (m = 1, I = 0.5, R = 1). A force f at (0.5, 0) with
    the offset o = (0.2, -0.3, 0.1) gives total force o_f + f and moment o_tau + 0.5 f_y:
    0.5 (0.2 + f_x) + 0.1 + 0.5 f_y = 0 and f_y - 0.3 <= 0, the ray from (-0.7, 0.3)
    along (1, -1)."""
    scene = _disc(0.0, [[0.0, -1.0]])
    o = (0.2, -0.3, 0.1)
    (reg,) = force_region(scene, "n", point=(0.5, 0.0), offset=o)
    assert reg.A_eq.shape[0] == 1 and not reg.bounded
    assert reg.vertices == pytest.approx(np.array([[-0.7, 0.3]]), abs=1e-12)
    (ray,) = reg.rays
    assert ray / np.linalg.norm(ray) == pytest.approx(np.array([1, -1]) / math.sqrt(2))
    cone = wrench_cone(scene, "n")
    B = np.array([wrench_at(scene, (0.5, 0.0), 0.0), wrench_at(scene, (0.5, 0.0),
                                                                 math.pi / 2)]).T
    for t, off, truth in [(0.0, 0.0, True), (1.0, 0.0, True), (25.0, 0.0, True),
                          (-0.5, 0.0, False), (1.0, 1e-3, False), (1.0, -1e-3, False)]:
        f = np.array([-0.7 + t + off, 0.3 - t])
        assert reg.contains(f) == truth == cone.contains(np.asarray(o) + B @ f), (t, off)


# --- sweeps -------------------------------------------------------------------------------
def test_sweep_equals_per_pose_calls_and_stops_on_contact():
    scene = load_scene(PAWL)
    poses = [[0.1 + 0.001 * k, 0.2, 0.0] for k in range(5)]  # the last touches fixel 1
    res = sweep(scene, poses, "arr", point=(0.0075, 0.035))
    assert res.stop == 4 and "fixel 1 is in contact" in res.stop_reason
    for k in range(4):
        single = force_directions(scene.with_pose(*poses[k]), "arr", point=(0.0075, 0.035))
        assert [(iv.lo, iv.hi, iv.best) for iv in res.intervals[k]] == [
            (iv.lo, iv.hi, iv.best) for iv in single]
    assert res.intervals[4] is None
    for k in range(360):  # the common intervals are the intersection
        phi = -math.pi + 2 * math.pi * (k + 0.5) / 360
        if near_endpoint(phi, [iv for ivs in res.intervals[:4] for iv in ivs] + list(
                res.common), 1e-9):
            continue
        assert inside(phi, res.common) == all(inside(phi, ivs) for ivs in res.intervals[:4])
    assert res.after and all(m.mode[0] != "a" for m in res.after)


@pytest.mark.slow
@pytest.mark.parametrize("exclusive", [False, True])
def test_sweep_of_a_turning_disc(exclusive):
    """A disc with an off-centre com turning in place on two pins (the contacts stay, the
    com moves, so the answer changes from pose to pose): every pose's intervals equal an
    independent force_directions call at that pose, and common is their intersection."""
    scene = scene_from_dict({
        "workpiece": {"mass": 1.0, "inertia": 0.4, "com": [0.3, 0.1],
                      "shape": {"type": "disc", "radius": 1.0}},
        "friction": 0.4, "fixels": [[-0.6, -0.8], [0.6, -0.8]]})
    poses = [(0.0, 0.0, th) for th in np.linspace(0.0, 1.2, 5)]
    res = sweep(scene, poses, "nn", exclusive=exclusive)
    assert res.stop is None
    per = []
    for k, pose in enumerate(poses):
        single = force_directions(scene.with_pose(*pose), "nn", exclusive=exclusive)
        assert single
        assert [(iv.lo, iv.hi, iv.best) for iv in res.intervals[k]] == [
            (iv.lo, iv.hi, iv.best) for iv in single]
        per.append(single)
    assert len({tuple((iv.lo, iv.hi) for iv in p) for p in per}) == len(poses)  # all differ
    n_common = 0
    for k in range(720):
        phi = -math.pi + 2 * math.pi * (k + 0.5) / 720
        if near_endpoint(phi, [iv for p in per for iv in p] + list(res.common), 1e-9):
            continue
        assert inside(phi, res.common) == all(inside(phi, p) for p in per)
        n_common += inside(phi, res.common)
    assert n_common > 0


# --- tray tilt -------------------------------------------------------------------------
def _tray_gravity(m, alpha, axis):
    """Gravity (N) on mass m seen in the frame of a tray rotated by alpha about the
    horizontal axis (cos axis, sin axis, 0), Rodrigues' formula: its in-plane (x, y)
    part."""
    k = np.array([math.cos(axis), math.sin(axis), 0.0])
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R = np.eye(3) + math.sin(alpha) * K + (1 - math.cos(alpha)) * K @ K
    return (R.T @ np.array([0.0, 0.0, -m * STANDARD_GRAVITY]))[:2]


@pytest.mark.parametrize("alpha, axis", [(0.1, 0.3), (0.5, -2.0), (math.pi / 2, 1.0)])
def test_tilt_gravity_force_matches_a_rotated_tray(alpha, axis):
    """The in-plane part of gravity in the tilted tray's frame is m g sin(alpha) along
    psi = axis - pi/2."""
    fx, fy = tilt_gravity_force(0.05, alpha, axis - math.pi / 2)
    assert (fx, fy) == pytest.approx(tuple(_tray_gravity(0.05, alpha, axis)), abs=1e-12)


def test_tilt_directions_are_the_tilts_that_slide_the_pawl():
    """For tilt axes all round, the 3-D gravity vector rotated into the tray and projected
    on its plane, applied at the com, is in the cone of arr (Cone.contains, not
    force_directions) exactly when tilt_directions says the axis (and its downhill
    direction) gives arr."""
    scene = load_scene(PAWL)
    cone = wrench_cone(scene, "arr")
    (t,) = tilt_directions(force_directions(scene, "arr"))
    m = scene.workpiece.mass
    n_in = 0
    for alpha in (0.05, 0.6):
        for k in range(360):
            axis = -math.pi + 2 * math.pi * (k + 0.5) / 360
            fx, fy = _tray_gravity(m, alpha, axis)
            if abs(cone.margin((fx, fy, 0.0))) < 1e-6:
                continue
            truth = cone.contains((fx, fy, 0.0))
            d = (axis - t.axis_lo) % (2 * math.pi)
            assert (d <= t.axis_hi - t.axis_lo) == truth, (alpha, math.degrees(axis))
            d = (axis - math.pi / 2 - t.downhill_lo) % (2 * math.pi)
            assert (d <= t.downhill_hi - t.downhill_lo) == truth
            n_in += truth
    assert 0 < n_in < 720


@pytest.mark.slow
@pytest.mark.parametrize("ratio", [1e-3, 1e6])
def test_exclusive_directions_and_classification_agree_across_the_verified_range(ratio):
    """At both edges of VERIFIED_INERTIA_RATIO, every direction farther than
    AGREEMENT_ANGLE_RAD inside an exclusive interval of the pawl is classified as that
    mode alone; at 1e-8 (outside, accepted with a warning) a direction 1e-2 rad inside an
    edge is also classified as a neighbouring mode, so the check can fail. Exact arithmetic
    decides each interval's midpoint, as an independent referee (the LP, in SI units, is
    not: its slack at the pawl's midpoints shrinks as 1 / ratio, to 5e-10 at 1e8)."""
    import warnings

    from wrenchcone_ros.core import consistent_modes, load_scene
    from wrenchcone_ros.core.directions import force_basis
    from wrenchcone_ros.core.modes import enumerate_modes
    from wrenchcone_ros.core.geometry import UnverifiedRangeWarning
    from wrenchcone_ros.core.tolerances import AGREEMENT_ANGLE_RAD, VERIFIED_INERTIA_RATIO

    assert ratio in VERIFIED_INERTIA_RATIO

    def disagreements(k: float, depth: float) -> list:
        data = load_scene(Path(__file__).resolve().parents[2] / "examples"
                          / "pawl_polygon.yaml").to_dict()
        L = load_scene(data).length_scale
        data["workpiece"]["inertia"] = k * data["workpiece"]["mass"] * L * L
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnverifiedRangeWarning)
            scene = load_scene(data)
        B = np.asarray(force_basis(scene, None), dtype=float)
        bad, probed = [], 0
        for mode in enumerate_modes(scene.in_contact):
            for iv in force_directions(scene, mode, exclusive=True):
                if iv.hi - iv.lo <= 2 * depth:
                    continue
                for phi in (iv.lo + depth, iv.hi - depth, (iv.lo + iv.hi) / 2):
                    g = B @ np.array([math.cos(phi), math.sin(phi)])
                    probed += 1
                    got = [m.mode for m in consistent_modes(scene, g)]
                    if got != [mode]:
                        bad.append((mode, phi, got))
                    elif phi == (iv.lo + iv.hi) / 2:
                        assert wrench_cone(scene, mode, exact=True).contains(g)
        assert probed >= 15
        return bad

    assert disagreements(ratio, AGREEMENT_ANGLE_RAD) == []
    assert disagreements(1e-8, 1e-2), "the probe no longer finds the known ambiguity at 1e-8"
