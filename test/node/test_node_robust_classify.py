# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``~/classify_wrench`` and ``~/check_wrench``'s ``classify`` under the node's
``uncertainty.*`` parameters, over real DDS: every mode a wrench is consistent with for
some model (possible), flagged ``certain`` when it is for every model, checked
independently by the LP of core/lp_check.py at models of the friction box (the core's
classifier beside it where the LP cannot say more: margins, sampled models); robust
exclusivity in
``only_mode``; the nominal answer unchanged (every mode certain); the work refused over
``max_classify_nodes``; the robust cones computed once per snapshot."""

from __future__ import annotations

import itertools
import math
import os

import numpy as np
import pytest

from helpers.node_directions import PAWL
from wrenchcone_ros.core import Uncertainty, consistent_modes, load_scene
from wrenchcone_ros.core.lp_check import lp_consistent
from wrenchcone_ros.core.modes import expand_mode
from wrenchcone_msgs.msg import Status

S = Status
U = Uncertainty(friction=(0.2, 0.4))
#: The pawl's tilts (docs/tutorial_tray_tilting.md): the nominal recommendation, and the
#: best tilt for every mu in [0.2, 0.4].
NOMINAL_TILT, ROBUST_TILT = math.radians(-68.71), math.radians(-65.21)


def tilt_wrench(scene, phi: float) -> tuple[float, float, float]:
    """The load m g of a tray tilted so that it points along phi (fixture frame)."""
    w = scene.workpiece.mass * 9.81
    return (math.cos(phi) * w, math.sin(phi) * w, 0.0)


def model(scene, mus: dict[int, float]):
    """The scene with fixel i's friction coefficient mus[i] (one model of the box)."""
    d = scene.to_dict()
    for i, mu in mus.items():
        d["fixels"][i]["friction"] = float(mu)
    return load_scene(d)


def lp_models(scene, lo: float, hi: float, k: int = 3) -> list:
    """Models of the friction box at the pins in contact: k values per fixel (the
    vertices and interior points), every combination."""
    pins = [i for i, c in enumerate(scene.in_contact) if c]
    grid = np.linspace(lo, hi, k)
    return [model(scene, dict(zip(pins, mus))) for mus in itertools.product(grid,
                                                                            repeat=len(pins))]


@pytest.fixture
def pawl(harness_factory):
    return harness_factory(scene_file=os.path.abspath(PAWL))


def _robust(h):
    results = h.set_parameters(uncertainty__friction=[0.2, 0.4])
    assert all(x.successful for x in results), [x.reason for x in results]


def test_classify_wrench_answers_for_every_and_some_model(pawl):
    """The node's answer against the LP of core/lp_check.py (Newton-Euler and Coulomb
    friction written out, not the cones) at the friction box's vertices and centre: a
    friction interval is handled exactly, and "for every model" of a box is decided at
    its vertices (docs/theory.md, "Uncertain models"), so a mode is certain iff the LP
    says consistent at every one of these models, possible (listed) iff at some, and no
    other mode is consistent at any; certain modes come first, then by margin."""
    scene = load_scene(PAWL)
    models = lp_models(scene, 0.2, 0.4)
    _robust(pawl)
    for phi in (NOMINAL_TILT, ROBUST_TILT):
        g = tilt_wrench(scene, phi)
        r = pawl.classify(g)
        assert r.status == S.OK, r.message
        lp = {mode: [lp_consistent(s, mode, g) for s in models]
              for mode in expand_mode("***", scene.in_contact)}
        assert all(x.decided for xs in lp.values() for x in xs)
        possible = {mode for mode, xs in lp.items() if any(x.consistent for x in xs)}
        certain = {mode for mode, xs in lp.items() if all(x.consistent for x in xs)}
        assert {m.mode for m in r.matches} == possible
        assert {m.mode for m in r.matches if m.certain} == certain
        for m in r.matches:
            assert m.margin >= 0 and (m.margin_all >= 0) == m.certain
        key = [(not m.certain, -m.margin) for m in r.matches]
        assert key == sorted(key)
        assert r.uncertainty == "friction [0.2, 0.4]" and r.guarantee == "exact"
        assert "for some model of friction [0.2, 0.4]" in r.message
    # the nominal recommendation: arr for some model, not for every one; the pawl may
    # also stick (snn) for some mu
    r = pawl.classify(tilt_wrench(scene, NOMINAL_TILT))
    first = r.matches[0]
    assert first.mode == "arr" and not first.certain and first.margin_all < 0 < first.margin
    assert "snn" in {m.mode for m in r.matches}
    # the robust best tilt: arr for every model, and no other mode for any model
    r = pawl.classify(tilt_wrench(scene, ROBUST_TILT))
    assert [(m.mode, m.certain) for m in r.matches] == [("arr", True)]
    assert r.matches[0].margin_all > 0


