# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Robust cones for friction intervals (core/robust.py), checked against independent truth:

* zero-width intervals give today's cones (every scene family of test/helpers/families.py);
* "all" equals the intersection of the cones of densely sampled models (every vertex of
  the box and 50 interior samples, each computed by wrench_cone on its own scene);
* "any" equals what a linear programme over the box decides (nu_i = lambda_i mu_i makes
  "some mu in the box" linear; written here from the contact frames, not from the core's
  matrices; strict conditions as lp_check does: the mode's feasibility LP, then the
  closure);
* float against exact (cddlib GMP);
* properties (hypothesis): a wrench in "all" is consistent at every sampled model, one
  outside "any" at none.

Directions within BAND_ROBUST (dimensionless, on the unit nondimensional direction) of a
boundary may go either way (rounding of two different computations of the same facet).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog

from helpers.families import FAMILIES, exact_contains, sample_directions, si_wrench
from helpers.paper_example import PAPER_G, same_rays
from helpers.strategies import random_scene
from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.core.engines import kernel_module, plan_code, pose_arrays
from wrenchcone_ros.core.lp_check import contact_jacobian, lp_consistent, lp_mode_feasible
from wrenchcone_ros.core.modes import ModeError, Sign, enumerate_modes, parse_mode
from wrenchcone_ros.core.robust import (
    _all_blocks,
    _vertex_mus,
    block_cones,
    intersect_rows,
    robust_cone,
    robust_cones,
)
from wrenchcone_ros.core.geometry import Fixel
from wrenchcone_ros.core.uncertainty import NOMINAL, Uncertainty

#: Dimensionless: directions whose margin in the robust cone (or, for the sampled
#: intersection, in any sampled cone) is below this in absolute value are not compared.
BAND_ROBUST = 1e-7


def with_friction(scene, mus):
    return dataclasses.replace(scene, fixels=tuple(
        Fixel(f.position, f.radius, float(mu)) for f, mu in zip(scene.fixels, mus)))


def same_cone(a, b, atol=1e-12):
    assert a.feasible == b.feasible
    assert a.F_hat.shape == b.F_hat.shape and a.E_hat.shape == b.E_hat.shape
    np.testing.assert_allclose(a.F_hat, b.F_hat, atol=atol)
    np.testing.assert_allclose(a.E_hat, b.E_hat, atol=atol)


# --- zero width: today's answers -----------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("family", sorted(FAMILIES))
@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_zero_width_is_the_nominal_cone(family, engine):
    rng = np.random.default_rng([20, sorted(FAMILIES).index(family)])
    cases = [c for c in FAMILIES[family](rng, 2) if not c.rejected]
    assert cases
    for case in cases:
        scene = load_scene(case.data)
        U = Uncertainty(friction=[(scene.mu(i), scene.mu(i)) for i in range(scene.n_fixels)])
        for mode in case.modes:
            ref = wrench_cone(scene, mode, engine=engine)
            for q in ("all", "any"):
                rc = robust_cone(scene, mode, U, q, engine=engine)
                assert str(rc.guarantee) == "exact"
                same_cone(rc.cone, ref)


def test_zero_width_exact_is_the_exact_cone():
    rng = np.random.default_rng(201)
    for case in FAMILIES["paper"](rng, 1) + FAMILIES["random"](rng, 2):
        scene = load_scene(case.data)
        U = Uncertainty(friction=[(scene.mu(i), scene.mu(i)) for i in range(scene.n_fixels)])
        for mode in case.modes:
            ref = wrench_cone(scene, mode, exact=True)
            rc = robust_cone(scene, mode, U, "all", exact=True).cone
            assert rc.feasible == ref.feasible
            if ref.feasible:
                assert set(rc.exact_rep.F) == set(ref.exact_rep.F)


