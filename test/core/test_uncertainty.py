# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The uncertainty model (core/uncertainty.py): validation with worded errors, the YAML
form, per-scene intervals and the sampling distribution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrenchcone_ros.core import Uncertainty, UncertaintyError, load_scene, load_uncertainty
from wrenchcone_ros.core.uncertainty import uncertainty_from_dict


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
