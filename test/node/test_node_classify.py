# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Classification over all modes and wildcard modes through the node."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrenchcone_ros.core import consistent_modes, default_scene, load_scene, mode_union
from wrenchcone_msgs.msg import Status

S = Status
WRENCHES = [(0.1, -1.0, 0.0), (0.0, -1.0, 0.0), (1.0, 0.0, -0.5), (0.0, 1.0, 0.0),
            *np.random.default_rng(3).normal(size=(12, 3))]
TWO_CONTACTS = {
    "workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.2, 0.1],
                  "shape": {"type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}},
    "friction": 0.3,
    "fixels": [[-0.5, -1.0], [0.5, -1.0], [1.5, 0.0]],
}


def test_classify_equals_core(harness):
    scene = default_scene()
    for g in WRENCHES:
        r = harness.classify(g)
        assert r.status == S.OK, r.message
        expected = consistent_modes(scene, g)
        assert [m.mode for m in r.matches] == [m.mode for m in expected]
        assert [m.margin for m in r.matches] == pytest.approx([m.margin for m in expected],
                                                              abs=1e-12)


def test_check_wrench_reports_other_modes_and_only(harness_factory, tmp_path):
    import yaml

    path = tmp_path / "two.yaml"
    path.write_text(yaml.safe_dump(TWO_CONTACTS))
    h = harness_factory(scene_file=str(path), modes=["ssa"])
    scene = load_scene(TWO_CONTACTS)
    seen_only = seen_shared = False
    for g in [(0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.2, -1.0, 0.05), (-0.5, -1.0, 0.0),
              *np.random.default_rng(5).normal(size=(20, 3))]:
        matches = {m.mode: m.margin for m in consistent_modes(scene, g)}
        for mode in ("nna", "ssa", "rra"):
            r = h.check(mode, g, classify=True)
            assert r.status in (S.OK, S.MODE_INFEASIBLE), r.message
            assert r.consistent == (mode in matches)
            others = {m: v for m, v in matches.items() if m != mode}
            assert {m.mode: m.margin for m in r.others} == pytest.approx(others)
            assert r.only_mode == (r.consistent and not others)
            seen_only |= r.only_mode
            seen_shared |= r.consistent and bool(others)
    assert seen_only and seen_shared  # both cases occurred: the test is not vacuous
    # without classify nothing is reported (and nothing is computed for it)
    r = h.check("nna", (0.0, -1.0, 0.0))
    assert not r.others and not r.only_mode


def test_wildcard_modes(harness):
    scene = default_scene()
    for mode in ("ca", "*a", "**", "c*"):
        union = mode_union(scene, mode)
        for g in WRENCHES:
            r = harness.check(mode, g)
            assert r.status == S.OK, r.message
            assert r.consistent == union.contains(g)
            assert r.margin == pytest.approx(union.margin(g), abs=1e-12)
        c = harness.get_cone(mode)
        assert c.status == S.INVALID_MODE and "wildcard" in c.message and not c.feasible
    r = harness.check("ac", (0.0, -1.0, 0.0))  # c needs contact at fixel 2
    assert r.status == S.MODE_NOT_ALLOWED and "fixel 2" in r.message


def test_classify_bad_inputs(harness_factory):
    h = harness_factory()
    assert h.classify((math.nan, 0.0, 0.0)).status == S.INVALID_WRENCH
    r = h.classify((1.0, 0.0, 0.0), out_of_plane=(1.0, 0.0, 0.0))
    assert r.status == S.INVALID_WRENCH and not r.matches
    h2 = harness_factory(wait_for_inputs=True)
    assert h2.classify((0.0, -1.0, 0.0)).status == S.NO_INPUTS
    # monitored modes cannot be wildcards (a topic per concrete mode)
    [res] = h.set_parameters(modes=["c*"])
    assert not res.successful