@pytest.mark.parametrize("exact", [False, True])
def test_no_friction_given_means_the_scene_values(exact):
    """An uncertainty that gives no parameter is the scene's own model: on the paper's
    disc (mu = 0.2) both robust sets of mode na are the paper's cone, whose generators
    the paper derives by hand (Eq. 5: (1, 0, -1), (-0.2, -1, -0.2), (0.2, -1, 0.2)); a
    friction of 0.3 instead gives other generators (the reference tells them apart)."""
    scene = load_scene("examples/paper_disc.yaml")
    for U in (Uncertainty(), Uncertainty(epsilon=0.1, seed=7), NOMINAL):
        for q in ("all", "any"):
            rc = robust_cone(scene, "na", U, q, exact=exact)
            assert str(rc.guarantee) == "exact" and len(rc.pieces) == 1
            assert same_rays(np.array(rc.cone.G, dtype=float), PAPER_G)
    other = robust_cone(scene, "na", Uncertainty(friction=(0.3, 0.3)), exact=exact)
    assert not same_rays(np.array(other.cone.G, dtype=float), PAPER_G)


def test_no_friction_given_agrees_with_the_lp_on_the_pawl():
    """The pawl's mode arr with no parameter given, against the LP of core/lp_check.py
    (Newton-Euler and Coulomb friction written out, no cone) on wrenches around the
    cone, at least 1e-4 rad off its faces."""
    scene = load_scene("examples/pawl_polygon.yaml")
    rc = robust_cone(scene, "arr", Uncertainty())
    feas = lp_mode_feasible(scene, "arr")
    rng = np.random.default_rng(98)
    checked = 0
    for u in sample_directions(rng, rc.cone, 40, 40, delta_range=(1e-4, 1e-2)):
        g = si_wrench(u, scene.length_scale)
        if abs(rc.margin(g)) < BAND_ROBUST:
            continue
        lp = lp_consistent(scene, "arr", g, feasibility=feas)
        assert lp.decided and lp.consistent == rc.contains(g), g
        checked += 1
    assert checked >= 40


# --- random scenes, modes and boxes ------------------------------------------------------------
def random_case(rng, n_uncertain=None):
    """A scene with 1-4 fixels in contact, a feasible mode and a friction box in which
    1-4 fixels are uncertain (every letter appears over the draws)."""
    for _ in range(200):
        k = int(rng.integers(1, 5)) if n_uncertain is None else n_uncertain
        gen = random_scene(rng, n_fixels=int(rng.integers(k, 5)), n_contact=k,
                           per_fixel_friction=False)
        try:
            scene = load_scene(gen.data)
        except Exception:
            continue
        modes = [m for m in enumerate_modes(scene.in_contact)
                 if sum(ch in "lrn" for ch in m) >= 1]
        rng.shuffle(modes)
        for mode in modes[:6]:
            if not wrench_cone(scene, mode).feasible:
                continue
            box = []
            for i in range(scene.n_fixels):
                lo = float(rng.choice([0.0, rng.uniform(0, 0.5)]))
                hi = lo + float(rng.uniform(0.05, 0.8))
                box.append((lo, hi) if scene.in_contact[i] else None)
            return scene, mode, Uncertainty(friction=box)
    raise AssertionError("no case found")


def box_samples(scene, U, mode, rng, interior=50):
    """Every vertex of the box of the fixels in contact, plus ``interior`` uniform samples."""
    iv = U.friction_intervals(scene)
    choices = [(lo, hi) if scene.in_contact[i] and lo < hi else (lo,)
               for i, (lo, hi) in enumerate(iv)]
    import itertools

    out = [list(v) for v in itertools.product(*choices)]
    lo = np.array([a for a, _ in iv])
    hi = np.array([b for _, b in iv])
    out += [list(rng.uniform(lo, hi)) for _ in range(interior)]
    return out


