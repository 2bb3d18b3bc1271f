# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The paper's algorithm against the paper's worked example, exact arithmetic and hand cases."""

from fractions import Fraction

import numpy as np
import pytest

from wrenchcone_ros.core import default_scene, load_scene, wrench_cone
from wrenchcone_ros.core.dynamics import problem
from wrenchcone_ros.core.paper import contact_matrices, kp_matrices, mode_constraints

from helpers.paper_example import PAPER_G, same_rays

@pytest.mark.parametrize("exact", [False, True])
def test_worked_example_generators(exact):
    cone = wrench_cone(default_scene(), "na", exact=exact, method="paper")
    assert cone.feasible
    assert same_rays(cone.G, PAPER_G)
    assert cone.equalities.shape == (0, 3) and cone.lineality.shape == (0, 3)


def test_worked_example_exact_rationals():
    """Exactly the paper's generators, as rationals (mu = 0.2 read as 1/5)."""
    cone = wrench_cone(default_scene(), "na", exact=True, method="paper")
    want = {(Fraction(1), Fraction(0), Fraction(-1)), (Fraction(-1, 5), Fraction(-1),
            Fraction(-1, 5)), (Fraction(1, 5), Fraction(-1), Fraction(1, 5))}
    got = set()
    for r in cone.exact_rep.G:
        scale = max(abs(x) for x in r)
        got.add(tuple(x / scale for x in r))
    assert got == want


def test_worked_example_facets_are_those_of_pos_G():
    """F's rows are the normalised facets of pos(G): each row is tight on two generators."""
    cone = wrench_cone(default_scene(), "na", method="paper")
    G = np.array(PAPER_G).T
    assert cone.F.shape == (3, 3)
    vals = cone.F @ G
    assert np.all(vals <= 1e-12)
    assert all(np.sum(np.abs(v) < 1e-12) == 2 for v in vals)
    nd = cone.F / np.array([1.0, 1.0, 1.0])  # L = 1 for the unit disc
    assert np.allclose(np.linalg.norm(nd, axis=1), 1.0)


def test_worked_example_intermediate_matrices():
    """A, C, K and P as printed in section 4 (with the sign fixes of docs/theory.md,
    "Sign fixes for readers of the published paper")."""
    prob = problem(default_scene(), "na", exact=True)
    A, B = contact_matrices(prob.J, prob.M)
    # C = [I, -A] as printed in section 4
    assert np.array_equal(A.astype(float), [[1, 0, 0, -1], [0, 1, 1, 0], [0, 1, 2, 1],
                                            [-1, 0, 1, 2]])
    assert np.array_equal(B.astype(float), [[0, 1, 0], [-1, 0, 0], [-1, 0, -1], [0, -1, -1]])
    K, P = kp_matrices(prob)
    mu = Fraction(1, 5)
    # rows a_1n, a_2n, a_1t (a_2t is free: E drops it); z = (-a_2n, u, w) with
    # c_1n = u + w, c_1t = mu (u - w): the paper's K up to its 1/2mu column scaling
    assert np.array_equal(K, np.array([[0, -1, -1], [-1, -mu, mu], [0, -2 * mu, 2 * mu]],
                                      dtype=object))
    assert np.array_equal(P.astype(float), [[0, 1, 0], [-1, 0, 0], [-1, 0, -1]])
    cons = mode_constraints(prob)
    assert [c.sign.value for c in cons[:4]] == ["= 0", "< 0", "= 0", "free"]


@pytest.mark.parametrize("mode", ["sa", "ss", "la", "ra", "na", "ls", "rs", "ns"])
def test_float_agrees_with_exact(mode):
    s = default_scene()
    for method in ("paper", "planar"):
        a = wrench_cone(s, mode, method=method)
        b = wrench_cone(s, mode, exact=True, method=method)
        assert a.feasible == b.feasible
        assert np.allclose(a.F_hat, b.F_hat, atol=1e-12)
        assert np.allclose(a.E_hat, b.E_hat, atol=1e-12)
        assert np.allclose(a.G_hat, b.G_hat, atol=1e-12)


def disc_scene(fixels, mu=0.2, modes=()):
    return load_scene({"workpiece": {"mass": 1.0, "inertia": 0.5, "shape": {
        "type": "disc", "radius": 1.0}}, "friction": mu, "fixels": fixels, "modes": list(modes)})


def test_mu_zero_works():
    """mu = 0: the paper's R divides by mu; ours does not.

    Rolling without friction on one point: the disc may only rotate about the contact
    point (a line of accelerations) and the fixel pushes along n: a half-plane.
    """
    s = disc_scene([[0.0, -1.0]], mu=0.0)
    for method in ("paper", "planar"):
        cone = wrench_cone(s, "n", method=method)
        assert cone.feasible
        # frictionless support from below: only a pure push down through the centre
        # (balanced) is consistent with no acceleration
        assert cone.contains((0.0, -1.0, 0.0))
        assert not cone.contains((0.1, -1.0, 0.0))
        assert cone.equalities.shape[0] == 1  # a half-plane: empty interior
        assert cone.lineality.shape[0] == 1 and cone.G.shape[0] == 1


def test_all_of_R3_half_space_and_zero():
    s = disc_scene([[0.0, -1.0]], mu=0.5)
    # separating a free fixel: no constraint tying g at all? 's' in contact needs a_n > 0
    sep = wrench_cone(disc_scene([[0.0, -1.5]]), "s")
    assert sep.feasible and sep.F.shape == (1, 3) and sep.lineality.shape[0] == 2
    # approaching + separating the same free point from both sides is R^3 in closure but
    # the free fixel alone approached: a half-space
    app = wrench_cone(disc_scene([[0.0, -1.5]]), "a")
    assert app.F.shape == (1, 3) and np.allclose(app.F_hat, -sep.F_hat)
    # rolling with huge friction at one point: consistent set is a half-space + ...
    roll = wrench_cone(s, "n")
    assert roll.feasible and roll.full_dimensional


def test_impossible_mode_is_infeasible_not_everything():
    """Three rolling fixels pin the body; a fourth 'a' is impossible (docs/theory.md,
    "Closure versus the mode itself")."""
    s = disc_scene([[0.0, -1.0], [0.866025403784, 0.5], [-0.866025403784, 0.5],
                    [1.5, 0.0]])
    for method in ("paper", "planar"):
        cone = wrench_cone(s, "nnna", method=method)
        assert not cone.feasible
        assert cone.closure is not None
        assert cone.closure.F.shape[0] == 0 and cone.closure.equalities.shape[0] == 0  # R^3
        for g in np.random.default_rng(0).normal(size=(50, 3)):
            assert not cone.contains(g)
            assert cone.margin(g) == -1.0
        assert np.allclose(cone.equalities, np.eye(3))  # published as {0}, never "anything"
