"""The typed cone topic ~/cone/<mode> (wrenchcone_ros/msg/WrenchCone) over DDS: its header
stamp is the newest input's, its inputs_version is the snapshot's that the services name,
its rows are the core's cone of exactly those inputs."""

from __future__ import annotations

import math

from node_harness import same_rows

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.core import default_scene, load_scene, wrench_cone
from wrenchcone_ros.msg import WrenchCone


def _stamp(m):
    return (m.header.stamp.sec, m.header.stamp.nanosec)


def test_cone_message_names_its_inputs(harness_factory):
    h = harness_factory(workpiece__com=[0.3, 0.0])
    col = h.subscribe_cone("na")
    first = col.wait_for(lambda m: True, "the initial cone")
    # the scene file's own pose and fixels: no input stamp yet
    assert _stamp(first) == (0, 0) and first.header.frame_id == "world"
    assert first.inputs_version == h.get_cone("na").inputs_version
    assert first.status == WrenchCone.OK and first.feasible and first.message == ""
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
    assert msg.status == WrenchCone.MODE_NOT_ALLOWED and not msg.feasible
    assert "fixel 1" in msg.message and conv.message_rows(msg) is None
    assert not (msg.inequalities or msg.equalities or msg.generators or msg.lineality)


def test_stale_inputs_publish_no_rows(harness_factory):
    h = harness_factory(input_timeout=1.0)  # long enough for a loaded machine
    col = h.subscribe_cone("na")
    h.publish_pose(0.0, 0.0, 0.0, stamp=(9, 0))
    col.wait_for(lambda m: _stamp(m) == (9, 0) and m.feasible, "the cone of the pose")
    msg = col.wait_for(lambda m: m.status == WrenchCone.STALE_INPUTS, "the stale message")
    assert not msg.feasible and conv.message_rows(msg) is None
    assert "input_timeout" in msg.message and _stamp(msg) == (9, 0)
    assert not (msg.inequalities or msg.equalities or msg.generators or msg.lineality)
    h.publish_pose(0.0, 0.0, 0.0, stamp=(10, 0))  # fresh again: the cone is back
    col.wait_for(lambda m: _stamp(m) == (10, 0) and m.status == WrenchCone.OK
                 and m.feasible, "the cone again")