def test_every_letter_and_1_to_4_uncertain_fixels_are_drawn():
    rng = np.random.default_rng(7)
    letters, counts = set(), set()
    for _ in range(40):
        scene, mode, U = random_case(rng)
        letters |= set(mode)
        counts.add(sum(scene.in_contact))
    assert set("lrns") <= letters and counts == {1, 2, 3, 4}


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(12))
def test_all_is_the_intersection_of_densely_sampled_models(seed):
    rng = np.random.default_rng([2020, seed])
    scene, mode, U = random_case(rng, n_uncertain=seed % 4 + 1)
    rc = robust_cone(scene, mode, U, "all").cone
    cones = [wrench_cone(with_friction(scene, mus), mode) for mus in box_samples(scene, U, mode,
                                                                                   rng)]
    target = rc if rc.feasible else rc.closure
    U_dirs = sample_directions(rng, target, 300, 300)
    L = scene.length_scale
    compared = 0
    for u in U_dirs:
        g = si_wrench(u, L)
        mine = rc.contains(g)
        margins = [c.margin(g) for c in cones]
        if abs(rc.margin(g)) < BAND_ROBUST or min(abs(m) for m in margins) < BAND_ROBUST:
            continue
        assert mine == all(c.contains(g) for c in cones), (mode, u)
        compared += 1
    assert compared > 300


