# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The uncertainty model (core/uncertainty.py): validation with worded errors, the YAML
form, per-scene intervals and the sampling distribution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from helpers.strategies import random_scene, random_wrench
from wrenchcone_ros.core import (
    NOMINAL,
    Uncertainty,
    UncertaintyError,
    consistent_modes,
    force_directions,
    load_scene,
    load_uncertainty,
    wrench_cone,
)
from wrenchcone_ros.core.directions import force_basis
from wrenchcone_ros.core.sweeps import sweep
from wrenchcone_ros.core.lp_check import lp_consistent
from wrenchcone_ros.core.modes import expand_mode
from wrenchcone_ros.core.plan.segments import margin_function, robust_directions
from wrenchcone_ros.core.classify import robust_classification_cones, robust_mode_matches
from wrenchcone_ros.core.uncertainty import as_uncertainty, nominal_model, uncertainty_from_dict


@pytest.fixture(scope="module")
def pawl():
    return load_scene("examples/pawl_polygon.yaml")


def test_friction_forms(pawl):
    assert Uncertainty(friction=(0.2, 0.4)).friction_intervals(pawl) == [(0.2, 0.4)] * 3
    per = Uncertainty(friction=[None, (0.1, 0.2), [0.3, 0.3]]).friction_intervals(pawl)
    assert per == [(0.3, 0.3), (0.1, 0.2), (0.3, 0.3)]
    assert Uncertainty().friction_intervals(pawl) == [(0.3, 0.3)] * 3
    with pytest.raises(UncertaintyError, match="2 interval.*3 fixel"):
        Uncertainty(friction=[(0.1, 0.2), (0.1, 0.2)]).friction_intervals(pawl)


@pytest.mark.parametrize("kwargs, message", [
    ({"friction": (0.4, 0.2)}, "lo must be <= hi"),
    ({"friction": (-0.1, 0.2)}, "lo must be >= 0"),
    ({"friction": (0.1, float("nan"))}, "finite"),
    ({"friction": "0.2"}, "interval"),
    ({"mass": (0.0, 1.0)}, "lo must be > 0"),
    ({"inertia": (1.0,)}, "interval"),
    ({"com_radius": -1e-3}, "com_radius must be >= 0"),
    ({"com_radius": 1e-3, "com_box": (1e-3, 1e-3)}, "not both"),
    ({"com_box": (1e-3, -1.0)}, "half-widths"),
    ({"normal_error": 2.0}, r"\[0, pi/2\)"),
    ({"epsilon": 0.0}, r"\(0, 1\)"),
    ({"beta": 1.5}, r"\(0, 1\)"),
    ({"seed": 1.5}, "seed must be an integer"),
])
def test_bad_inputs_are_refused_with_what_is_allowed(kwargs, message):
    with pytest.raises(UncertaintyError, match=message):
        Uncertainty(**kwargs)


def test_yaml_round_trip_and_scene_files(tmp_path, pawl):
    U = Uncertainty(friction=[None, (0.2, 0.4), (0.2, 0.4)], mass=(0.04, 0.06),
                    com_radius=1e-3, normal_error=[0.0, 0.01, 0.02], seed=7)
    assert uncertainty_from_dict(U.to_dict()) == U
    path = tmp_path / "u.yaml"
    path.write_text("friction: [0.2, 0.4]\ncom_radius: 0.001\n")
    assert load_uncertainty(path) == Uncertainty(friction=(0.2, 0.4), com_radius=1e-3)
    assert load_uncertainty("examples/pawl_polygon.yaml") is None
    with pytest.raises(UncertaintyError, match="unknown key.*'frction'"):
        uncertainty_from_dict({"frction": [0.2, 0.4]})


