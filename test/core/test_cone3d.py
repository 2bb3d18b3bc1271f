# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_ros.core.cone3d against exact cddlib (Fractions of the same float inputs).

Every random cone is converted by cone3d (float) and by exact cddlib
(``vrep_to_hrep``/``hrep_to_vrep`` with ``exact=True``, then normalised like cones.py).
Agreement means: the same number of facets, rays, equalities and lines; facets and rays
equal up to ``ANGLE`` (pairwise, one-to-one); E and lines spanning the same subspaces.
cone3d may instead raise Cone3Error (its self-check failed: the caller falls back to exact
cddlib); those are counted and must be rare. A result that is returned but disagrees is a
failure (``silent``), always.

Input families (``FAMILIES``, test/helpers/cone3d_cases.py): pointed cones, random directions, rays + lines, small
integer vectors (exact degeneracies: coplanar rays, r and -r, three rays summing to zero,
duplicates) with power-of-two anisotropic scaling (exact), exactly planar sets, exactly
collinear sets, nearly parallel rays (1e-3 .. 1e-9 rad apart) and nearly coplanar rays
(1e-3 .. 1e-9 rad off a plane), float anisotropic scaling (1e-3 .. 1e3 per axis).
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.cone3d_cases import (
    ANGLE,
    FAMILIES,
    _rot_towards,
    _unit,
    agree,
    check_generators,
    check_inequalities,
    exact_from_generators,
    run_family,
    well_formed,
)

from wrenchcone_ros.core.cone3d import Cone3, Cone3Error, from_generators, from_inequalities

#: Cones per family per direction in the test (the benchmark script measures more).
N_RANDOM = 150


def _assert_tally(tally: Counter, n: int) -> None:
    examples = tally.get("examples", [])
    assert tally["silent"] == 0, f"{tally['silent']} silent disagreements, first: {examples[:1]}"
    assert tally["agree"] + tally["cone3error"] == n
    assert tally["cone3error"] <= max(2, n // 100), f"too many Cone3Error: {tally}"


@pytest.mark.slow
@pytest.mark.parametrize("name", list(FAMILIES))
def test_random_generators_agree_with_exact_cdd(name):
    tally = run_family(name, N_RANDOM, 20240601, False)
    _assert_tally(tally, N_RANDOM)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(FAMILIES))
def test_random_inequalities_agree_with_exact_cdd(name):
    tally = run_family(name, N_RANDOM, 20240602, True)
    _assert_tally(tally, N_RANDOM)


# --- hypothesis ---------------------------------------------------------------------------------
_vec = st.lists(st.integers(-4, 4), min_size=3, max_size=3)
_near = st.one_of(st.none(), st.tuples(st.integers(0, 20), st.floats(-9, -3)))


@st.composite
def generator_sets(draw):
    """Small-integer rays and lines (exact degeneracies), power-of-two axis scaling, and
    optionally (after the scaling) one ray turned 1e-9..1e-3 rad away from another."""
    rays = np.array(draw(st.lists(_vec, max_size=8)), dtype=float).reshape(-1, 3)
    lines = np.array(draw(st.lists(_vec, max_size=2)), dtype=float).reshape(-1, 3)
    neg = draw(st.lists(st.integers(0, 7), max_size=3))
    extra = [-rays[i] for i in neg if i < rays.shape[0]]
    if extra:
        rays = np.vstack([rays, extra])
    s = 2.0 ** np.array(draw(st.lists(st.integers(-12, 12), min_size=3, max_size=3)))
    rays, lines = rays * s, lines * s
    # each row scaled by its own power of two (the cone is unchanged, exactly), zero rows
    k = draw(st.lists(st.integers(-300, 300), min_size=rays.shape[0], max_size=rays.shape[0]))
    rays = rays * (2.0 ** np.array(k, dtype=float))[:, None] if rays.shape[0] else rays
    if draw(st.booleans()):
        rays = np.vstack([rays, np.zeros((1, 3))])
    near = draw(_near)
    if near is not None and rays.shape[0]:
        i, lg = near
        r = rays[i % rays.shape[0]]
        if np.any(r):
            rays = np.vstack([rays, _rot_towards(r, np.random.default_rng(i), 10.0 ** lg)])
    return rays, lines


