# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""~/markers over DDS against the scene, worked by hand (positions, normals, friction-cone
edges from Table 2's physics), following pose updates, switched off by a parameter."""

from __future__ import annotations

import math

import numpy as np
import pytest
from visualization_msgs.msg import Marker, MarkerArray

from wrenchcone_ros.core.drawing import LETTER_COLOURS
from wrenchcone_ros.core.uncertainty import NOMINAL
from wrenchcone_ros.node.markers import ARROW_LENGTH, POINT_FIXEL_SIZE
from wrenchcone_ros.node.publishers import CONE_QOS

PAWL_VERTICES = [(0.0, 0.0), (0.06, 0.0), (0.06, 0.01), (0.015, 0.01), (0.015, 0.035),
                 (0.0, 0.035)]


def _subscribe(h):
    return h.subscribe(MarkerArray, "wrenchcone/markers", CONE_QOS)


def _by_ns(msg: MarkerArray) -> dict[str, dict[int, Marker]]:
    out: dict[str, dict[int, Marker]] = {}
    for m in msg.markers[1:]:
        out.setdefault(m.ns, {})[m.id] = m
    return out


def _xy(points) -> np.ndarray:
    return np.array([(p.x, p.y) for p in points])


def _rgb(m: Marker):
    return (round(m.color.r, 6), round(m.color.g, 6), round(m.color.b, 6))


def test_markers_show_the_default_scene(harness):
    msg = _subscribe(harness).wait_for(lambda m: len(m.markers) > 1, "markers")
    assert msg.markers[0].action == Marker.DELETEALL
    assert all(m.header.frame_id == "world" for m in msg.markers)
    ns = _by_ns(msg)
    outline = _xy(ns["workpiece"][0].points)
    assert np.allclose(np.hypot(outline[:, 0], outline[:, 1]), 1.0)  # the unit disc
    assert np.allclose(outline[0], outline[-1])
    # marker ids are the fixel numbers, 1-based as on every interface
    fixels = ns["fixels"]
    assert set(fixels) == {1, 2}
    assert np.allclose([fixels[1].pose.position.x, fixels[1].pose.position.y], (0.0, -1.0))
    assert np.allclose([fixels[2].pose.position.x, fixels[2].pose.position.y], (1.001, 0.0))
    assert fixels[1].scale.x == POINT_FIXEL_SIZE * 1.0  # point fixels, L = 1 m
    # only fixel 1 touches: its normal points up into the disc
    assert set(ns["normals"]) == {1}
    assert np.allclose(_xy(ns["normals"][1].points), [(0, -1), (0, -1 + ARROW_LENGTH)])
    # rolling on fixel 1 (mu 0.2): the whole cone (0, -1) + s (+-0.2, 1) / |.|, green
    assert set(ns["friction_cone/na"]) == {1}
    cone = ns["friction_cone/na"][1]
    assert cone.type == Marker.TRIANGLE_LIST and _rgb(cone) == LETTER_COLOURS["n"]
    d = ARROW_LENGTH / math.hypot(0.2, 1.0)
    got = _xy(cone.points)
    assert np.allclose(got[0], (0, -1))
    assert sorted(map(tuple, np.round(got[1:], 12))) == sorted(
        [(round(-0.2 * d, 12), round(-1 + d, 12)), (round(0.2 * d, 12), round(-1 + d, 12))])
    texts = {m.id: m.text for m in ns["letters/na"].values()}
    assert texts == {1: "na: 1n", 2: "na: 2a"}


def test_markers_follow_the_pose_and_show_sliding_edges(harness_factory):
    h = harness_factory(scene_file="examples/pawl_polygon.yaml", modes=["arr"])
    col = _subscribe(h)
    col.wait_for(lambda m: len(m.markers) > 1, "markers")
    h.publish_pose(0.095, 0.2, 0.0, stamp=(50, 60))  # slid 5 mm left along the pins
    msg = col.wait_for(lambda m: m.markers[-1].header.stamp.sec == 50, "markers, new pose")
    ns = _by_ns(msg)
    want = np.array(PAWL_VERTICES) + (0.095, 0.2)
    assert np.allclose(_xy(ns["workpiece"][0].points)[:-1], want)
    pins = {i: (m.pose.position.x, m.pose.position.y, m.scale.x) for i, m in
            ns["fixels"].items()}
    assert pins == {1: (0.167, 0.205, 0.006), 2: (0.12, 0.197, 0.006),
                    3: (0.15, 0.197, 0.006)}
    # sliding right (the pawl moves along +x over the pins): friction on the pawl along
    # -x, so the force edge is (-mu, 1) / |.| with mu = 0.3, purple
    L = h.node.snapshot.scene.length_scale
    for i in (2, 3):  # fixels 2 and 3
        edge = ns["friction_cone/arr"][1000 + i]
        a, b = _xy(edge.points)
        assert np.allclose((b - a) / (ARROW_LENGTH * L), np.array([-0.3, 1.0]) /
                           math.hypot(0.3, 1.0))
        assert _rgb(edge) == LETTER_COLOURS["r"]
    assert 1001 not in ns["friction_cone/arr"]  # fixel 1 is free: no cone, no edge
    assert 1 not in ns["friction_cone/arr"]
    # slid 5 mm left, the com (x = 0.115 m) is left of both pins (0.12, 0.15): a pull at
    # the com loads both pins while sliding only if it is horizontal (zero normal force),
    # so the fan collapses to the single direction 0
    assert np.allclose(_fan_angles(ns["force_fan/arr"][0], h), 0.0, atol=1e-9)
    a, b = _xy(ns["force_best/arr"][0].points)  # shown as its arrow
    assert np.allclose(a, h.node.snapshot.scene.com_world)
    assert math.atan2(b[1] - a[1], b[0] - a[0]) == pytest.approx(0.0, abs=1e-9)