def test_nonlinear_flags_only_real_widths(pawl):
    assert not Uncertainty(friction=(0.2, 0.4)).nonlinear(pawl)
    assert not Uncertainty(mass=(0.05, 0.05), com_radius=0.0, normal_error=0.0).nonlinear(pawl)
    assert Uncertainty(com_radius=1e-3).nonlinear(pawl)
    assert Uncertainty(inertia=(1e-5, 3e-5)).nonlinear(pawl)
    assert Uncertainty(normal_error=[0, 0, 0.01]).nonlinear(pawl)


def test_samples_stay_in_the_set_and_fill_it(pawl):
    U = Uncertainty(friction=(0.2, 0.4), mass=(0.04, 0.06), inertia=(1e-5, 3e-5),
                    com_radius=1e-3, normal_error=0.02)
    models = U.sample(pawl, 4000, friction=True)
    com = np.array([m.com for m in models]) - np.array(pawl.workpiece.com)
    r = np.hypot(com[:, 0], com[:, 1])
    assert r.max() <= 1e-3 and np.mean(r <= 0.5e-3) == pytest.approx(0.25, abs=0.03)
    e = np.array([m.normal_error for m in models])
    assert np.abs(e).max() <= 0.02 and np.abs(e).max() > 0.0199
    mu = np.array([m.friction for m in models])
    assert mu.min() >= 0.2 and mu.max() <= 0.4
    assert all(0.04 <= m.mass <= 0.06 and 1e-5 <= m.inertia <= 3e-5 for m in models)
    assert U.sample(pawl, 3) == U.sample(pawl, 3)  # reproducible from the seed
    box = Uncertainty(com_box=(1e-3, 2e-3)).sample(pawl, 2000, seed=1)
    d = np.array([m.com for m in box]) - np.array(pawl.workpiece.com)
    assert np.abs(d[:, 0]).max() <= 1e-3 and np.abs(d[:, 1]).max() <= 2e-3
    assert np.abs(d[:, 1]).max() > 1.9e-3


def test_as_uncertainty_is_the_one_normaliser(pawl):
    """None is NOMINAL, an Uncertainty itself, friction intervals an Uncertainty of them;
    with a scene, a count of intervals other than its fixels' is refused; anything else
    is refused naming what is allowed."""
    assert as_uncertainty() is NOMINAL and as_uncertainty(None, pawl) is NOMINAL
    u = Uncertainty(mass=(0.04, 0.06))
    assert as_uncertainty(u) is u
    assert as_uncertainty((0.2, 0.4)) == Uncertainty(friction=(0.2, 0.4))
    per = as_uncertainty([(0.1, 0.2), None, [0.3, 0.4]], pawl)
    assert per.friction_intervals(pawl) == [(0.1, 0.2), (pawl.mu(1), pawl.mu(1)), (0.3, 0.4)]
    with pytest.raises(UncertaintyError, match="2 interval"):
        as_uncertainty([(0.2, 0.4)] * 2, pawl)
    with pytest.raises(UncertaintyError, match="lo must be <= hi"):
        as_uncertainty((0.4, 0.2))
    for bad in (0.3, "0.2 0.4", {"friction": [0.2, 0.4]}):
        with pytest.raises(TypeError, match="friction interval"):
            as_uncertainty(bad)


def test_the_nominal_model_is_the_scenes_own():
    """Every fixel's own mu (per-fixel values, the scene's default elsewhere), the
    workpiece's mass, inertia and centre of mass, no normal turn: the model a friction
    box of zero width at the scene's values contains, and the planner's nominal run."""
    from wrenchcone_ros.core.plan.execution import capture_models

    d = load_scene("examples/pawl_polygon.yaml").to_dict()
    d["fixels"][1]["friction"] = 0.45
    scene = load_scene(d)
    m = nominal_model(scene)
    wp = scene.workpiece
    assert m.friction == (scene.mu(0), 0.45, scene.mu(2)) and scene.mu(0) != 0.45
    assert (m.mass, m.inertia, m.com, m.normal_error) == (wp.mass, wp.inertia,
                                                          tuple(wp.com), (0.0,) * 3)
    assert capture_models(scene, NOMINAL) == [("nominal", m)]


