# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node over real DDS: answers equal the core's, F is published, inputs and parameters
take effect, and every bad input gets a status, never a crash."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from helpers.node_harness import DEADLINE_S, no_cone, published_rows, same_rows

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.core import default_scene, enumerate_modes, load_scene, wrench_cone
from wrenchcone_msgs.msg import Status

S = Status
RNG_WRENCHES = np.random.default_rng(20261121).normal(size=(40, 3))
# the generators of the paper's worked example (docs/theory.md): on the boundary; plus
# clearly inside/outside ones
PAPER_G = [(1.0, 0.0, -1.0), (-0.2, -1.0, -0.2), (0.2, -1.0, 0.2)]
PINNED = {  # three rolling contacts pin the disc; a fourth fixel is free
    "workpiece": {"mass": 1.0, "inertia": 1.0, "shape": {"type": "disc", "radius": 1.0}},
    "friction": 0.2,
    "fixels": [[0.0, -1.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.5]],
    "modes": ["nnna"],
}


def assert_matches_core(resp, cone, g):
    assert resp.status == S.OK, resp.message
    assert resp.consistent == cone.contains(g)
    assert resp.margin == pytest.approx(cone.margin(g), abs=1e-12)


def test_default_scene_answers_equal_core(harness):
    cone = wrench_cone(default_scene(), "na")
    for g in [*PAPER_G, (0.1, -1.0, 0.0), (0.0, 1.0, 0.0), *RNG_WRENCHES]:
        assert_matches_core(harness.check("na", g), cone, g)
    # some inside, some outside: the comparison is not vacuous
    answers = {harness.check("na", g).consistent for g in RNG_WRENCHES}
    assert answers == {True, False}
    r = harness.check("na", (0.1, -1.0, 0.0))
    assert r.consistent and r.margin > 0 and r.frame_id == "world" and r.inputs_version >= 1


def test_get_cone_equals_core(harness):
    cone = wrench_cone(default_scene(), "na")
    r = harness.get_cone("na")
    assert r.status == S.OK and r.feasible
    assert same_rows(conv.rows_from_flat(r.inequalities), cone.F)
    assert same_rows(conv.rows_from_flat(r.equalities), cone.equalities)
    assert same_rows(conv.rows_from_flat(r.generators), cone.G)
    assert same_rows(conv.rows_from_flat(r.lineality), cone.lineality)
    assert r.length_scale == cone.length_scale


def test_published_F_equals_core(harness):
    cone = wrench_cone(default_scene(), "na")
    msg = harness.subscribe_cone("na").wait_for(lambda m: True, "a cone on ~/cone/na")
    F, E, marker = published_rows(msg)
    assert marker is None
    assert same_rows(F, cone.F) and same_rows(E, cone.equalities)


def test_every_mode_of_the_default_scene(harness):
    scene = default_scene()
    for mode in enumerate_modes(scene.in_contact):
        cone = wrench_cone(scene, mode)
        r = harness.get_cone(mode)
        assert r.status == (S.OK if cone.feasible else S.MODE_INFEASIBLE), r.message
        if cone.feasible:
            assert same_rows(conv.rows_from_flat(r.inequalities), cone.F)


def test_pose_update_changes_published_F(harness_factory):
    # com off the disc centre: rotating the disc keeps both contacts but moves the com
    h = harness_factory(workpiece__com=[0.3, 0.0])
    col = h.subscribe_cone("na")
    base = load_scene({**default_scene().to_dict(),
                       "workpiece": {**default_scene().to_dict()["workpiece"],
                                     "com": [0.3, 0.0]}})
    first = col.wait_for(lambda m: True, "the initial cone")
    assert same_rows(published_rows(first)[0], wrench_cone(base, "na").F)
    h.publish_pose(0.0, 0.0, 0.7, stamp=(12, 34))
    expected = wrench_cone(base.with_pose(0.0, 0.0, 0.7), "na").F
    assert not same_rows(expected, wrench_cone(base, "na").F)
    col.wait_for(lambda m: same_rows(published_rows(m)[0], expected), "F after the pose")
    r = h.check("na", (0.1, -1.0, 0.0))
    assert (r.pose_stamp.sec, r.pose_stamp.nanosec) == (12, 34)
    cone = wrench_cone(base.with_pose(0.0, 0.0, 0.7), "na")
    assert_matches_core(r, cone, (0.1, -1.0, 0.0))


