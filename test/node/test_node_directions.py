"""The ``~/force_directions`` service over real DDS equals the core, with stamps, caching
per (snapshot, mode, point, exclusive) and status codes for bad requests."""

from __future__ import annotations

import math

import pytest

from wrenchcone_ros.core import force_directions, load_scene
from wrenchcone_ros.srv import ForceDirections

S = ForceDirections.Response
PAWL = "examples/pawl_polygon.yaml"


def call(h, mode, point=None, exclusive=False):
    req = ForceDirections.Request(mode=mode, exclusive=exclusive, at_com=point is None)
    if point is not None:
        req.point.x, req.point.y = (float(v) for v in point)
    cli = getattr(h, "_directions_cli", None)
    if cli is None:
        cli = h._directions_cli = h.tester.create_client(
            ForceDirections, f"{h.ns}/wrenchcone/force_directions")
        assert cli.wait_for_service(timeout_sec=30.0)
    return h._call(cli, req)


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
        assert list(r.lo) == [iv.lo for iv in core] and list(r.hi) == [iv.hi for iv in core]
        assert list(r.best) == [iv.best for iv in core]
        assert list(r.margin) == [iv.margin for iv in core]
        assert r.inputs_version >= 1 and r.frame_id
    r = call(pawl, "arr")
    assert r.lo[0] == pytest.approx(math.atan2(-10, 3), abs=1e-12) and r.hi[0] == 0.0


def test_cached_per_snapshot_and_recomputed_on_new_inputs(pawl):
    call(pawl, "arr", (0.0075, 0.035))
    snap = pawl.node.snapshot
    key = ("force_directions", "arr", (0.0075, 0.035), False)
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
    assert list(r.lo) == [iv.lo for iv in core] and list(r.hi) == [iv.hi for iv in core]
    assert r.lo[0] != first.intervals[0].lo  # the interval moved with the pose


def test_statuses(pawl):
    r = call(pawl, "ann")
    assert r.status == S.MODE_INFEASIBLE and not r.lo
    r = call(pawl, "nrr")
    assert r.status == S.MODE_NOT_ALLOWED and "fixel 1" in r.message
    r = call(pawl, "arx")
    assert r.status == S.INVALID_MODE and not r.lo
    r = call(pawl, "arr", (0.0, float("nan")))
    assert r.status == S.INVALID_WRENCH and "finite" in r.message
    r = call(pawl, "arr", (0.0, 0.0))  # the foot's corner: a valid point, no direction
    assert r.status == S.OK and not r.lo and "no force direction" in r.message