def test_describe_and_scenario_size_one_is_the_classic_bound():
    U = Uncertainty(friction=(0.2, 0.4), com_radius=1e-3)
    assert U.describe() == "friction [0.2, 0.4], com_radius 0.001"
    assert U.scenario_size(1) == math.ceil(math.log(U.beta) / math.log(1 - U.epsilon))


def test_a_scene_file_may_carry_its_uncertainty(tmp_path):
    text = open("examples/pawl_polygon.yaml").read()
    path = tmp_path / "pawl_uncertain.yaml"
    path.write_text(text + "uncertainty:\n  friction: [0.2, 0.4]\n  com_radius: 0.001\n")
    scene = load_scene(path)
    assert scene.n_fixels == 3
    assert load_uncertainty(path) == Uncertainty(friction=(0.2, 0.4), com_radius=1e-3)
    path.write_text(text + "uncertainty:\n  friction: [0.4, 0.2]\n")
    with pytest.raises(UncertaintyError, match="lo must be <= hi"):
        load_uncertainty(path)


# --- the nominal model is the zero-width uncertainty ----------------------------------------
# None, NOMINAL and explicit zero-width intervals must give the same answers through every
# public function (one code path: the zero-width uncertainty takes the nominal fast path
# behind robust_cones and the ModeClassifier), and those answers must agree with the LP
# oracle (core/lp_check.py: Newton-Euler and Table 2 as an LP, no cone).

#: Skip wrenches whose unit nondimensional direction is this close to a cone's boundary
#: (dimensionless): the float cone and the LP may round either way there.
_BAND = 1e-6


def _zero_width(scene):
    """Every way of asking for the nominal model of ``scene``."""
    wp = scene.workpiece
    return [None, NOMINAL,
            Uncertainty(friction=[(scene.mu(i), scene.mu(i)) for i in range(scene.n_fixels)]),
            Uncertainty(mass=(wp.mass, wp.mass), inertia=(wp.inertia, wp.inertia),
                        com_radius=0.0, normal_error=0.0)]


def _scenes():
    rng = np.random.default_rng(26)
    out = [load_scene("examples/pawl_polygon.yaml"), load_scene("examples/paper_disc.yaml")]
    while len(out) < 6:
        out.append(load_scene(random_scene(rng, n_fixels=int(rng.integers(2, 4))).data))
    return out


_SCENES = _scenes()


def _lp_modes(scene, g) -> tuple[set[str], set[str]]:
    """(modes the LP says g is consistent with, modes it cannot decide or that lie within
    _BAND of their cone's boundary)."""
    yes, unsure = set(), set()
    for mode in expand_mode("*" * scene.n_fixels, scene.in_contact):
        r = lp_consistent(scene, mode, g)
        if not r.decided or abs(wrench_cone(scene, mode, engine="numpy").margin(g)) < _BAND:
            unsure.add(mode)
        elif r.consistent:
            yes.add(mode)
    return yes, unsure


@pytest.mark.parametrize("k", range(len(_SCENES)))
def test_consistent_modes_of_the_zero_width_uncertainty_are_the_nominal_ones(k):
    scene = _SCENES[k]
    rng = np.random.default_rng(k)
    for _ in range(3):
        g = random_wrench(rng, scene.length_scale)
        got = [[(m.mode, m.margin, m.certain, m.margin_all, str(m.guarantee))
                for m in consistent_modes(scene, g, uncertainty=u)]
               for u in _zero_width(scene)]
        assert all(x == got[0] for x in got[1:])
        assert all(certain and m_all == m for _mode, m, certain, m_all, _g in got[0])
        # the general path (every mode's "all" and "any" sets, no pruning) agrees
        exhaustive = robust_mode_matches(g, *robust_classification_cones(scene, NOMINAL))
        assert [m.mode for m in exhaustive] == [x[0] for x in got[0]]
        yes, unsure = _lp_modes(scene, g)
        assert {x[0] for x in got[0]} - unsure == yes