def test_pose_that_breaks_contact_invalidates_mode_once(harness):
    col = harness.subscribe_cone("na")
    col.wait_for(lambda m: published_rows(m)[2] is None, "the initial cone")
    harness.publish_pose(0.0, 0.01, 0.0)  # lifts the disc off fixel 1
    col.wait_for(lambda m: no_cone(m, S.MODE_NOT_ALLOWED), "MODE_NOT_ALLOWED, no rows")
    r = harness.check("na", (0.0, 1.0, 0.0))
    assert r.status == S.MODE_NOT_ALLOWED and not r.consistent
    assert "fixel 1" in r.message
    assert harness.check("aa", (0.0, 1.0, 0.0)).status == S.OK
    harness.publish_pose(0.0, 0.0, 0.0)  # back in contact
    col.wait_for(lambda m: published_rows(m)[2] is None and published_rows(m)[0].size,
                 "the cone again")


def test_fixel_update_changes_published_F(harness):
    col = harness.subscribe_cone("na")
    col.wait_for(lambda m: True, "the initial cone")
    a = 0.5
    fixels = [(math.sin(a), -math.cos(a)), (1.5, 0.0)]
    harness.publish_fixels(fixels, stamp=(5, 6))
    scene = default_scene().with_fixels(fixels)
    expected = wrench_cone(scene, "na")
    assert not same_rows(expected.F, wrench_cone(default_scene(), "na").F)
    col.wait_for(lambda m: same_rows(published_rows(m)[0], expected.F), "F after fixels")
    r = harness.check("na", (0.0, 1.0, 0.0))
    assert (r.fixels_stamp.sec, r.fixels_stamp.nanosec) == (5, 6)
    assert_matches_core(r, expected, (0.0, 1.0, 0.0))
    # three fixels now: a two-letter mode is a fixel-count mismatch, with a status
    harness.publish_fixels([(0.0, -1.0), (1.001, 0.0), (-1.5, 0.0)])
    col.wait_for(lambda m: no_cone(m, S.INVALID_MODE), "INVALID_MODE (3 fixels)")
    r = harness.check("na", (0.0, 1.0, 0.0))
    assert r.status == S.INVALID_MODE and "3 fixel" in r.message
    three = default_scene().with_fixels([(0.0, -1.0), (1.001, 0.0), (-1.5, 0.0)])
    assert wrench_cone(three, "nas").feasible and not wrench_cone(three, "naa").feasible
    assert_matches_core(harness.check("nas", (0.0, 1.0, 0.0)), wrench_cone(three, "nas"),
                        (0.0, 1.0, 0.0))
    assert harness.check("naa", (0.0, 1.0, 0.0)).status == S.MODE_INFEASIBLE


def test_parameter_changes_take_effect(harness):
    col = harness.subscribe_cone("na")
    col.wait_for(lambda m: True, "the initial cone")
    [res] = harness.set_parameters(friction=0.5)
    assert res.successful, res.reason
    scene = load_scene({**default_scene().to_dict(), "friction": 0.5})
    expected = wrench_cone(scene, "na")
    col.wait_for(lambda m: same_rows(published_rows(m)[0], expected.F), "F with mu = 0.5")
    r = harness.get_cone("na")
    assert same_rows(conv.rows_from_flat(r.inequalities), expected.F)
    # monitored modes: a new topic appears, latched
    [res] = harness.set_parameters(modes=["na", "sa"])
    assert res.successful, res.reason
    msg = harness.subscribe_cone("sa").wait_for(lambda m: True, "a cone on ~/cone/sa")
    assert same_rows(published_rows(msg)[0], wrench_cone(scene, "sa").F)
    # workpiece parameters, set together atomically from one request
    v = harness.get_cone("na").inputs_version
    res = harness.set_parameters_atomically({"workpiece.mass": 2.0, "workpiece.inertia": 0.1})
    assert res.successful, res.reason
    assert harness.get_cone("na").inputs_version == v + 1  # one snapshot for both
    d = scene.to_dict()
    d["workpiece"].update(mass=2.0, inertia=0.1)
    expected = wrench_cone(load_scene(d), "na")
    col.wait_for(lambda m: same_rows(published_rows(m)[0], expected.F), "F after mass")


