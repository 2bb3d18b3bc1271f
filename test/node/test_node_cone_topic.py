# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The typed cone topic ~/cone/<mode> (wrenchcone_msgs/msg/WrenchCone) over DDS: its header
stamp is the newest input's, its inputs_version is the snapshot's that the services name,
its rows are the core's cone of exactly those inputs."""

from __future__ import annotations

import math

from helpers.node_harness import same_rows

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.core import default_scene, load_scene, wrench_cone
from wrenchcone_msgs.msg import Status


def _stamp(m):
    return (m.header.stamp.sec, m.header.stamp.nanosec)


def test_cone_message_names_its_inputs(harness_factory):
    h = harness_factory(workpiece__com=[0.3, 0.0])
    col = h.subscribe_cone("na")
    first = col.wait_for(lambda m: True, "the initial cone")
    # the scene file's own pose and fixels: no input stamp yet
    assert _stamp(first) == (0, 0) and first.header.frame_id == "world"
    assert first.inputs_version == h.get_cone("na").inputs_version
    assert first.status == Status.OK and first.feasible and first.message == ""
    assert first.uncertainty == "" and first.guarantee == ""  # the nominal model
    d = default_scene().to_dict()
    d["workpiece"]["com"] = [0.3, 0.0]
    base = load_scene(d)

    a = 0.4
    fixels = [(math.sin(a), -math.cos(a)), (1.5, 0.0)]
    steps = [  # (what to publish, the newest stamp expected in the header)
        (lambda: h.publish_fixels(fixels, stamp=(100, 5)), (100, 5)),
        (lambda: h.publish_pose(0.0, 0.0, 0.3, stamp=(90, 0)), (100, 5)),  # older pose
        (lambda: h.publish_pose(0.0, 0.0, 0.6, stamp=(200, 7)), (200, 7)),
    ]
    scene, version = base.with_fixels(fixels), first.inputs_version
    poses = iter([(0.0, 0.0, 0.0), (0.0, 0.0, 0.3), (0.0, 0.0, 0.6)])
    for publish, stamp in steps:
        publish()
        scene = scene.with_pose(*next(poses))
        msg = col.wait_for(lambda m, v=version: m.inputs_version > v, "a new cone")
        assert _stamp(msg) == stamp
        reply = h.get_cone("na")  # no input in between: the same snapshot
        assert msg.inputs_version == reply.inputs_version
        assert stamp == max((reply.pose_stamp.sec, reply.pose_stamp.nanosec),
                            (reply.fixels_stamp.sec, reply.fixels_stamp.nanosec))
        cone = wrench_cone(scene, "na")
        F, E = conv.message_rows(msg)
        assert same_rows(F, cone.F) and same_rows(E, cone.equalities)
        assert same_rows(conv.rows_from_flat(msg.generators), cone.G)
        assert msg.length_scale == cone.length_scale
        version = msg.inputs_version


def test_invalid_mode_is_unmistakable(harness):
    col = harness.subscribe_cone("na")
    col.wait_for(lambda m: m.feasible, "the initial cone")
    harness.publish_pose(0.0, 0.01, 0.0, stamp=(3, 0))  # lifts the disc off fixel 1
    msg = col.wait_for(lambda m: _stamp(m) == (3, 0), "the cone after the pose")
    assert msg.status == Status.MODE_NOT_ALLOWED and not msg.feasible
    assert "fixel 1" in msg.message and conv.message_rows(msg) is None
    assert not (msg.inequalities or msg.equalities or msg.generators or msg.lineality)


def test_stale_inputs_publish_no_rows(harness_factory):
    h = harness_factory(input_timeout=1.0)  # long enough for a loaded machine
    col = h.subscribe_cone("na")
    h.publish_pose(0.0, 0.0, 0.0, stamp=(9, 0))
    col.wait_for(lambda m: _stamp(m) == (9, 0) and m.feasible, "the cone of the pose")
    msg = col.wait_for(lambda m: m.status == Status.STALE_INPUTS, "the stale message")
    assert not msg.feasible and conv.message_rows(msg) is None
    assert "input_timeout" in msg.message and _stamp(msg) == (9, 0)
    assert not (msg.inequalities or msg.equalities or msg.generators or msg.lineality)
    h.publish_pose(0.0, 0.0, 0.0, stamp=(10, 0))  # fresh again: the cone is back
    col.wait_for(lambda m: _stamp(m) == (10, 0) and m.status == Status.OK
                 and m.feasible, "the cone again")


def test_a_topic_nobody_listens_to_is_caught_up_when_someone_does(harness_factory):
    """Lazy publishing: with no subscriber a cone topic is not built (at a 1 kHz pose
    stream the messages cost more than the cones); a subscriber that appears later gets
    the cone of the newest inputs (within the catch-up period), not an older one."""
    h = harness_factory(modes=["na", "ns"])
    watcher = h.subscribe_cone("na")  # keeps the node publishing; "ns" has nobody
    first = watcher.wait_for(lambda m: True, "the initial cone")
    for k in range(1, 6):
        h.publish_pose(0.0, 0.0, 0.05 * k, stamp=(10 + k, 0))
    last = watcher.wait_for(lambda m: _stamp(m) == (15, 0), "the last pose's cone")
    assert last.inputs_version > first.inputs_version
    cones = h.node.snapshot_publishers[0]
    assert "ns" in cones._pending  # skipped: nobody listens
    late = h.subscribe_cone("ns")
    msg = late.wait_for(lambda m: m.inputs_version == last.inputs_version,
                        "the late subscriber's current cone")
    assert _stamp(msg) == (15, 0)
    scene = default_scene().with_pose(0.0, 0.0, 0.25)
    cone = wrench_cone(scene, "ns")
    if cone.feasible:
        F, E = conv.message_rows(msg)
        assert same_rows(F, cone.F) and same_rows(E, cone.equalities)
    else:
        assert msg.status == Status.MODE_INFEASIBLE and not msg.feasible
