# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Message conversions: planar conventions, refusals with named tolerances, cone layout."""

from __future__ import annotations

from wrenchcone_msgs.msg import Status
import math
import struct

import numpy as np
import pytest
from geometry_msgs.msg import Pose, PoseArray, PoseStamped, Wrench
from hypothesis import given, settings
from hypothesis import strategies as st
from rclpy.serialization import deserialize_message, serialize_message

from wrenchcone_ros.ros import conversions as conv


def pose(x=0.0, y=0.0, q=(0.0, 0.0, 0.0, 1.0)):
    p = Pose()
    p.position.x, p.position.y = x, y
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = q
    return p


@pytest.mark.parametrize("yaw", [0.0, 0.3, -2.0, math.pi - 1e-9, 3.0])
def test_yaw_round_trip(yaw):
    x, y, th = conv.pose_to_planar(pose(1.5, -2.0, conv.yaw_to_quaternion(yaw)))
    assert (x, y) == (1.5, -2.0)
    assert math.isclose(math.remainder(th - yaw, 2 * math.pi), 0.0, abs_tol=1e-12)


def test_tilted_pose_refused_with_tolerance_named():
    a = 0.01  # rotation about x by 0.01 rad
    q = (math.sin(a / 2), 0.0, 0.0, math.cos(a / 2))
    with pytest.raises(conv.ConversionError, match="tilted.*tolerance"):
        conv.pose_to_planar(pose(q=q))
    # within a looser tolerance it is accepted, yaw 0
    assert conv.pose_to_planar(pose(q=q), tilt_tolerance=0.02)[2] == pytest.approx(0.0)


@pytest.mark.parametrize("q", [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 2.0),
                               (0.0, 0.0, math.nan, 1.0)])
def test_bad_quaternions_refused(q):
    with pytest.raises(conv.ConversionError):
        conv.pose_to_planar(pose(q=q))


def test_nan_position_refused():
    with pytest.raises(conv.ConversionError, match="non-finite"):
        conv.pose_to_planar(pose(x=math.inf))


def test_fixels_from_pose_array():
    """A PoseArray gives positions; the radii are fixel_radius's (one for all, one per
    fixel), and without them (or with a count that fits neither) it is refused."""
    from wrenchcone_ros.core import Fixel

    msg = PoseArray()
    for x, y in [(0.0, -1.0), (1.001, 0.0)]:
        p = Pose()
        p.position.x, p.position.y = x, y
        msg.poses.append(p)
    assert conv.fixels_from_pose_array(msg, [0.0]) == (Fixel((0.0, -1.0)), Fixel((1.001, 0.0)))
    assert conv.fixels_from_pose_array(msg, [0.003, 0.004]) == (
        Fixel((0.0, -1.0), 0.003), Fixel((1.001, 0.0), 0.004))
    with pytest.raises(conv.ConversionError, match="fixel_radius is not set"):
        conv.fixels_from_pose_array(msg, [])
    with pytest.raises(conv.ConversionError, match="3 radii for a PoseArray of 2"):
        conv.fixels_from_pose_array(msg, [0.1, 0.2, 0.3])
    with pytest.raises(conv.ConversionError, match="no poses"):
        conv.fixels_from_pose_array(PoseArray(), [0.0])
    with pytest.raises(conv.ConversionError, match="fixel 2 radius"):
        conv.fixels_from_pose_array(msg, [0.0, -1.0])
    msg.poses[1].position.y = math.nan
    with pytest.raises(conv.ConversionError, match="fixel 2"):
        conv.fixels_from_pose_array(msg, [0.0])