@pytest.mark.parametrize("name,value,words", [
    ("friction", -0.1, "friction"),
    ("friction", math.nan, "friction"),
    ("workpiece.mass", 0.0, "mass"),
    ("workpiece.shape", "triangle", "disc"),
    ("workpiece.com", [1.0], "com"),
    ("contact_tolerance", 0.0, "contact_tolerance"),
    ("modes", ["na", "nx"], "nx"),
    ("fixture_frame", "", "fixture_frame"),
    ("scene_file", "other.yaml", ""),  # read-only at run time
    ("friction", "high", ""),  # wrong type
])
def test_invalid_parameters_refused_with_reason(harness, name, value, words):
    before = harness.get_cone("na")
    [res] = harness.set_parameters(**{name: value})
    assert not res.successful and words in res.reason
    after = harness.get_cone("na")
    assert after.status == S.OK and after.inputs_version == before.inputs_version


def test_polygon_parameters(harness_factory):
    h = harness_factory(workpiece__shape="polygon",
                        workpiece__vertices=[-1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0])
    scene = load_scene({**default_scene().to_dict(), "workpiece": {
        "mass": 1.0, "inertia": 1.0,
        "shape": {"type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}}})
    r = h.get_cone("na")
    assert r.status == S.OK, r.message
    assert same_rows(conv.rows_from_flat(r.inequalities), wrench_cone(scene, "na").F)
    [res] = h.set_parameters(workpiece__vertices=[0.0, 0.0, 1.0, 0.0])
    assert not res.successful and "vertices" in res.reason
    # atomic: one bad value refuses the whole request
    res = h.set_parameters_atomically({"friction": 0.4, "workpiece.mass": -1.0})
    assert not res.successful and "mass" in res.reason
    assert h.node.get_parameter("friction").value == 0.2


def test_bad_requests_get_a_status(harness):
    cases = [
        ("", (1.0, 0.0, 0.0), (0, 0, 0), S.INVALID_MODE),
        ("nx", (1.0, 0.0, 0.0), (0, 0, 0), S.INVALID_MODE),
        ("NA", (1.0, 0.0, 0.0), (0, 0, 0), S.INVALID_MODE),
        ("n", (1.0, 0.0, 0.0), (0, 0, 0), S.INVALID_MODE),
        ("nnn", (1.0, 0.0, 0.0), (0, 0, 0), S.INVALID_MODE),
        ("aa", (1.0, 0.0, 0.0), (0, 0, 0), S.MODE_NOT_ALLOWED),
        ("nn", (1.0, 0.0, 0.0), (0, 0, 0), S.MODE_NOT_ALLOWED),
        ("na", (math.nan, 0.0, 0.0), (0, 0, 0), S.INVALID_WRENCH),
        ("na", (math.inf, 0.0, 0.0), (0, 0, 0), S.INVALID_WRENCH),
        ("na", (1.0, 0.0, 0.0), (0.5, 0, 0), S.INVALID_WRENCH),
        ("na", (1.0, 0.0, 0.0), (0, 0, 1e-3), S.INVALID_WRENCH),
        ("na", (0.0, 0.0, 0.0), (0, 1e-9, 0), S.INVALID_WRENCH),
    ]
    for mode, g, oop, status in cases:
        r = harness.check(mode, g, oop)
        assert r.status == status, (mode, g, oop, r.message)
        assert not r.consistent and r.margin == -1.0 and r.message
        c = harness.get_cone(mode)
        if status != S.INVALID_WRENCH:
            assert c.status == status and not c.feasible and not c.inequalities
    # the node is still serving
    assert harness.check("na", (0.1, -1.0, 0.0)).consistent


def test_infeasible_mode_never_consistent_nor_anything_goes(harness_factory, tmp_path):
    scene = load_scene(PINNED)
    bad = [m for m in enumerate_modes(scene.in_contact) if not wrench_cone(scene, m).feasible]
    assert "nnna" in bad  # three rolling contacts pin the disc
    path = tmp_path / "pinned.yaml"
    import yaml

    path.write_text(yaml.safe_dump(PINNED))
    h = harness_factory(scene_file=str(path))
    msg = h.subscribe_cone("nnna").wait_for(lambda m: True, "the nnna cone message")
    assert no_cone(msg, S.MODE_INFEASIBLE)
    for g in [(0.0, 0.0, 0.0), *RNG_WRENCHES[:10]]:
        r = h.check("nnna", g)
        assert r.status == S.MODE_INFEASIBLE and not r.consistent and r.margin == -1.0
    c = h.get_cone("nnna")
    assert c.status == S.MODE_INFEASIBLE and not c.feasible
    assert not c.inequalities and not c.equalities and "infeasible" in c.message


def test_bad_topic_messages_are_refused_and_node_keeps_serving(harness):
    r0 = harness.check("na", (0.1, -1.0, 0.0))
    v0 = r0.inputs_version
    tilt = (math.sin(0.05), 0.0, 0.0, math.cos(0.05))
    harness.publish_pose(0.0, 0.0, 0.0, quaternion=tilt)
    harness.publish_pose(0.0, 0.0, 0.0, quaternion=(0.0, 0.0, 0.0, 0.0))
    harness.publish_pose(math.nan, 0.0, 0.0)
    harness.publish_pose(0.0, 0.0, 0.0, frame="map")
    harness.publish_fixels([(0.0, -1.0), (1.001, 0.0)], frame="")
    harness.publish_fixels([])
    harness.publish_fixels([(0.0, math.inf), (1.0, 0.0)])
    # a valid pose after the bad ones: the answers come from it and from the fixture the
    # node had (how many snapshots lie between depends on when the node took the
    # messages, on a busy machine one by one: not counted here)
    harness.publish_pose(0.0, 0.0, 0.0, stamp=(99, 0))
    deadline = time.monotonic() + DEADLINE_S
    r = harness.check("na", (0.1, -1.0, 0.0))
    while r.pose_stamp.sec != 99 and time.monotonic() < deadline:
        harness.wait_version_above(r.inputs_version)
        r = harness.check("na", (0.1, -1.0, 0.0))
    assert r.pose_stamp.sec == 99 and r.inputs_version > v0
    assert (r.fixels_stamp.sec, r.fixels_stamp.nanosec) == (r0.fixels_stamp.sec,
                                                            r0.fixels_stamp.nanosec)
    assert r.status == S.OK and r.consistent and r.margin == r0.margin


def test_penetrating_fixel_is_a_scene_error_then_recovers(harness):
    col = harness.subscribe_cone("na")
    col.wait_for(lambda m: published_rows(m)[2] is None, "the initial cone")
    harness.publish_fixels([(0.0, -0.5), (1.001, 0.0)])  # inside the disc
    col.wait_for(lambda m: no_cone(m, S.SCENE_ERROR), "SCENE_ERROR, no rows")
    r = harness.check("na", (0.1, -1.0, 0.0))
    assert r.status == S.SCENE_ERROR and "penetrates" in r.message and not r.consistent
    seen = len(col.messages)  # the cone published before the error matches too
    harness.publish_fixels([(0.0, -1.0), (1.001, 0.0)])
    col.wait_for(lambda m: published_rows(m)[2] is None and published_rows(m)[0].size,
                 "the cone again", since=seen)
    assert harness.check("na", (0.1, -1.0, 0.0)).consistent


def test_wait_for_inputs(harness_factory):
    h = harness_factory(wait_for_inputs=True)
    col = h.subscribe_cone("na")
    col.wait_for(lambda m: no_cone(m, S.NO_INPUTS), "NO_INPUTS, no rows")
    r = h.check("na", (0.1, -1.0, 0.0))
    assert r.status == S.NO_INPUTS and "workpiece_pose" in r.message and not r.consistent
    h.publish_pose(0.0, 0.0, 0.0)
    v = h.wait_version_above(r.inputs_version)
    r = h.check("na", (0.1, -1.0, 0.0))
    assert r.status == S.NO_INPUTS and "fixels" in r.message
    h.publish_fixels([(0.0, -1.0), (1.001, 0.0)])
    h.wait_version_above(v)
    r = h.check("na", (0.1, -1.0, 0.0))
    assert r.status == S.OK and r.consistent
    col.wait_for(lambda m: published_rows(m)[2] is None, "the cone")


def test_answers_are_cached_per_snapshot(harness):
    snap = harness.node.snapshot
    harness.check("na", (0.1, -1.0, 0.0))
    harness.check("ns", (0.1, -1.0, 0.0))
    assert set(snap.answers) >= {"na", "ns"}
    cone = snap.answers["na"].cone
    harness.check("na", (0.2, -1.0, 0.0))
    assert snap.answers["na"].cone is cone  # not recomputed
    assert "la" not in snap.answers  # nothing computed for modes nobody asked for


@pytest.mark.slow
def test_bad_scene_file_at_start_is_one_clear_error(tmp_path):
    import os
    import subprocess
    import sys

    bad = tmp_path / "bad.yaml"
    bad.write_text("workpiece: {mass: -1}\n")
    for path in (str(tmp_path / "missing.yaml"), str(bad)):
        out = subprocess.run(
            [sys.executable, "-m", "wrenchcone_ros.node", "--ros-args", "-p",
             f"scene_file:={path}"], capture_output=True, text=True, cwd=tmp_path,
            env=dict(os.environ), timeout=120, check=False)
        assert out.returncode == 2, out.stderr
        assert "scene_file" in out.stderr and "Traceback" not in out.stderr


def test_every_answer_matches_the_inputs_it_names(harness_factory):
    """Poses and fixels stream in while check_wrench is called: each reply's stamps name
    the pose and fixels it used, and the reply equals the core's answer for exactly
    those inputs (never a pose from one update with fixels from another). The last
    reply must use the newest pose: pose_reuse_window 0 (by default a reply may use a
    pose up to 5 ms older than the newest, and the poses here come faster)."""
    h = harness_factory(workpiece__com=[0.3, 0.0], pose_reuse_window=0.0)
    base = load_scene({**default_scene().to_dict(),
                       "workpiece": {**default_scene().to_dict()["workpiece"],
                                     "com": [0.3, 0.0]}})
    fixel_sets = {0: [(0.0, -1.0), (1.001, 0.0)],
                  1: [(math.sin(0.4), -math.cos(0.4)), (1.001, 0.0)]}
    g = (0.05, -1.0, 0.02)
    replies = []
    for i in range(1, 25):
        h.publish_pose(0.0, 0.0, 0.05 * i, stamp=(i, 0))
        replies.append(h.check("na", g))
        h.publish_fixels(fixel_sets[i % 2], stamp=(1000 + i, 0))
        replies.append(h.check("na", g))
    h.publish_pose(0.0, 0.0, 0.0, stamp=(99, 0))
    h.wait_version_above(replies[-1].inputs_version)
    replies.append(h.check("na", g))
    assert replies[-1].pose_stamp.sec == 99
    cache = {}
    for r in replies:
        assert r.status == S.OK, r.message
        key = (r.pose_stamp.sec, r.fixels_stamp.sec)
        if key not in cache:
            scene = base
            if r.pose_stamp.sec:
                th = 0.0 if r.pose_stamp.sec == 99 else 0.05 * r.pose_stamp.sec
                scene = scene.with_pose(0.0, 0.0, th)
            if r.fixels_stamp.sec:
                scene = scene.with_fixels(fixel_sets[(r.fixels_stamp.sec - 1000) % 2])
            cache[key] = wrench_cone(scene, "na")
        cone = cache[key]
        assert r.consistent == cone.contains(g)
        assert r.margin == pytest.approx(cone.margin(g), abs=1e-12)
    versions = [r.inputs_version for r in replies]
    assert versions == sorted(versions)
    assert len(cache) > 3  # the replies did see several input combinations


def test_a_workpiece_outside_the_verified_range_is_logged_once(harness):
    """The core's numerics caveat (I/(m L^2) outside the verified range) reaches the user
    as one warning on /rosout when such a workpiece is set, and the node goes on
    answering; a workpiece beyond the accepted range is refused, naming it."""
    from rcl_interfaces.msg import Log
    from rclpy.qos import DurabilityPolicy, QoSProfile

    logs: list[str] = []
    harness.tester.create_subscription(
        Log, "/rosout", lambda m: logs.append(m.msg) if m.name.endswith("wrenchcone")
        else None, QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    # beyond ACCEPTED_INERTIA_RATIO: refused with the range, the scene unchanged
    res = harness.set_parameters_atomically({"workpiece.mass": 1e9})
    assert not res.successful and "[1e-08, 1e+06]" in res.reason, res.reason
    res = harness.set_parameters_atomically({"workpiece.mass": 1e5})
    assert res.successful, res.reason
    assert harness.check("na", (1.0, 0.0, -1.0)).status == Status.OK
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline and not any("verified range" in m for m in logs):
        time.sleep(0.05)
    caveats = [m for m in logs if "verified range" in m]
    assert len(caveats) == 1 and "I/(m L^2) = " in caveats[0], logs
