# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The scenario guarantee of robust cones (mass, inertia, com region, normal errors), checked
empirically: over 10,000 fresh models, drawn independently of the ones the cones were
built from, the share of models at which a wrench of the "all" cone is inconsistent is
below epsilon, and so is the share at which a wrench outside the "any" union is
consistent.

Each fresh model's cone is computed here from the scene's contact frames (contact point,
normal turned by the model's angle, moment arms about the model's com, friction drawn in
its interval) by the numpy reference (planar.planar_cone on a Problem), not by the
batched rows robust.py builds.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from helpers.strategies import wrench_from_cone
from wrenchcone_ros.core import Uncertainty, force_directions, load_scene, robust_cone
from wrenchcone_ros.core.dynamics import Problem
from wrenchcone_ros.core.modes import parse_mode
from wrenchcone_ros.core.planar import planar_cone

FRESH = 10_000

U_PAWL = Uncertainty(friction=(0.2, 0.4), com_radius=1e-3, mass=(0.045, 0.055),
                     inertia=(1.8e-5, 2.2e-5), normal_error=math.radians(1.0))


def model_cone(scene, mode, model):
    """The cone of one model, wrenches about the model's own com (numpy reference)."""
    th = scene.pose[2]
    c, s = math.cos(th), math.sin(th)
    x, y = scene.pose[:2]
    com = np.array([x + c * model.com[0] - s * model.com[1],
                    y + s * model.com[0] + c * model.com[1]])
    L = scene.length_scale
    cols_n, cols_t = [], []
    for ct, e in zip(scene.contacts, model.normal_error):
        n0, t0 = np.asarray(ct.n, float), np.asarray(ct.t, float)
        n = math.cos(e) * n0 + math.sin(e) * t0
        t = np.array([-n[1], n[0]])
        r = np.asarray(ct.p, float) - com
        cols_n.append([n[0], n[1], (r[0] * n[1] - r[1] * n[0]) / L])
        cols_t.append([t[0], t[1], (r[0] * t[1] - r[1] * t[0]) / L])
    J = np.array(cols_n + cols_t, dtype=float).T
    M = np.diag([1.0, 1.0, model.inertia / (model.mass * L * L)])
    inters = parse_mode(mode, scene.in_contact)
    return planar_cone(Problem(mode, inters, scene.in_contact, J, M, model.friction, L, False))


def about_model_com(scene, model, g0):
    """A wrench about the nominal com expressed about the model's com."""
    th = scene.pose[2]
    wx, wy = (model.com[0] - scene.workpiece.com[0], model.com[1] - scene.workpiece.com[1])
    dx, dy = math.cos(th) * wx - math.sin(th) * wy, math.sin(th) * wx + math.cos(th) * wy
    f = np.asarray(g0, float)
    return np.array([f[0], f[1], f[2] - (dx * f[1] - dy * f[0])])


@pytest.fixture(scope="module")
def pawl():
    return load_scene("examples/pawl_polygon.yaml")


@pytest.fixture(scope="module")
def fresh(pawl):
    models = U_PAWL.sample(pawl, FRESH, seed=12345, friction=True)
    return models, [model_cone(pawl, "arr", m) for m in models]


def test_scenario_sizes():
    U = Uncertainty(epsilon=0.05, beta=1e-3)
    assert U.scenario_size(1) == math.ceil(math.log(1e-3) / math.log(0.95)) == 135
    n = U.scenario_size(3)
    tail = sum(math.comb(n, i) * 0.05 ** i * 0.95 ** (n - i) for i in range(3))
    tail_before = sum(math.comb(n - 1, i) * 0.05 ** i * 0.95 ** (n - 1 - i) for i in range(3))
    assert tail <= 1e-3 < tail_before


@pytest.mark.slow
def test_all_cone_violation_frequency_below_epsilon(pawl, fresh):
    models, cones = fresh
    rc = robust_cone(pawl, "arr", U_PAWL, "all")
    assert rc.guarantee.kind == "scenario" and rc.guarantee.models == U_PAWL.scenario_size()
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(10):
        g0 = wrench_from_cone(rng, rc.cone, pawl.length_scale)
        bad = sum(not c.contains(about_model_com(pawl, m, g0)) for m, c in zip(models, cones))
        worst = max(worst, bad / FRESH)
    assert worst < U_PAWL.epsilon, worst


@pytest.mark.slow
def test_any_union_holds_what_fresh_models_allow(pawl, fresh):
    models, cones = fresh
    rc = robust_cone(pawl, "arr", U_PAWL, "any")
    rng = np.random.default_rng(4)
    checked = 0
    while checked < 10:
        u = rng.normal(size=3)
        g0 = np.array([u[0], u[1], u[2] * pawl.length_scale])
        if rc.contains(g0):
            continue
        hits = sum(c.contains(about_model_com(pawl, m, g0)) for m, c in zip(models, cones))
        assert hits / FRESH < U_PAWL.epsilon
        checked += 1


@pytest.mark.slow
def test_robust_best_tilt_holds_for_fresh_models(pawl, fresh):
    models, cones = fresh
    (iv,) = force_directions(pawl, "arr", uncertainty=U_PAWL)
    g = np.array([math.cos(iv.best), math.sin(iv.best), 0.0])  # at each model's own com
    bad = sum(not c.contains(g) for c in cones)
    assert bad / FRESH < U_PAWL.epsilon
    margins = np.array([c.margin(g) for c in cones])
    # the worst case over the sampled models is a guarantee in the scenario sense only
    assert np.mean(margins < iv.margin) < U_PAWL.epsilon


def test_model_rows_match_the_reference_geometry(pawl):
    """robust.py's rows of a model (com moved, normals turned) give the same cone as the
    reference built from the contact frames."""
    from wrenchcone_ros.core.robust import _all_blocks, block_cones, model_rows

    for model in U_PAWL.sample(pawl, 20, seed=9, friction=True):
        data = model_rows(pawl, model)
        (mine,) = block_cones(_all_blocks(data.A, "arr", pawl.in_contact,
                                          [(m, m) for m in model.friction]),
                              data.kappa, pawl.length_scale, "arr")
        ref = model_cone(pawl, "arr", model)
        assert mine.feasible == ref.feasible
        np.testing.assert_allclose(mine.F_hat, ref.F_hat, atol=1e-9)
