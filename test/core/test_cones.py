# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Cone representations: special cones, canonical form, contains() and margin()."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wrenchcone_ros.core import default_scene, wrench_cone
from wrenchcone_ros.core.cones import cone_from_hrep, cone_from_vrep

KW = {"mode": "test", "length_scale": 1.0, "method": "test"}


@pytest.mark.parametrize("exact", [False, True])
def test_all_of_R3(exact):
    c = cone_from_hrep([], [], exact=exact, **KW)
    assert c.F.shape == (0, 3) and c.equalities.shape == (0, 3) and c.G.shape == (0, 3)
    assert np.allclose(c.lineality @ c.lineality.T, np.eye(3))
    assert c.contains((1, 2, 3)) and c.margin((1, 2, 3)) == 1.0


@pytest.mark.parametrize("exact", [False, True])
def test_zero_cone(exact):
    c = cone_from_vrep([], [], exact=exact, **KW)
    assert c.F.shape == (0, 3) and c.G.shape == (0, 3) and c.lineality.shape == (0, 3)
    assert np.allclose(c.equalities @ c.equalities.T, np.eye(3))
    assert not c.contains((1, 0, 0)) and c.contains((0, 0, 0))
    assert c.margin((1, 0, 0)) == pytest.approx(-1.0)


@pytest.mark.parametrize("exact", [False, True])
def test_half_space(exact):
    c = cone_from_hrep([[0, 0, 2]], [], exact=exact, **KW)  # z <= 0
    assert np.allclose(c.F, [[0, 0, 1]])
    assert np.allclose(c.G, [[0, 0, -1]]) and c.lineality.shape == (2, 3)
    assert c.margin((0, 0, -5)) == pytest.approx(1.0)
    assert c.margin((1, 0, 1)) == pytest.approx(-np.sqrt(0.5))


@pytest.mark.parametrize("exact", [False, True])
def test_redundant_and_implicit_equalities_are_removed(exact):
    # x <= 0, x >= 0 (implicit equality x = 0), y <= 0 twice, a redundant x + y <= 0
    c = cone_from_hrep([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, 2, 0], [1, 1, 0]], [],
                       exact=exact, **KW)
    assert np.allclose(np.abs(c.equalities), [[1, 0, 0]])
    assert np.allclose(c.F, [[0, 1, 0]])
    assert np.allclose(c.G, [[0, -1, 0]]) and np.allclose(np.abs(c.lineality), [[0, 0, 1]])
    assert not c.full_dimensional and c.margin((0, -1, 0)) == 0.0


def test_ray_and_wedge():
    ray = cone_from_vrep([[1, 1, 0]], [], exact=False, **KW)
    assert ray.equalities.shape == (2, 3) and ray.F.shape == (1, 3)
    assert ray.contains((2, 2, 0)) and not ray.contains((-2, -2, 0))
    wedge = cone_from_vrep([[1, 0, 0], [0, 1, 0]], [], exact=False, **KW)
    assert wedge.equalities.shape == (1, 3) and wedge.F.shape == (2, 3)


def test_margin_is_scale_invariant_and_signed():
    cone = wrench_cone(default_scene(), "na")
    g_in = np.array([1.0, -1.0, -1.0]) + np.array([-0.2, -1.0, -0.2])
    m = cone.margin(g_in)
    assert m > 0 and cone.margin(1e6 * g_in) == pytest.approx(m)
    assert cone.margin(-g_in) < 0
    assert cone.margin((0, 0, 0)) == 0.0 and cone.contains((0, 0, 0))


def test_margin_uses_the_nondimensional_metric():
    """Changing units (m -> mm) scales torques by 1e3 and L by 1e3: margin unchanged."""
    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.scene_yaml import PAPER_DISC

    mm = {**PAPER_DISC, "workpiece": {**PAPER_DISC["workpiece"], "inertia": 1e6,
                                      "shape": {"type": "disc", "radius": 1000.0}},
          "fixels": [[0.0, -1000.0], [1001.0, 0.0]], "contact_tolerance": 1e-6}
    a, b = wrench_cone(default_scene(), "na"), wrench_cone(load_scene(mm), "na")
    g = np.array([0.3, -1.0, -0.1])
    assert b.margin(g * [1, 1, 1000]) == pytest.approx(a.margin(g), abs=1e-12)


def test_non_finite_wrench_is_an_error():
    cone = wrench_cone(default_scene(), "na")
    with pytest.raises(ValueError, match="finite"):
        cone.contains((np.nan, 0, 0))


vec = st.lists(st.floats(-1, 1, allow_nan=False), min_size=3, max_size=3)


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(st.lists(vec, min_size=1, max_size=6), vec)
def test_margin_matches_membership_and_distance(rays, g):
    """Property: sign of margin agrees with contains(); outside, -margin is the distance
    of the unit direction to the cone (checked against points of the cone)."""
    rays = [r for r in rays if np.linalg.norm(r) > 1e-3]
    if not rays or np.linalg.norm(g) < 1e-3:
        return
    c = cone_from_vrep(rays, [], exact=False, **KW)
    m = c.margin(g)
    if m > 1e-8:
        assert c.contains(g)
    if m < -1e-8:
        assert not c.contains(g)
        u = np.asarray(g) / np.linalg.norm(g)
        # no generator combination is closer than the reported distance
        for r in c.G:
            for t in np.linspace(0, 2, 9):
                assert np.linalg.norm(u - t * r) >= -m - 1e-9
    for r in c.G:  # every generator is in the cone, on its boundary when pointed
        assert c.contains(r, tol=1e-9)
        if c.lineality.shape[0] == 0:
            assert abs(c.margin(r)) < 1e-9