@pytest.mark.parametrize("k", range(len(_SCENES)))
def test_force_directions_of_the_zero_width_uncertainty_are_the_nominal_ones(k):
    scene = _SCENES[k]
    contact = scene.in_contact
    modes = [m for m in expand_mode("*" * scene.n_fixels, contact)
             if wrench_cone(scene, m).feasible][:2]
    modes.append("".join("c" if t else "*" for t in contact))  # a wildcard mode
    B = force_basis(scene, None)
    for mode in modes:
        for exclusive in (False, True):
            got = [force_directions(scene, mode, exclusive=exclusive, uncertainty=u)
                   for u in _zero_width(scene)]
            rows = [[(iv.lo, iv.hi, iv.best, iv.margin, str(iv.guarantee)) for iv in ivs]
                    for ivs in got]
            assert all(r == rows[0] for r in rows[1:]), (mode, exclusive)
            mine = set(expand_mode(mode, contact))
            for iv in got[0]:  # the LP at the middle of each interval
                if iv.width < 1e-6:
                    continue
                phi = 0.5 * (iv.lo + iv.hi)
                yes, unsure = _lp_modes(scene, B @ np.array([math.cos(phi), math.sin(phi)]))
                if (mine | (set() if not exclusive else set(yes))) & unsure:
                    continue
                assert yes & mine, (mode, phi)
                if exclusive:
                    assert yes <= mine, (mode, phi, yes)


def test_plan_segments_of_the_zero_width_uncertainty_are_the_nominal_ones():
    scene = load_scene("examples/pawl_seating.yaml")
    for point in (None, (0.03, 0.0)):
        ref = robust_directions(scene, "arr", point, None)
        for u in _zero_width(scene)[1:]:
            assert robust_directions(scene, "arr", point, u) == ref
        margin = [margin_function([scene], "arr", point, u) for u in _zero_width(scene)]
        for iv in ref:
            phis = np.linspace(iv.lo, iv.hi, 5)
            ms = [[m(float(p)) for p in phis] for m in margin]
            assert all(x == ms[0] for x in ms[1:])
            # the margin in the robust "all" cone of NOMINAL is the nominal cone's margin
            cone = wrench_cone(scene, "arr")
            B = force_basis(scene, point)
            assert ms[0] == [cone.margin(B @ np.array([math.cos(p), math.sin(p)]))
                             for p in phis]


def test_a_sweep_of_the_zero_width_uncertainty_is_the_nominal_one():
    scene = load_scene("examples/pawl_seating.yaml")
    poses = [(scene.pose[0] + dx, scene.pose[1], scene.pose[2]) for dx in (0.0, 0.002, 0.004)]
    got = [sweep(scene, poses, "arr", uncertainty=u) for u in _zero_width(scene)]
    for r in got[1:]:
        assert (r.stop, r.stop_reason, r.after) == (got[0].stop, got[0].stop_reason, got[0].after)
        assert [[(iv.lo, iv.hi, iv.best, iv.margin) for iv in ivs or ()] for ivs in r.intervals] \
            == [[(iv.lo, iv.hi, iv.best, iv.margin) for iv in ivs or ()]
                for ivs in got[0].intervals]
        assert [(iv.lo, iv.hi) for iv in r.common] == [(iv.lo, iv.hi) for iv in got[0].common]
    # the common directions hold at every pose: the mode's nominal cone holds the force
    cones = [wrench_cone(scene.with_pose(*p), "arr") for p in poses[:got[0].stop]]
    for iv in got[0].common:
        phi = 0.5 * (iv.lo + iv.hi)
        f = np.array([math.cos(phi), math.sin(phi)])
        assert all(c.contains(force_basis(scene.with_pose(*p), None) @ f)
                   for c, p in zip(cones, poses))