@pytest.mark.slow
def test_the_robust_answers_agree_with_an_lp_at_models_of_the_box():
    """Independent of the robust engine: the LP check at the friction box's vertices and
    centre (mu of each pin in {0.2, 0.3, 0.4})."""
    scene = load_scene(PAWL)
    models = lp_models(scene, 0.2, 0.4)
    at_nominal = tilt_wrench(scene, NOMINAL_TILT)
    arr = [lp_consistent(s, "arr", at_nominal).consistent for s in models]
    assert any(arr) and not all(arr)  # possible, not certain
    assert any(lp_consistent(s, "snn", at_nominal).consistent for s in models)
    at_robust = tilt_wrench(scene, ROBUST_TILT)
    assert all(lp_consistent(s, "arr", at_robust).consistent for s in models)
    for mode in expand_mode("***", scene.in_contact):
        if mode != "arr":
            assert not any(lp_consistent(s, mode, at_robust).consistent for s in models), mode


def test_check_wrench_classify_is_robust(pawl):
    scene = load_scene(PAWL)
    _robust(pawl)
    # the answer, not the request's wall-clock cap (max_request_time, 0: none), is what
    # this test checks: on a busy machine the robust classification took longer than it
    assert all(x.successful for x in pawl.set_parameters(max_request_time=0.0))
    g = tilt_wrench(scene, NOMINAL_TILT)
    r = pawl.check("arr", g, classify=True)
    assert r.status == S.OK and not r.consistent and not r.only_mode, r.message
    # the other modes possible for some model: the LP's at the friction box's models
    models = lp_models(scene, 0.2, 0.4)
    lp = {mode for mode in expand_mode("***", scene.in_contact) if mode != "arr"
          and any(lp_consistent(s, mode, g).consistent for s in models)}
    assert {m.mode for m in r.others} == lp and "snn" in {m.mode for m in r.others}
    assert min(m.margin for m in r.others) >= 0
    assert "for every model of friction [0.2, 0.4] (guarantee exact)" in r.message
    assert "others: for some model" in r.message and "nominal" not in r.message
    r = pawl.check("arr", tilt_wrench(scene, ROBUST_TILT), classify=True)
    assert r.status == S.OK and r.consistent and r.only_mode, r.message  # robust exclusivity
    assert list(r.others) == []
    r = pawl.check("snn", g, classify=True)  # another requested mode: arr is among the others
    assert not r.consistent and not r.only_mode and r.others[0].mode == "arr"


def test_the_nominal_answer_is_certain_for_its_one_model(pawl):
    scene = load_scene(PAWL)
    for phi in (NOMINAL_TILT, ROBUST_TILT, 0.3, -2.0):
        g = tilt_wrench(scene, phi)
        r = pawl.classify(g)
        core = consistent_modes(scene, g)
        assert r.status == S.OK and r.message in ("", "the wrench is consistent with no "
                                                      "mode of the current scene")
        assert [m.mode for m in r.matches] == [m.mode for m in core]
        assert [m.margin for m in r.matches] == pytest.approx([m.margin for m in core],
                                                              abs=1e-12)
        assert all(m.certain and m.margin_all == m.margin for m in r.matches)
        assert r.uncertainty == "" and r.guarantee == ""
    r = pawl.check("arr", tilt_wrench(scene, NOMINAL_TILT), classify=True)
    assert r.consistent and r.only_mode and r.message == ""  # nominally: arr alone