def test_fixels_message_round_trip_and_refusals():
    """Fixels <-> core fixels: radius and friction per fixel (FRICTION_UNSET: None);
    a negative radius, a friction neither FRICTION_UNSET nor in range, NaN: refused."""
    from wrenchcone_msgs.msg import Fixel as FixelMsg

    from wrenchcone_ros.core import Fixel

    fixels = (Fixel((0.1, 0.2), 0.003), Fixel((0.3, 0.2), 0.004, 0.5))
    msg = conv.fixels_message(fixels, "world", (3, 4))
    assert (msg.header.frame_id, msg.header.stamp.sec, msg.header.stamp.nanosec) == (
        "world", 3, 4)
    assert msg.fixels[0].friction == FixelMsg.FRICTION_UNSET == -1.0
    assert FixelMsg().friction == FixelMsg.FRICTION_UNSET  # a new message: unset
    assert conv.fixels_from_message(msg) == fixels
    for field, value, words in (("radius", -0.001, "fixel 2 radius"),
                                ("radius", math.nan, "fixel 2 radius"),
                                ("friction", -0.5, "fixel 2 friction"),
                                ("friction", math.nan, "fixel 2 friction"),
                                ("friction", math.inf, "fixel 2 friction")):
        bad = conv.fixels_message(fixels, "world")
        setattr(bad.fixels[1], field, value)
        with pytest.raises(conv.ConversionError, match=words):
            conv.fixels_from_message(bad)
    bad = conv.fixels_message(fixels, "world")
    bad.fixels[0].position.z = math.inf
    with pytest.raises(conv.ConversionError, match="fixel 1 position"):
        conv.fixels_from_message(bad)
    with pytest.raises(conv.ConversionError, match="no fixel"):
        conv.fixels_from_message(conv.fixels_message((), "world"))


def wrench(fx=0.0, fy=0.0, fz=0.0, tx=0.0, ty=0.0, tz=0.0):
    w = Wrench()
    w.force.x, w.force.y, w.force.z = fx, fy, fz
    w.torque.x, w.torque.y, w.torque.z = tx, ty, tz
    return w


def test_wrench_planar_and_out_of_plane_refusal():
    assert conv.wrench_to_planar(wrench(1.0, 2.0, tz=3.0)) == (1.0, 2.0, 3.0)
    # relative tolerance: tiny out-of-plane noise on a large wrench passes
    assert conv.wrench_to_planar(wrench(1e3, fz=1e-5))[0] == 1e3
    with pytest.raises(conv.ConversionError, match="out-of-plane.*tolerance"):
        conv.wrench_to_planar(wrench(1.0, fz=0.1))
    with pytest.raises(conv.ConversionError, match="out-of-plane"):
        conv.wrench_to_planar(wrench(tx=1e-12))  # nothing in plane
    # torque is compared through the length scale: tx / L
    with pytest.raises(conv.ConversionError):
        conv.wrench_to_planar(wrench(1.0, tx=1e-3), length_scale=1.0)
    assert conv.wrench_to_planar(wrench(1.0, tx=1e-3), length_scale=1e4)
    with pytest.raises(conv.ConversionError, match="non-finite"):
        conv.wrench_to_planar(wrench(math.nan))


def test_cone_message_layout():
    from wrenchcone_ros.core import default_scene, load_scene, wrench_cone

    cone = wrench_cone(default_scene(), "sa")  # a cone with a line: every array filled
    msg = conv.cone_message("sa", Status.OK, "", cone, frame_id="fixture",
                            stamp=(7, 8), inputs_version=42)
    assert msg.header.frame_id == "fixture" and (msg.header.stamp.sec,
                                                 msg.header.stamp.nanosec) == (7, 8)
    assert msg.mode == "sa" and msg.feasible and msg.inputs_version == 42
    assert msg.length_scale == cone.length_scale
    for field, rows in (("inequalities", cone.F), ("equalities", cone.equalities),
                        ("generators", cone.G), ("lineality", cone.lineality)):
        assert np.array_equal(conv.rows_from_flat(getattr(msg, field)), rows.reshape(-1, 3))
    F, E = conv.message_rows(msg)
    assert np.array_equal(F, cone.F) and E.shape == (0, 3)
    # an infeasible mode: status says so, no rows, never "anything goes"
    pinned = load_scene({"workpiece": {"mass": 1.0, "inertia": 1.0,
                                       "shape": {"type": "disc", "radius": 1.0}},
                         "friction": 0.2, "fixels": [[0.0, -1.0], [1.0, 0.0], [-1.0, 0.0],
                                                     [0.0, 1.5]]})
    bad = wrench_cone(pinned, "nnna")
    assert not bad.feasible
    msg = conv.cone_message("nnna", Status.MODE_INFEASIBLE, "impossible", bad,
                            frame_id="world", stamp=None, inputs_version=1)
    assert not msg.feasible and conv.message_rows(msg) is None
    assert not (msg.inequalities or msg.equalities or msg.generators or msg.lineality)
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (0, 0)


