# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``~/force_directions`` service over real DDS equals the core, with stamps, caching
per (snapshot, mode, point, exclusive), the request limits, stale inputs and status codes
for bad requests."""

from __future__ import annotations

import math

import pytest
from geometry_msgs.msg import Point

from wrenchcone_ros.core import NOMINAL, force_directions, load_scene
from wrenchcone_ros.core.modes import count_concrete_modes
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench, ForceDirections

from helpers.node_directions import PAWL, S, call

@pytest.fixture
def pawl(harness_factory):
    import os

    return harness_factory(scene_file=os.path.abspath(PAWL))


def test_service_equals_core(pawl):
    scene = load_scene(PAWL)
    for mode, point, exclusive in [("arr", None, False), ("arr", None, True),
                                   ("arr", (0.0075, 0.035), False), ("a**", None, False),
                                   ("s**", (0.06, 0.0), True), ("***", None, False)]:
        r = call(pawl, mode, point, exclusive)
        assert r.status == S.OK, r.message
        core = force_directions(scene, mode, point=point, exclusive=exclusive)
        assert [(iv.lo, iv.hi, iv.best, iv.margin) for iv in r.intervals] == [
            (iv.lo, iv.hi, iv.best, iv.margin) for iv in core]
        assert r.inputs_version >= 1 and r.frame_id
    r = call(pawl, "arr")
    assert r.intervals[0].lo == pytest.approx(math.atan2(-10, 3), abs=1e-12)
    assert r.intervals[0].hi == 0.0


def test_empty_request_means_the_centre_of_mass(pawl):
    # use_point defaults to false: a request with only a mode asks about the com, and a
    # point given without use_point is ignored
    scene = load_scene(PAWL)
    at_com = [(iv.lo, iv.hi) for iv in force_directions(scene, "arr")]
    at_origin = [(iv.lo, iv.hi) for iv in force_directions(scene, "arr", point=(0.0, 0.0))]
    assert at_com and at_com != at_origin
    cli = pawl.tester.create_client(ForceDirections, f"{pawl.ns}/wrenchcone/force_directions")
    assert cli.wait_for_service(timeout_sec=30.0)
    for req in (ForceDirections.Request(mode="arr"),
                ForceDirections.Request(mode="arr", point=Point(x=0.0, y=0.0))):
        r = pawl._call(cli, req)
        assert r.status == S.OK, r.message
        assert [(iv.lo, iv.hi) for iv in r.intervals] == at_com


def test_reply_names_the_inputs_it_used(pawl):
    v = pawl.get_cone("").inputs_version
    pawl.publish_pose(0.101, 0.2, 0.0, stamp=(12, 345))
    pawl.wait_version_above(v)
    fixels = [(0.167, 0.205), (0.12, 0.197), (0.15, 0.197)]
    v = pawl.get_cone("").inputs_version
    pawl.publish_fixels(fixels, stamp=(13, 7), radii=[f.radius for f in load_scene(PAWL).fixels])
    pawl.wait_version_above(v)
    r = call(pawl, "arr", exclusive=True)
    snap = pawl.node.snapshot
    assert r.status == S.OK, r.message
    assert (r.pose_stamp.sec, r.pose_stamp.nanosec) == (12, 345) == snap.pose_stamp
    assert (r.fixels_stamp.sec, r.fixels_stamp.nanosec) == (13, 7) == snap.fixels_stamp
    assert r.inputs_version == snap.version and r.frame_id == snap.frame_id
    assert r.inputs_age >= 0.0
    core = force_directions(load_scene(PAWL).with_pose(0.101, 0.2, 0.0), "arr",
                            exclusive=True)
    assert [(iv.lo, iv.hi) for iv in r.intervals] == [(iv.lo, iv.hi) for iv in core]


def test_request_limits(harness_factory):
    import os

    # the pawl's modes: 2 letters at the free fixel 1, 4 at each pin
    scene = load_scene(PAWL)
    assert count_concrete_modes("***", scene.in_contact) == 32
    h = harness_factory(scene_file=os.path.abspath(PAWL), max_concrete_modes=8,
                        max_mode_length=5)
    key_count = lambda: sum(1 for k in h.node.snapshot.answers  # noqa: E731
                            if isinstance(k, tuple) and k[0] == "force_directions")
    r = call(h, "a**")  # 16 concrete modes > 8: refused like check_wrench refuses it
    assert r.status == S.LIMIT_EXCEEDED and "max_concrete_modes" in r.message and not r.intervals
    cw = h._call(h.check_cli, CheckWrench.Request(mode="a**"))
    assert cw.status == Status.LIMIT_EXCEEDED == S.LIMIT_EXCEEDED
    r = call(h, "arr", exclusive=True)  # compares with all 32 modes of the scene > 8
    assert r.status == S.LIMIT_EXCEEDED and "32 modes" in r.message and not r.intervals
    r = call(h, "arrrrr")  # longer than max_mode_length
    assert r.status == S.LIMIT_EXCEEDED and "max_mode_length" in r.message
    assert key_count() == 0  # nothing computed, nothing cached
    r = call(h, "arr")  # within every limit
    assert r.status == S.OK and len(r.intervals) == 1
    r = call(h, "a*r")  # 4 concrete modes
    assert r.status == S.OK, r.message
    [res] = h.set_parameters(max_concrete_modes=32)
    assert res.successful, res.reason
    r = call(h, "arr", exclusive=True)
    assert r.status == S.OK, r.message
    core = force_directions(scene, "arr", exclusive=True)
    assert [(iv.lo, iv.hi) for iv in r.intervals] == [(iv.lo, iv.hi) for iv in core]


def test_stale_inputs_give_no_directions(harness_factory):
    import os
    import time

    h = harness_factory(scene_file=os.path.abspath(PAWL), input_timeout=1.0)
    v = h.get_cone("").inputs_version
    h.publish_pose(0.1, 0.2, 0.0, stamp=(21, 0))
    h.wait_version_above(v)
    r = call(h, "arr")
    if r.status == S.OK:  # fresh (unless this machine took over a second to answer)
        assert len(r.intervals) == 1 and r.inputs_age <= 1.0
    time.sleep(1.2)  # the pose is now older than input_timeout
    r = call(h, "arr")
    assert r.status == S.STALE_INPUTS and "input_timeout" in r.message
    assert "1 interval(s)" in r.message  # what the stale inputs would give
    assert not r.intervals  # fail-safe: no direction offered
    assert r.inputs_age > 1.0 and (r.pose_stamp.sec, r.pose_stamp.nanosec) == (21, 0)
    r = call(h, "ann")  # an infeasible mode from stale inputs is stale too
    assert r.status == S.STALE_INPUTS and not r.intervals


def test_cached_per_snapshot_and_recomputed_on_new_inputs(pawl):
    call(pawl, "arr", (0.0075, 0.035))
    snap = pawl.node.snapshot
    key = ("force_directions", "arr", (0.0075, 0.035), False, NOMINAL)
    first = snap.answers[key]
    call(pawl, "arr", (0.0075, 0.035))
    assert pawl.node.snapshot is snap and snap.answers[key] is first  # not recomputed
    v = snap.version
    pawl.publish_pose(0.102, 0.2, 0.0)
    pawl.wait_version_above(v)
    r = call(pawl, "arr", (0.0075, 0.035))
    core = force_directions(load_scene(PAWL).with_pose(0.102, 0.2, 0.0), "arr",
                            point=(0.0075, 0.035))
    assert r.inputs_version > v
    assert [(iv.lo, iv.hi) for iv in r.intervals] == [(iv.lo, iv.hi) for iv in core]
    assert r.intervals[0].lo != first.intervals[0].lo  # the interval moved with the pose


def test_statuses(pawl):
    r = call(pawl, "ann")
    assert r.status == S.MODE_INFEASIBLE and not r.intervals
    r = call(pawl, "nrr")
    assert r.status == S.MODE_NOT_ALLOWED and "fixel 1" in r.message
    r = call(pawl, "arx")
    assert r.status == S.INVALID_MODE and not r.intervals
    r = call(pawl, "arr", (0.0, float("nan")))
    assert r.status == S.INVALID_WRENCH and "finite" in r.message
    r = call(pawl, "arr", (0.0, 0.0))  # the foot's corner: a valid point, no direction
    assert r.status == S.OK and not r.intervals and "no force direction" in r.message