_HYP = settings(max_examples=150, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.slow
@_HYP
@given(generator_sets())
def test_hypothesis_generators(gens):
    tally: Counter = Counter()
    check_generators(*gens, tally)
    assert tally["silent"] == 0, tally.get("examples")


@pytest.mark.slow
@_HYP
@given(generator_sets())
def test_hypothesis_inequalities(gens):
    tally: Counter = Counter()
    check_inequalities(*gens, tally)
    assert tally["silent"] == 0, tally.get("examples")


# --- the special cones --------------------------------------------------------------------------
X, Y, Z = np.eye(3)
SPECIAL = {
    # name: (rays, lines, (#F, #E, #rays, #lines))
    "R3": ([], [X, Y, Z], (0, 0, 0, 3)),
    "R3 from rays": ([X, Y, Z, -X - Y - Z], [], (0, 0, 0, 3)),
    "zero": ([], [], (0, 3, 0, 0)),
    "zero rays": ([[0, 0, 0]], [[0, 0, 0]], (0, 3, 0, 0)),
    "half-space": ([X], [Y, Z], (1, 0, 1, 2)),
    "half-space from rays": ([X, Y, -Y, Z, -Z], [], (1, 0, 1, 2)),
    "half-space, three rays summing to 0": ([Y, Z, -Y - Z, X + Y], [], (1, 0, 1, 2)),
    "ray": ([X + Y], [], (1, 2, 1, 0)),
    "ray, duplicated": ([X + Y, 3 * (X + Y)], [], (1, 2, 1, 0)),
    "line": ([], [X - Z], (0, 2, 0, 1)),
    "line from rays": ([X, -2 * X], [], (0, 2, 0, 1)),
    "2-D wedge": ([X, X + Y, Y], [], (2, 1, 2, 0)),
    "half-plane": ([Y], [X], (1, 1, 1, 1)),
    "half-plane from rays": ([X, -X, Y, X + Y], [], (1, 1, 1, 1)),
    "plane": ([], [X, Y], (0, 1, 0, 2)),
    "plane from rays": ([X, Y, -X - Y], [], (0, 1, 0, 2)),
    "plane from line and rays": ([Y, -Y], [X], (0, 1, 0, 2)),
    "pointed orthant": ([X, Y, Z], [], (3, 0, 3, 0)),
    "pointed square": ([X + Z, Y + Z, -X + Z, -Y + Z, Z], [], (4, 0, 4, 0)),
    "wedge + line": ([X, Y], [Z], (2, 0, 2, 1)),
    "wedge + line from rays": ([X, Y, Z, -Z, X + Y], [], (2, 0, 2, 1)),
    "R3 from line and rays": ([X, Y, -X - Y], [Z], (0, 0, 0, 3)),
}


@pytest.mark.parametrize("name", list(SPECIAL))
def test_special_cones(name):
    rays, lines, counts = SPECIAL[name]
    c = from_generators(rays, lines)
    well_formed(c)
    assert (c.F.shape[0], c.E.shape[0], c.rays.shape[0], c.lines.shape[0]) == counts
    assert agree(c, exact_from_generators(rays, lines))
    # the polar has the swapped counts, and from_inequalities gives the cone back
    back = from_inequalities(-c.F, c.E)
    assert agree(back, c, 1e-12)
    assert agree(from_generators(c.rays, c.lines), c, 1e-12)


def test_special_inequalities():
    assert agree(from_inequalities([], []), Cone3(np.zeros((0, 3)), np.zeros((0, 3)),
                                                  np.zeros((0, 3)), np.eye(3)))
    zero = from_inequalities([], np.eye(3))
    assert zero.E.shape == (3, 3) and zero.rays.shape[0] == zero.lines.shape[0] == 0
    orthant = from_inequalities(np.eye(3), [])
    assert agree(orthant, Cone3(-np.eye(3), np.zeros((0, 3)), np.eye(3), np.zeros((0, 3))))
    # redundant and zero rows
    c = from_inequalities([X, Y, Z, X + Y, [0, 0, 0]], [])
    assert agree(c, orthant)
    # x >= 0 and x <= 0: the plane x = 0
    c = from_inequalities([X, -X], [])
    assert c.E.shape[0] == 1 and c.lines.shape[0] == 2 and c.F.shape[0] == 0


# --- round trips and properties -----------------------------------------------------------------
@pytest.mark.parametrize("name", list(FAMILIES))
def test_round_trips(name):
    # a cone with 1e-9 rad features is ill-conditioned: a ray where two facets 1e-9 rad
    # from opposite meet moves by ~1e-7 when the facets move by an ulp
    tol = ANGLE if name.startswith("near") else 1e-9
    rng = np.random.default_rng([7, list(FAMILIES).index(name)])
    for _ in range(60):
        rays, lines = FAMILIES[name](rng)
        try:
            c = from_generators(rays, lines)
        except Cone3Error:
            continue
        assert agree(from_inequalities(-c.F, c.E), c, tol)
        assert agree(from_generators(c.rays, c.lines), c, tol)
        p = c.polar()
        assert agree(from_generators(p.rays, p.lines), p, tol)
        # invariance under positive rescaling and permutation of the generators
        perm = rng.permutation(len(rays))
        scale = rng.uniform(0.1, 10.0, size=len(rays))
        c2 = from_generators(np.asarray(rays)[perm] * scale[:, None] if len(rays) else rays,
                             lines)
        assert agree(c2, c, 1e-6)


def test_extreme_magnitudes_and_zero_rows():
    """Rows of 1e-300 or 1e300 (no under- or overflow) and zero rows change nothing."""
    base = from_generators([X, Y, Z, X + Y + Z], [])
    for scale in (1e-300, 1e-160, 1e160, 1e300):
        c = from_generators([X * scale, Y, Z * scale, (X + Y + Z) / scale, [0, 0, 0]], [])
        assert agree(c, base, 1e-12)
        c = from_inequalities([X * scale, Y, [0, 0, 0], Z / scale], [[0, 0, 0]])
        assert agree(c, from_inequalities(np.eye(3), []), 1e-12)


def test_rejects_non_finite():
    with pytest.raises(ValueError):
        from_generators([[np.nan, 0, 0]], [])
    with pytest.raises(ValueError):
        from_inequalities([[np.inf, 0, 0]], [])


def test_cone3error_is_a_runtime_error():
    # the same family cddlib's float failures belong to (cones._with_exact_fallback)
    assert issubclass(Cone3Error, RuntimeError)


def test_self_checks_raise_cone3error():
    """The self-checks refuse inconsistent intermediate results (white box: these states
    do not arise from the random families, see docs/cone3d.md)."""
    from wrenchcone_ros.core import cone3d

    R = np.array([X, Y, Z, _unit(X + Y + Z)])
    # a pointed cone with one facet missing: ray/facet counts disagree
    F = -np.eye(3)[:2]
    with pytest.raises(Cone3Error):
        cone3d._pointed(R, np.vstack([F, [_unit(-X - Y + Z)]]), None, None, None)
    # two facets whose line has rays along one way only
    with pytest.raises(Cone3Error):
        cone3d._wedge_line(R, -np.eye(3)[:2])
    # one facet whose plane is not spanned by the rays on it
    with pytest.raises(Cone3Error):
        cone3d._halfspace(R, -X)
    # facet candidates that chain: a ~ b, b ~ c, a !~ c
    eps = 1.5 * cone3d._TOL
    chain = np.array([_unit(Z + k * eps * X) for k in (0, 1, 2)])
    with pytest.raises(Cone3Error):
        cone3d._merge(chain, np.array([3.0, 2.0, 1.0]))
