"""Message conversions: planar conventions, refusals with named tolerances, cone layout."""

from __future__ import annotations

import math

import numpy as np
import pytest
from geometry_msgs.msg import Pose, PoseArray, Wrench

from wrenchcone_ros import conversions as conv


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
    msg = PoseArray()
    for x, y in [(0.0, -1.0), (1.001, 0.0)]:
        p = Pose()
        p.position.x, p.position.y = x, y
        msg.poses.append(p)
    assert conv.fixels_from_pose_array(msg) == [(0.0, -1.0), (1.001, 0.0)]
    with pytest.raises(conv.ConversionError, match="no poses"):
        conv.fixels_from_pose_array(PoseArray())
    msg.poses[1].position.y = math.nan
    with pytest.raises(conv.ConversionError, match="fixel 2"):
        conv.fixels_from_pose_array(msg)


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


def test_cone_layout_round_trip_and_markers():
    F = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.5]])
    E = np.array([[0.0, 0.0, 1.0]])
    msg = conv.cone_to_multiarray(F, E)
    assert [d.label for d in msg.layout.dim] == ["rows", "fx,fy,tz,kind"]
    assert [d.size for d in msg.layout.dim] == [3, 4]
    F2, E2, marker = conv.multiarray_to_rows(msg)
    assert marker is None and np.array_equal(F2, F) and np.array_equal(E2, E)
    assert list(np.asarray(msg.data).reshape(-1, 4)[:, 3]) == [0.0, 0.0, 1.0]
    for kind in (conv.KIND_INFEASIBLE, conv.KIND_INVALID):
        m = conv.marker_multiarray(kind)
        F3, E3, marker = conv.multiarray_to_rows(m)
        assert marker == kind and F3.size == 0 and E3.size == 0
        # a naive consumer ignoring the kind column still accepts no wrench
        rows = np.asarray(m.data).reshape(-1, 4)[:, :3]
        assert not np.all(rows @ np.zeros(3) <= 0)