def _robust_sets(snap):
    """The robust classification sets the snapshot's classifier holds (None: not
    computed)."""
    clf = snap.answers.get(("classifier",))
    return None if clf is None else clf._robust_sets


def test_the_robust_cones_are_computed_once_per_snapshot(pawl):
    scene = load_scene(PAWL)
    _robust(pawl)
    pawl.classify(tilt_wrench(scene, NOMINAL_TILT))
    snap = pawl.node.snapshot
    cones = _robust_sets(snap)
    assert cones is not None
    r = pawl.classify(tilt_wrench(scene, ROBUST_TILT))  # another wrench, the same cones
    assert pawl.node.snapshot is snap and _robust_sets(snap) is cones
    assert [m.mode for m in r.matches] == ["arr"]
    pawl.check("arr", tilt_wrench(scene, 0.3), classify=True)  # check_wrench shares them
    assert _robust_sets(snap) is cones
    v = snap.version
    pawl.publish_pose(0.101, 0.2, 0.0)  # new inputs: a new snapshot computes its own
    pawl.wait_version_above(v)
    assert pawl.classify(tilt_wrench(scene, ROBUST_TILT)).inputs_version > v
    assert _robust_sets(pawl.node.snapshot) is not cones


def test_the_work_is_held_to_max_classify_nodes(harness_factory, tmp_path):
    """The robust classification computes two cones of every mode of the scene for every
    model (no pruning): modes x models count against max_classify_nodes, refused before
    anything is computed."""
    import yaml

    rim = {"workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.0, 0.0],
                         "shape": {"type": "disc", "radius": 1.0}},
           "friction": 0.3,
           "fixels": [[math.cos(2 * math.pi * k / 8), math.sin(2 * math.pi * k / 8)]
                      for k in range(8)]}
    path = tmp_path / "rim.yaml"
    path.write_text(yaml.safe_dump(rim))
    h = harness_factory(scene_file=str(path), uncertainty__friction=[0.2, 0.4])
    r = h.classify((0.0, 1.0, 0.0))
    assert r.status == S.LIMIT_EXCEEDED and not r.matches
    assert "65536 modes" in r.message and "max_classify_nodes (2000)" in r.message
    c = h.check("nnnnnnnn", (0.0, 1.0, 0.0), classify=True)
    assert c.status == S.LIMIT_EXCEEDED and not c.consistent and not c.others
    assert _robust_sets(h.node.snapshot) is None  # nothing computed
    nominal = h.check("nnnnnnnn", (0.0, 1.0, 0.0))  # the cone itself is still answered
    assert nominal.status == S.OK, nominal.message
    # the pawl with a 1 mm centre-of-mass disc: 32 modes x 220 sampled models
    p = harness_factory(scene_file=os.path.abspath(PAWL), uncertainty__friction=[0.2, 0.4],
                        uncertainty__com_radius=1e-3)
    scene = load_scene(PAWL)
    g = tilt_wrench(scene, NOMINAL_TILT)
    r = p.classify(g)
    assert r.status == S.LIMIT_EXCEEDED and "32 modes" in r.message
    assert "220 sampled models" in r.message and "7040" in r.message
    [res] = p.set_parameters(max_classify_nodes=7040)
    assert res.successful, res.reason
    r = p.classify(g)
    assert r.status == S.OK, r.message
    u = Uncertainty(friction=(0.2, 0.4), com_radius=1e-3)
    core = consistent_modes(scene, g, uncertainty=u)
    assert [(m.mode, m.certain) for m in r.matches] == [(m.mode, m.certain) for m in core]
    assert r.guarantee == "scenario(eps=0.05, beta=0.001, N=220)" == str(core[0].guarantee)