def test_status_codes_are_one_table_with_one_meaning_per_number():
    from wrenchcone_ros.node.status import STATUS_NAMES

    # the constants are properties of the generated class's metaclass; the codes are
    # its integer ones (the others: the input sources and the interface version)
    codes = {n: getattr(Status, n) for n, v in vars(type(Status)).items()
             if isinstance(v, property) and isinstance(getattr(Status, n), int)}
    assert "OK" in codes and "NOT_ACTIVE" in codes
    assert len(set(codes.values())) == len(codes), codes
    assert STATUS_NAMES == {v: k for k, v in codes.items()}
    # an interface with a status repeats the table, never a code of its own
    cone = {n: getattr(conv.WrenchCone, n) for n, v in vars(type(conv.WrenchCone)).items()
            if isinstance(v, property) and isinstance(getattr(conv.WrenchCone, n), int)}
    assert cone == codes


def test_newest_stamp():
    assert conv.newest_stamp(None, None) is None
    assert conv.newest_stamp((3, 5), None) == (3, 5)
    assert conv.newest_stamp((3, 5), (3, 4)) == (3, 5)
    assert conv.newest_stamp((2, 999999999), (3, 0)) == (3, 0)


# --- the pose read straight from its serialized bytes (inputs.py) ----------------------
_any_double = st.floats(allow_nan=True, allow_infinity=True, width=64)


def _same(a: float, b: float) -> bool:
    return struct.pack("<d", a) == struct.pack("<d", b)  # bit for bit, NaN included


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(frame=st.text(max_size=40), sec=st.integers(-2**31, 2**31 - 1),
       nanosec=st.integers(0, 2**32 - 1), values=st.lists(_any_double, min_size=7,
                                                          max_size=7))
def test_pose_stamped_fields_agree_with_rclpy(frame, sec, nanosec, values):
    """The hand-read CDR fields equal what rclpy's own deserializer makes of the bytes
    rclpy serialized, for any frame (any length, so any padding), stamp and values."""
    if "\x00" in frame:
        frame = frame.replace("\x00", "")  # a ROS string holds no NUL
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.header.stamp.sec, msg.header.stamp.nanosec = sec, nanosec
    p, q = msg.pose.position, msg.pose.orientation
    p.x, p.y, p.z, q.x, q.y, q.z, q.w = values
    data = serialize_message(msg)
    back = deserialize_message(data, PoseStamped)
    got = conv.pose_stamped_fields(data)
    assert got is not None
    assert got[0] == back.header.frame_id
    assert got[1] == (back.header.stamp.sec, back.header.stamp.nanosec)
    bp, bq = back.pose.position, back.pose.orientation
    assert all(map(_same, got[2], (bp.x, bp.y, bp.z, bq.x, bq.y, bq.z, bq.w)))


def test_pose_stamped_fields_leave_other_bytes_to_rclpy():
    msg = PoseStamped()
    msg.header.frame_id = "world"
    data = serialize_message(msg)
    assert conv.pose_stamped_fields(data) is not None
    assert conv.pose_stamped_fields(data[:-1]) is None  # truncated
    assert conv.pose_stamped_fields(data + b"\x00" * 8) is None  # longer
    assert conv.pose_stamped_fields(b"\x00\x07" + data[2:]) is None  # XCDR2 encapsulation
    assert conv.pose_stamped_fields(data[:16]) is None
    assert conv.pose_stamped_fields(b"") is None
    bad_terminator = bytearray(data)
    bad_terminator[16 + len("world")] = ord("x")
    assert conv.pose_stamped_fields(bytes(bad_terminator)) is None
    bad_utf8 = bytearray(data)
    bad_utf8[16] = 0xFF
    assert conv.pose_stamped_fields(bytes(bad_utf8)) is None


def test_big_endian_cdr_is_read_too():
    """A big-endian writer (encapsulation 0x0000): the same layout, the other byte order."""
    body = struct.pack(">iII", 3, 4, 6) + b"world\x00" + b"\x00" * 6  # payload 18 -> 24
    body += struct.pack(">7d", 1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    assert conv.pose_stamped_fields(b"\x00\x00\x00\x00" + body) == (
        "world", (3, 4), (1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0))