@pytest.mark.parametrize("seed", range(16))
def test_compiled_all_equals_the_reference_path(seed):
    """The compiled "all" cone (kernel.planar_all: one call for every friction vertex and
    their intersection) equals the reference path (each vertex's cone by the numpy
    planar method, then the stacked facets converted once), and the compiled path is the
    one taken (it did not decline the case)."""
    km = kernel_module()
    if km is None:
        pytest.skip("no compiled engine (numba missing)")
    rng = np.random.default_rng([2121, seed])
    scene, mode, U = random_case(rng, n_uncertain=seed % 4 + 1)
    A, kappa, _ = pose_arrays(scene)
    mus = np.array(_vertex_mus(mode, U.friction_intervals(scene)), dtype=float)
    status, feasible, *_ = km.planar_all(A, float(kappa), mus, plan_code(mode, scene.in_contact))
    assert status == 0
    same_cone(robust_cone(scene, mode, U, "all", engine="kernel").cone,
              robust_cone(scene, mode, U, "all", engine="numpy").cone, atol=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("quantifier", ["all", "any"])
def test_compiled_equals_the_reference_on_every_mode(seed, quantifier):
    """Every mode of a random scene (impossible ones too: their closures), the compiled
    batched paths (kernel.planar_all per mode, all modes' "any" cones in one
    planar_batch call) against the reference (numpy planar method, cone by cone)."""
    rng = np.random.default_rng([2323, seed])
    scene, _, U = random_case(rng, n_uncertain=seed % 4 + 1)
    modes = list(enumerate_modes(scene.in_contact))
    fast = robust_cones(scene, modes, U, quantifier, engine="kernel")
    ref = robust_cones(scene, modes, U, quantifier, engine="numpy")
    for a, b in zip(fast, ref):
        assert a.mode == b.mode and a.feasible == b.feasible, a.mode
        same_set(a.cone, b.cone)
        if not a.feasible:
            same_set(a.cone.closure, b.cone.closure)


def same_set(a, b, atol=1e-9):
    """The same cone as a set: the same facets (canonical: unit, sorted) and the same
    span of equalities (a basis of it is not unique: compare the projectors)."""
    np.testing.assert_allclose(a.F_hat, b.F_hat, atol=atol)

    def projector(E):
        return E.T @ np.linalg.pinv(E @ E.T) @ E if E.shape[0] else np.zeros((3, 3))

    np.testing.assert_allclose(projector(a.E_hat), projector(b.E_hat), atol=atol)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_intersection_of_many_rows_is_the_set_they_define(seed):
    """intersect_rows (many rows, as the scenario approach stacks them: cuts added to a
    small cone) against the definition {g : F g <= 0, E g = 0}, evaluated directly on
    random and near-boundary directions; the cone's own generators satisfy every row."""
    rng = np.random.default_rng([88, seed])
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    spread = (0.3, 0.7, 0.95)[seed % 3]
    F = -(axis + spread * sample_sphere(rng, 40 * (seed % 5 + 2)))
    E = np.zeros((0, 3))
    if seed % 2:  # a plane through the axis, repeated with rounding-level noise
        e = np.cross(axis, rng.normal(size=3))
        E = e + 1e-15 * rng.normal(size=(30, 3))
    cone = intersect_rows(F, E, "x", 1.0)
    FE = np.vstack([F, E, -E]) / np.linalg.norm(np.vstack([F, E, -E]), axis=1, keepdims=True)
    for G in (cone.G_hat, cone.L_hat, -cone.L_hat):
        if G.shape[0]:
            assert (FE @ (G / np.linalg.norm(G, axis=1, keepdims=True)).T).max() <= 1e-9
    if E.shape[0]:  # directions in the plane
        b1 = axis - (axis @ E[0]) * E[0] / (E[0] @ E[0])
        b1 /= np.linalg.norm(b1)
        b2 = np.cross(E[0], b1)
        b2 /= np.linalg.norm(b2)
        t = rng.uniform(0, 2 * np.pi, 2000)
        U = np.outer(np.cos(t), b1) + np.outer(np.sin(t), b2)
    else:
        U = sample_directions(rng, cone, 1000, 1000)
    compared = 0
    for u in U:
        truth = (F @ u / np.linalg.norm(F, axis=1)).max()
        if abs(truth) < BAND_ROBUST or abs(cone.margin(u)) < BAND_ROBUST:
            continue
        assert cone.contains(u) == (truth <= 0), (u, truth)
        compared += 1
    assert compared > 500


def sample_sphere(rng, n):
    u = rng.normal(size=(n, 3))
    return u / np.linalg.norm(u, axis=1, keepdims=True)


def test_cones_of_many_modes_hold_only_their_own_rows():
    """Robust cones of every mode of 5 sliding-capable fixels (1,024 modes, 32 friction
    vertices each) keep only their own small arrays: no cone holds a view into a kernel
    batch's output (which once kept ~10 MB alive per mode)."""
    data = {"workpiece": {"mass": 1.0, "inertia": 0.4, "com": [0.0, 0.0], "pose": [0, 0, 0],
                          "shape": {"type": "polygon",
                                    "vertices": [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]}},
            "friction": 0.3,
            "fixels": [{"position": [-1.0 + 2.0 * (i + 0.5) / 5, -0.5]} for i in range(5)]}
    scene = load_scene(data)
    modes = list(enumerate_modes(scene.in_contact))
    assert len(modes) == 1024
    U = Uncertainty(friction=(0.2, 0.4))
    assert held_bytes(rc.cone for rc in robust_cones(scene, modes, U, "all")) < 2e6
    # the cones of one mode's 32 vertices, from one kernel call
    A, kappa, _ = pose_arrays(scene)
    blocks = _all_blocks(A, "rrrrr", scene.in_contact, U.friction_intervals(scene))
    vertex = block_cones(blocks, kappa, scene.length_scale, "rrrrr")
    assert len(vertex) == 32 and held_bytes(vertex) < 2e5


def held_bytes(cones) -> int:
    """Bytes the cones' arrays keep alive (a view keeps its whole base)."""
    held = 0
    for c in cones:
        for cone in (c, c.closure) if c.closure is not None else (c,):
            for a in (cone.F_hat, cone.E_hat, cone.G_hat, cone.L_hat):
                held += (a.base if isinstance(a.base, np.ndarray) else a).nbytes
    return held


def lp_any(scene, mode, intervals, g) -> float:
    """Largest slack s of: some mu in the box, accelerations u and forces with
    Newton-Euler for the unit g_hat, the mode's closed acceleration conditions relaxed by
    -s (|u| <= 1 box) and its force rules over the box, written with nu_i = mu_i c_in:
    sliding l: c_it = -nu_i, r: c_it = +nu_i, lo c_in <= nu_i <= hi c_in; rolling:
    |c_it| <= hi c_in. The closed "any" set holds g iff s >= 0 (up to the LP's noise)."""
    in_contact = scene.in_contact
    inters = parse_mode(mode, in_contact)
    n = len(inters)
    L = scene.length_scale
    J = contact_jacobian(scene)
    J[2, :] /= L
    gh = np.array([g[0], g[1], g[2] / L])
    gh /= np.linalg.norm(gh)
    kappa = scene.workpiece.inertia / (scene.workpiece.mass * L * L)
    # variables: u (3), c_n (n), c_t (n), nu (n), s
    nv = 3 + 3 * n + 1
    A_eq, b_eq, A_ub, b_ub = [], [], [], []
    for k in range(3):
        row = np.zeros(nv)
        row[k] = (1.0, 1.0, kappa)[k]
        row[3:3 + n] = -J[k, :n]
        row[3 + n:3 + 2 * n] = -J[k, n:]
        A_eq.append(row)
        b_eq.append(gh[k])
    bounds = [(None, None)] * 3 + [(0, None)] * n + [(None, None)] * n + [(0, None)] * n + [(-1, 1)]

    def acc(row3, sign):
        if sign is Sign.FREE:
            return
        r = np.zeros(nv)
        r[:3] = row3 / np.linalg.norm(row3)
        if sign.closure is Sign.ZERO:
            A_eq.append(r)
            b_eq.append(0.0)
            return
        d = sign.direction  # d r.u >= -s ... we want d r.u + s >= 0 for the closure test
        r2 = -d * r
        A_ub.append(r2)
        b_ub.append(0.0)

    for i, inter in enumerate(inters):
        acc(J[:, i], inter.a_n(in_contact[i]))
        acc(J[:, n + i], inter.a_t)
        cn, ct, nu = 3 + i, 3 + n + i, 3 + 2 * n + i
        lo, hi = intervals[i]
        if not inter.loaded:
            bounds[cn] = bounds[ct] = bounds[nu] = (0, 0)
            continue
        edges = inter.c_t.edges
        if len(edges) == 2:  # rolling: |c_t| <= hi c_n
            for sgn in (1, -1):
                r = np.zeros(nv)
                r[ct], r[cn] = sgn, -hi
                A_ub.append(r)
                b_ub.append(0.0)
            bounds[nu] = (0, 0)
        else:
            r = np.zeros(nv)
            r[ct], r[nu] = 1.0, -edges[0]
            A_eq.append(r)
            b_eq.append(0.0)
            for a, b in ((lo, -1.0), (-hi, 1.0)):  # lo c_n - nu <= 0, nu - hi c_n <= 0
                r = np.zeros(nv)
                r[cn], r[nu] = a, b
                A_ub.append(r)
                b_ub.append(0.0)
    # slack: the Newton-Euler residual allowed up to |e| <= -s, maximise s (s = 0 feasible)
    for k in range(3):
        for sgn in (1, -1):
            r = np.zeros(nv)
            r[:] = sgn * np.array(A_eq[k])
            r[-1] = 1.0
            A_ub.append(r)
            b_ub.append(sgn * b_eq[k])
    A_eq_f, b_eq_f = A_eq[3:], b_eq[3:]
    cost = np.zeros(nv)
    cost[-1] = -1.0
    res = linprog(cost, A_ub=np.array(A_ub), b_ub=np.array(b_ub),
                  A_eq=np.array(A_eq_f) if A_eq_f else None,
                  b_eq=np.array(b_eq_f) if b_eq_f else None, bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return float(res.x[-1])


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_any_is_what_an_lp_over_the_box_decides(seed):
    rng = np.random.default_rng([2021, seed])
    scene, mode, U = random_case(rng, n_uncertain=seed % 4 + 1)
    rc = robust_cone(scene, mode, U, "any").cone
    assert rc.feasible == lp_mode_feasible(scene, mode).consistent
    iv = U.friction_intervals(scene)
    L = scene.length_scale
    compared = 0
    for u in sample_directions(rng, rc, 60, 60, delta_range=(1e-5, 1e-1)):
        g = si_wrench(u, L)
        m = rc.margin(g)
        if abs(m) < 1e-5:
            continue
        s = lp_any(scene, mode, iv, g)
        assert (s >= -1e-9) == (m >= 0), (mode, u, s, m)
        compared += 1
    assert compared > 60


@pytest.mark.parametrize("seed", range(6))
def test_float_agrees_with_exact(seed):
    rng = np.random.default_rng([2022, seed])
    scene, mode, U = random_case(rng, n_uncertain=seed % 4 + 1)
    L = scene.length_scale
    for q in ("all", "any"):
        fl = robust_cone(scene, mode, U, q).cone
        ex = robust_cone(scene, mode, U, q, exact=True).cone
        assert fl.feasible == ex.feasible
        if not ex.feasible:
            continue
        for u in sample_directions(rng, ex, 100, 100):
            if abs(fl.margin(si_wrench(u, L))) < 1e-8:
                continue
            assert fl.contains(si_wrench(u, L)) == exact_contains(ex, u)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_all_holds_at_every_model_and_outside_any_at_none(seed):
    rng = np.random.default_rng(seed)
    scene, mode, U = random_case(rng)
    a, y = robust_cones(scene, [mode], U, "all")[0], robust_cones(scene, [mode], U, "any")[0]
    models = [wrench_cone(with_friction(scene, mus), mode)
              for mus in box_samples(scene, U, mode, rng, interior=20)]
    L = scene.length_scale
    from helpers.strategies import wrench_from_cone

    if a.feasible:
        for _ in range(5):
            g = wrench_from_cone(rng, a.cone, L)
            if g is None or abs(a.margin(g)) < BAND_ROBUST:
                continue
            assert all(c.contains(g) for c in models)
    for u in sample_directions(rng, y.cone if y.feasible else y.cone.closure, 20, 20):
        g = si_wrench(u, L)
        if y.contains(g) or y.margin(g) > -BAND_ROBUST:
            continue
        assert not any(c.contains(g) for c in models)


# --- robust consistent modes (the classifier's path) ---------------------------------------
def test_consistent_modes_certain_and_possible_on_the_pawl():
    scene = load_scene("examples/pawl_polygon.yaml")
    U = Uncertainty(friction=(0.2, 0.4))
    classifier = ModeClassifier(scene, uncertainty=U)
    assert not classifier.pruned
    g = (math.cos(math.radians(-68.71)), math.sin(math.radians(-68.71)), 0.0)
    got = {m.mode: m for m in classifier.consistent_modes(g)}
    # atan(1 / 0.4) = 68.20 deg: with mu = 0.4 the pawl sticks at -68.71 deg
    assert set(got) == {"arr", "snn"}
    assert not got["arr"].certain and not got["snn"].certain
    g = (math.cos(math.radians(-30)), math.sin(math.radians(-30)), 0.0)
    got = classifier.consistent_modes(g)
    assert [(m.mode, m.certain) for m in got] == [("arr", True)]


def test_wildcards_and_bad_inputs_are_refused():
    scene = load_scene("examples/pawl_polygon.yaml")
    U = Uncertainty(friction=(0.2, 0.4))
    with pytest.raises(ModeError, match="concrete"):
        robust_cone(scene, "a**", U)
    with pytest.raises(ValueError, match="quantifier"):
        robust_cone(scene, "arr", U, "some")
    with pytest.raises(ValueError, match="frame"):
        robust_cone(scene, "arr", U, frame="world")
    with pytest.raises(ValueError, match="friction intervals only"):
        robust_cone(scene, "arr", Uncertainty(com_radius=1e-3), exact=True)
