# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Robust answers users call (force_directions, sweep, consistent_modes with
``uncertainty=``), checked against the nominal answers of sampled models: every vertex of
the friction box and interior samples, each a scene of its own (the nominal code path).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest
import yaml

from wrenchcone_ros.core import (
    Fixel,
    Uncertainty,
    consistent_modes,
    force_directions,
    load_scene,
    sweep,
)

PAWL = "examples/pawl_polygon.yaml"
U = Uncertainty(friction=(0.2, 0.4))


def models(scene, interior=12, seed=0):
    rng = np.random.default_rng(seed)
    mus = [list(v) for v in itertools.product((0.2, 0.4), repeat=scene.n_fixels)]
    mus += [list(rng.uniform(0.2, 0.4, scene.n_fixels)) for _ in range(interior)]
    return [dataclasses.replace(scene, fixels=tuple(
        Fixel(f.position, f.radius, float(mu)) for f, mu in zip(scene.fixels, m)))
        for m in mus]


@pytest.fixture(scope="module")
def pawl():
    return load_scene(PAWL)


def test_consistent_modes_certain_is_every_model_possible_is_some(pawl):
    rng = np.random.default_rng(5)
    ms = models(pawl)
    for _ in range(12):
        phi = rng.uniform(-math.pi, math.pi)
        g = (math.cos(phi), math.sin(phi), rng.normal() * pawl.length_scale * 0.2)
        robust = {m.mode: m for m in consistent_modes(pawl, g, uncertainty=U)}
        seen = [{m.mode: m.margin for m in consistent_modes(s, g)} for s in ms]
        some = set().union(*seen)
        every = set.intersection(*(set(s) for s in seen))
        # far from every boundary the sampled answer decides; near one either may go
        sure = {m for m in some if all(abs(s.get(m, 1.0)) > 1e-6 for s in seen)}
        assert sure <= set(robust)  # seen at a sampled model: possible
        for mode, match in robust.items():
            if match.certain:
                assert mode in every or abs(match.margin_all) < 1e-6
            elif mode in every and mode in sure:
                pytest.fail(f"{mode} holds at every sampled model but is not certain")


def test_exclusive_directions_give_only_the_mode_at_every_model(pawl):
    (iv,) = force_directions(pawl, "arr", uncertainty=U, exclusive=True)
    ms = models(pawl)
    for phi in np.linspace(iv.lo, iv.hi, 9)[1:-1]:
        g = (math.cos(phi), math.sin(phi), 0.0)
        for s in ms:
            assert [m.mode for m in consistent_modes(s, g)] == ["arr"]
    for phi in (iv.lo - 0.01, iv.hi + 0.01):  # just outside: some model does otherwise
        g = (math.cos(phi), math.sin(phi), 0.0)
        assert any([m.mode for m in consistent_modes(s, g)] != ["arr"] for s in ms)


def test_sweep_with_uncertainty_is_robust_directions_per_pose(pawl):
    poses = yaml.safe_load(open("examples/pawl_slide_poses.yaml"))["poses"]
    point = (0.0075, 0.035)
    res = sweep(pawl, poses, "arr", point=point, uncertainty=U)
    assert res.stop == 8 and str(res.common[0].guarantee) == "exact"
    for k in (0, 3, 7):
        (iv,) = force_directions(pawl.with_pose(*poses[k]), "arr", point=point,
                                 uncertainty=U)
        (got,) = res.intervals[k]
        assert (got.lo, got.hi) == pytest.approx((iv.lo, iv.hi), abs=1e-12)
    lo = max(ivs[0].lo for ivs in res.intervals[:8])
    hi = min(ivs[0].hi for ivs in res.intervals[:8])
    assert (res.common[0].lo, res.common[0].hi) == pytest.approx((lo, hi), abs=1e-9)
    assert [m.mode for m in res.after] == ["nnn"] and res.after[0].certain


def test_robust_directions_against_the_nominal_ones_of_every_corner(pawl):
    point = (0.0075, 0.035)
    (iv,) = force_directions(pawl, "arr", point=point, uncertainty=U)
    nominal = [force_directions(s, "arr", point=point)[0] for s in models(pawl, 0)]
    assert iv.lo == pytest.approx(max(n.lo for n in nominal), abs=1e-9)
    assert iv.hi == pytest.approx(min(n.hi for n in nominal), abs=1e-9)