def _fan_angles(fan: Marker, h) -> np.ndarray:
    """Directions (rad) of a force fan's rim points, seen from the com it is drawn at."""
    pts = _xy(fan.points).reshape(-1, 3, 2)
    com = h.node.snapshot.scene.com_world
    assert np.allclose(pts[:, 0], com)
    rim = pts[:, 1:].reshape(-1, 2) - com
    return np.arctan2(rim[:, 1], rim[:, 0])


def test_force_fan_of_the_pawl_at_its_start_pose(harness_factory):
    # the node's real force_directions at the com: a pull along the friction edge
    # (mu, -1) just balances sliding right, anything above the horizontal lifts the foot
    # off the pins: from atan2(-1, 0.3) to 0 (docs/tutorial_tray_tilting.md, section 1)
    h = harness_factory(scene_file="examples/pawl_polygon.yaml", modes=["arr"])
    msg = _subscribe(h).wait_for(lambda m: len(m.markers) > 1, "markers")
    ang = _fan_angles(_by_ns(msg)["force_fan/arr"][0], h)
    assert ang.min() == pytest.approx(math.atan2(-1.0, 0.3), abs=1e-9)
    assert ang.max() == pytest.approx(0.0, abs=1e-9)
    # the fan came from the snapshot's shared cache (its classifier's cones), the one the
    # ~/force_directions service answers from: the mode's cone is computed once
    snap = h.node.snapshot
    cached = snap.answers[("force_directions", "arr", None, False, NOMINAL)]
    assert [iv.lo for iv in cached.intervals] == [pytest.approx(math.atan2(-1.0, 0.3))]
    assert "arr" in snap.answers[("classifier",)]._cones


def test_markers_can_be_switched_off(harness):
    col = _subscribe(harness)
    col.wait_for(lambda m: len(m.markers) > 1, "markers")
    [res] = harness.set_parameters(publish_markers=False)
    assert res.successful, res.reason
    col.wait_for(lambda m: len(m.markers) == 1 and m.markers[0].action == Marker.DELETEALL,
                 "the markers cleared")
    v = harness.get_cone("").inputs_version
    harness.publish_pose(0.0, 0.0, 0.3, stamp=(77, 0))  # while off
    v = harness.wait_version_above(v)
    harness.publish_pose(0.0, 0.0, 0.4, stamp=(88, 0))
    harness.wait_version_above(v)
    [res] = harness.set_parameters(publish_markers=True)  # drawn again, newest inputs
    assert res.successful, res.reason
    col.wait_for(lambda m: len(m.markers) > 1 and m.markers[1].header.stamp.sec == 88,
                 "markers again")
    # one publisher, reliable and in order: anything drawn while off would have come first
    assert not any(m.markers[-1].header.stamp.sec == 77 for m in col.messages)


def test_force_fan_is_drawn_from_the_given_intervals():
    # scene_markers draws whatever intervals it is given: a fixed [-2, -1] rad here
    from collections import namedtuple

    from wrenchcone_ros.core import default_scene
    from wrenchcone_ros.node.markers import FAN_RADIUS, scene_markers
    from wrenchcone_ros.node.answers import monitored_answers
    from wrenchcone_ros.node.store import Snapshot

    Interval = namedtuple("Interval", "lo hi best margin")
    calls = []

    def directions(snapshot, mode):
        calls.append((snapshot, mode))
        return [Interval(-2.0, -1.0, -1.5, 0.1)]

    snap = Snapshot(1, default_scene(), 0, "", "world", None, None)
    ns = _by_ns(scene_markers(snap, ["na"], monitored_answers(snap, ["na"]), directions))
    assert calls == [(snap, "na")]
    pts = _xy(ns["force_fan/na"][0].points).reshape(-1, 3, 2)
    assert np.allclose(pts[:, 0], (0.0, 0.0))  # the com of the default disc
    rim = pts[:, 1:].reshape(-1, 2)
    assert np.allclose(np.hypot(rim[:, 0], rim[:, 1]), FAN_RADIUS)
    ang = np.arctan2(rim[:, 1], rim[:, 0])
    assert ang.min() == pytest.approx(-2.0) and ang.max() == pytest.approx(-1.0)