def test_contains_many_and_margin_many_equal_the_scalar_calls():
    """Vectorised queries are elementwise identical to contains()/margin() on every kind
    of cone (feasible, infeasible, with equalities and lines) and on awkward wrenches
    (zero, on a ray, huge, tiny)."""
    from helpers.strategies import random_scene, random_wrench

    from wrenchcone_ros.core import enumerate_modes, load_scene, wrench_cones

    rng = np.random.default_rng(20261123)
    kinds = set()
    for _ in range(12):
        s = load_scene(random_scene(rng, n_fixels=int(rng.integers(1, 4))).data)
        for cone in wrench_cones(s, list(enumerate_modes(s.in_contact))):
            kinds.add((cone.feasible, cone.E_hat.shape[0], cone.L_hat.shape[0]))
            G = [random_wrench(rng, s.length_scale) for _ in range(30)]
            G += [np.zeros(3), np.array([1e150, 0.0, 0.0]), np.array([0.0, 1e-300, 0.0])]
            G += list(cone.G) + [-r for r in cone.lineality]
            G = np.array(G)
            inside, margin = cone.check_many(G)
            assert np.array_equal(cone.contains_many(G), inside)
            assert np.array_equal(cone.margin_many(G), margin)
            assert inside.tolist() == [cone.contains(g) for g in G]
            assert margin.tolist() == [cone.margin(g) for g in G]
            loose = cone.contains_many(G, tol=1e-3)
            assert loose.tolist() == [cone.contains(g, 1e-3) for g in G]
    assert len(kinds) >= 5  # pointed, infeasible, lower-dimensional, with lines, ...


def test_many_queries_refuse_bad_input():
    c = cone_from_vrep([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [], mode="x", length_scale=1.0,
                       method="t", exact=False)
    with pytest.raises(ValueError, match="must be finite"):
        c.contains_many([[1.0, 0.0, 0.0], [np.nan, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        c.margin_many([[1.0, 0.0]])
    assert c.contains_many([1.0, 1.0, 1.0]).tolist() == [True]  # one wrench as (3,)
    assert c.contains_many(np.zeros((0, 3))).shape == (0,)


def test_margin_on_the_boundary_is_plus_zero():
    """A wrench on the cone's boundary (a generator of the paper's cone) had margin -0.0,
    printed "margin -0" by the CLI: the margin there is +0.0, in check, margin and
    margin_many alike."""
    import math

    cone = wrench_cone(default_scene(), "na")
    for g in cone.G:
        assert cone.contains(g)
        m = cone.margin(g)
        assert m == 0.0 and math.copysign(1.0, m) == 1.0, m
        mm = cone.margin_many(np.array([g]))
        assert mm[0] == 0.0 and math.copysign(1.0, mm[0]) == 1.0, mm


def test_margin_geometries_of_many_cones_are_each_cones_own():
    """The lane's one-pass geometry of a snapshot's cones is, cone by cone, exactly the
    geometry of each cone alone, for every kind: R^3, {0}, a half-space (lineality), a
    cone with an equality, a ray, a wedge and the modes of the default scene."""
    from wrenchcone_ros.core.cones import margin_geometries, margin_geometry
    from wrenchcone_ros.core.tolerances import RANK_TOLERANCE as tol

    cones = [cone_from_hrep([], [], exact=False, **KW), cone_from_vrep([], [], exact=False, **KW),
             cone_from_hrep([[0, 0, 2]], [], exact=False, **KW),
             cone_from_hrep([[1, 0, 0], [-1, 0, 0], [0, 1, 0]], [], exact=False, **KW),
             cone_from_vrep([[1, 1, 0]], [], exact=False, **KW),
             cone_from_vrep([[1, 0, 0], [0, 1, 0]], [], exact=False, **KW)]
    scene = default_scene()
    cones += [c for c in (wrench_cone(scene, m) for m in ("na", "ns", "ra", "la", "ss"))
              if c.feasible]
    hats = [(c.F_hat, c.E_hat, c.G_hat, c.L_hat) for c in cones]
    together = margin_geometries(hats)
    assert len(together) == len(cones)
    for hat, (rays, planes) in zip(hats, together):
        # the definition, written out: unit rays orthogonal to the lineality space;
        # I - f f^T per facet of a full-dimensional cone, else I - E^T E
        F, E, G, L = hat
        r = G - G @ (L.T @ L) if L.shape[0] else G
        n = np.linalg.norm(r, axis=1)
        assert np.allclose(rays, r[n > tol] / n[n > tol, None], atol=1e-15)
        want = (np.eye(3) - E.T @ E)[None] if E.shape[0] else \
            np.eye(3) - F[:, :, None] * F[:, None, :]
        assert np.allclose(planes, want, atol=1e-15)
        alone = margin_geometry(*hat)
        assert np.array_equal(alone[0], rays) and np.array_equal(alone[1], planes)
    assert margin_geometries([]) == []
