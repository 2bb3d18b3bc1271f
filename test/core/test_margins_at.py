# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""cones.margins_at, the direction searches' fast margin of several cones at one wrench,
against the scalar reference (Cone.check, itself tested against the NNLS distance in
test_cone_margin.py): the same doubles, compared exactly (float.hex, so the sign of a
zero counts too), never approximately."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wrenchcone_ros.core import enumerate_modes, load_scene, wrench_cone
from wrenchcone_ros.core.cones import cone_from_vrep, margins_at


def scalar(cones, g) -> list[str]:
    """The reference: each cone's own scalar check, as hex strings."""
    return [c.check(g)[1].hex() for c in cones]


def fast(cones, g) -> list[str]:
    return [m.hex() for m in margins_at(cones, g)]


def scene_cones() -> list:
    out = []
    for path in ("examples/paper_disc.yaml", "examples/pawl_polygon.yaml",
                 "examples/pawl_seating.yaml", "examples/tbar_swing.yaml"):
        scene = load_scene(path)
        out += [wrench_cone(scene, m) for m in enumerate_modes(scene.in_contact)]
    return out


def synthetic_cones() -> list:
    """Every kind of cone: R^3, {0}, half-space, wedge, plane, half-plane, sector, ray,
    line, pointed, nearly flat; at two length scales."""
    shapes = [([], np.eye(3)), ([], []), ([[0, 0, 1]], [[1, 0, 0], [0, 1, 0]]),
              ([[1, 0, 0], [0, 1, 0]], [[0, 0, 1]]), ([], [[1, 0, 0], [0, 1, 0]]),
              ([[0, 1, 0]], [[1, 0, 0]]), ([[1, 0, 0], [1, 1, 0]], []), ([[1, 2, 3]], []),
              ([], [[1, -1, 0.5]]), ([[1, 0, 1], [0, 1, 1], [-1, -1, 1]], []),
              ([[1, 0, 1], [1, 1e-6, 1], [1, 0, 1 + 1e-6]], [])]
    return [cone_from_vrep(rays, lines, mode="x", length_scale=L, method="test", exact=False)
            for rays, lines in shapes for L in (1.0, 0.01)]


CONES = scene_cones() + synthetic_cones()
RNG = np.random.default_rng(11)
WRENCHES = np.vstack([RNG.normal(size=(150, 3)) * 10.0 ** RNG.integers(-4, 4, size=(150, 1)),
                      np.eye(3), -np.eye(3), np.zeros((1, 3)),
                      [[0.0, -0.0, 0.0], [1e-300, 0.0, 0.0], [1e150, -1e150, 1e150]]])


def test_every_kind_of_cone_and_scene_mode_gives_the_scalar_margin_exactly():
    """All the cones in one call (length scales mixed, so the wrench is normalised again
    whenever the scale changes; infeasible modes; cones with equalities and lines)."""
    assert any(not c.feasible for c in CONES) and any(c.L_hat.shape[0] for c in CONES)
    assert any(c.E_hat.shape[0] for c in CONES)
    outside = 0
    for g in WRENCHES:
        want = scalar(CONES, g)
        assert fast(CONES, g) == want, g
        outside += sum(float.fromhex(m) < 0 for m in want)
    assert outside > 1000  # the projections' branch, not only the inside one


def test_a_wrench_that_is_not_finite_is_refused_as_the_scalar_call_refuses_it():
    cone = CONES[0]
    for g in ([math.inf, 0.0, 0.0], [0.0, math.nan, 1.0], [1e200, 1e200, 0.0]):
        with pytest.raises(ValueError) as want:
            cone.margin(g)
        with pytest.raises(ValueError) as got:
            margins_at([cone], g)
        assert str(got.value) == str(want.value)
    assert margins_at([], [math.inf, 0, 0]) == []


finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)
small = st.one_of(finite, st.sampled_from([0.0, -0.0, 1e-12, -1e-300]))
vec = st.lists(small, min_size=3, max_size=3)


@settings(max_examples=300, deadline=None)
@given(st.lists(vec, min_size=1, max_size=6), st.lists(vec, max_size=2),
       st.sampled_from([1.0, 0.05, 7.0]), st.lists(vec, min_size=1, max_size=4))
def test_random_cones_and_wrenches_give_the_scalar_margin_exactly(rays, lines, L, wrenches):
    """Random generators (rays and lines, so pointed cones, wedges, half-spaces and
    planes), random wrenches including zeros and signed zeros: ``==`` on every bit."""
    try:
        cone = cone_from_vrep(rays, lines, mode="x", length_scale=L, method="test",
                              exact=False)
    except ValueError:  # not a cone the float conversion accepts
        return
    cones = [cone, CONES[3]]  # and one of another length scale after it
    for g in wrenches:
        assert fast(cones, g) == scalar(cones, g), (rays, lines, L, g)


def test_margins_of_wrench_sets_equal_each_sets_own_margin_exactly():
    """Unions of several pieces (wildcard modes), single pieces, an empty union and
    plain cones in one call: each value is the set's own ``margin(g)``."""
    from wrenchcone_ros.core import wrench_cones
    from wrenchcone_ros.core.wrenchset import WrenchSet, margins_of

    scene = load_scene("examples/pawl_seating.yaml")
    n = scene.n_fixels
    concrete = list(enumerate_modes(scene.in_contact))
    sets = wrench_cones(scene, ["*" * n, "a" + "*" * (n - 1), "s" * n, concrete[-1]])
    sets = [s if isinstance(s, WrenchSet) else WrenchSet.of(s) for s in sets]
    sets += [WrenchSet("x", ()), CONES[5], CONES[-1]]
    assert max(len(s.pieces) for s in sets[:4]) > 2
    for g in WRENCHES:
        want = [s.margin(g).hex() for s in sets]
        assert [m.hex() for m in margins_of(sets, g)] == want, g
