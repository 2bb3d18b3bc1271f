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

import numpy as np
import pytest
from scipy.optimize import linprog

from strategies import random_mode, random_scene
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
from wrenchcone_ros.core.directions import STANDARD_GRAVITY
from wrenchcone_ros.core.lp_check import lp_consistent, lp_mode_feasible
from wrenchcone_ros.core.modes import expand_mode
from wrenchcone_ros.core.scene import scene_from_dict

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


@pytest.mark.parametrize("seed", range(200, 208))
def test_float_endpoints_agree_with_exact_ones(seed):
    scene, mode, point, exclusive, _ = _case(seed)
    if exclusive and scene.n_fixels > 2:
        exclusive = False  # exact cones of every mode: keep the test fast
    fl = force_directions(scene, mode, point=point, exclusive=exclusive)
    ex = force_directions(scene, mode, point=point, exclusive=exclusive, exact=True)
    assert len(fl) == len(ex)
    for a, b in zip(fl, ex):
        assert abs(a.lo - b.lo) < 1e-7 and abs(a.hi - b.hi) < 1e-7
        if not b.whole_circle:
            assert all(isinstance(x, Fraction) for x in b.lo_direction + b.hi_direction)
            assert math.atan2(*map(float, b.lo_direction[::-1])) == pytest.approx(
                b.lo if b.lo > -math.pi else math.pi, abs=1e-15) or b.lo == -math.pi


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


@pytest.mark.parametrize("seed", [500, 501])
def test_sweep_on_random_scenes(seed):
    rng = np.random.default_rng(seed)
    scene, mode, point, exclusive, _ = _case(seed)
    poses = [scene.pose] + [tuple(np.asarray(scene.pose) + rng.normal(size=3) * 1e-12)]
    res = sweep(scene, poses, mode, point=point, exclusive=exclusive)
    single = force_directions(scene, mode, point=point, exclusive=exclusive)
    if not single:
        assert res.stop == 0
    else:
        assert [iv.lo for iv in res.intervals[0]] == [iv.lo for iv in single]


# --- tray tilt -------------------------------------------------------------------------
@pytest.mark.parametrize("alpha, axis", [(0.1, 0.3), (0.5, -2.0), (math.pi / 2, 1.0)])
def test_tilt_convention_matches_a_rotated_tray(alpha, axis):
    """Rotate the tray by alpha about the horizontal axis (cos k, sin k, 0): gravity seen
    in the tray frame has the in-plane part m g sin(alpha) along psi = k - pi/2."""
    k = np.array([math.cos(axis), math.sin(axis), 0.0])
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R = np.eye(3) + math.sin(alpha) * K + (1 - math.cos(alpha)) * K @ K  # Rodrigues
    m = 0.05
    g_tray = R.T @ np.array([0.0, 0.0, -m * STANDARD_GRAVITY])
    fx, fy = tilt_gravity_force(m, alpha, axis - math.pi / 2)
    assert (fx, fy) == pytest.approx(tuple(g_tray[:2]), abs=1e-12)
    ivs = force_directions(load_scene(PAWL), "arr")
    (t,) = tilt_directions(ivs)
    assert (t.downhill_lo, t.downhill_hi) == (ivs[0].lo, ivs[0].hi)
    assert t.axis_lo == pytest.approx(ivs[0].lo + math.pi / 2)
