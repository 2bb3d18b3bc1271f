"""ROS messages <-> core types, with the planar conventions checked (no silent projection).

Planar convention (docs/node.md): everything is in one fixture frame whose x-y plane is
the plane of motion. A wrench g = (fx N, fy N, tz N m) is applied to the workpiece, in
fixture axes, moment about the workpiece's centre of mass. A pose is (x m, y m, yaw rad)
of the workpiece frame in the fixture frame.

Refusals (each raises :class:`ConversionError`, a ValueError, with a one-line message):

* any NaN / inf component; a pose or fixel position component beyond the core's
  coordinate limit ``MAX_COORDINATE_M`` (1e9 m, core/tolerances.py);
* a pose whose orientation is not a unit quaternion (|q| off by more than
  ``QUATERNION_NORM_TOLERANCE``) or is tilted out of the plane by more than
  ``tilt_tolerance`` rad (default ``TILT_TOLERANCE_RAD``): the angle between the
  workpiece's z axis and the fixture's z axis;
* a wrench whose out-of-plane part is not negligible: with L the scene's length scale,
  ``|(fz, tx / L, ty / L)| > out_of_plane_tolerance * |(fx, fy, tz / L)|`` (default
  ``OUT_OF_PLANE_TOLERANCE``, relative, so independent of the wrench's magnitude and of
  the units; a wrench with zero in-plane part and any out-of-plane part is refused).

Published cone: wrenchcone_ros/msg/WrenchCone (:func:`cone_message`), rows flattened
row-major with 3 columns (:func:`rows_flat`); status and feasible say whether any wrench
is consistent.
"""

from __future__ import annotations

import array
import math
import struct
from collections.abc import Sequence
from typing import Any

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, PoseArray, Wrench

from wrenchcone_ros.core.tolerances import MAX_COORDINATE_M


def _import_generated():
    """The generated types (wrenchcone_ros.srv, .msg), wherever the package runs from.

    The srv and msg modules exist only in the colcon install tree. When the source tree shadows
    it on sys.path (``python -m ...`` from the repository root), extend the package's
    search path to the other ``wrenchcone_ros`` directories on sys.path (the install
    tree, via PYTHONPATH from install/setup.bash) and try again.
    """
    try:
        from wrenchcone_ros import msg, srv
    except ImportError:
        import pkgutil

        import wrenchcone_ros

        wrenchcone_ros.__path__ = pkgutil.extend_path(wrenchcone_ros.__path__,
                                                      "wrenchcone_ros")
        from wrenchcone_ros import msg, srv
    return srv.CheckWrench, srv.ClassifyWrench, srv.GetCone, msg.WrenchCone


CheckWrench, ClassifyWrench, GetCone, WrenchCone = _import_generated()

#: Default out-of-plane tolerance for wrenches (relative, dimensionless).
OUT_OF_PLANE_TOLERANCE = 1e-6
#: Default tilt tolerance for poses (rad).
TILT_TOLERANCE_RAD = 1e-4
#: Wrenches with a component beyond this (N or N m), or all below its inverse, are
#: rescaled by a power of two before use (cone tests are scale-invariant).
WRENCH_RESCALE_ABOVE = 1e100
#: A pose quaternion must have norm 1 within this (absolute) tolerance.
QUATERNION_NORM_TOLERANCE = 1e-3


class ConversionError(ValueError):
    """A message that cannot be turned into planar data; the message says why."""


def _finite(values: Sequence[float], what: str) -> None:
    for v in values:
        if not math.isfinite(v):
            raise ConversionError(f"{what} has a non-finite component ({v!r})")


def _coordinates(values: Sequence[float], what: str) -> None:
    """Finite and within the core's coordinate limit (tolerances.MAX_COORDINATE_M)."""
    _finite(values, what)
    for v in values:
        if abs(v) > MAX_COORDINATE_M:
            raise ConversionError(f"{what} has a component {v!r} beyond +-"
                                  f"{MAX_COORDINATE_M:g} m (the scene's coordinate limit)")


def quaternion_to_yaw(x: float, y: float, z: float, w: float,
                      tilt_tolerance: float = TILT_TOLERANCE_RAD) -> float:
    """Yaw (rad) of a unit quaternion that rotates about z only; refuses a tilted one."""
    _finite((x, y, z, w), "orientation quaternion")
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE:
        raise ConversionError(
            f"orientation quaternion has norm {norm:.6g}, not 1 (tolerance "
            f"{QUATERNION_NORM_TOLERANCE:g}); an all-zero orientation is not a rotation")
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    # Angle between the rotated z axis and the fixture z axis: cos = 1 - 2 (x^2 + y^2).
    tilt = 2.0 * math.asin(min(1.0, math.sqrt(x * x + y * y)))
    if tilt > tilt_tolerance:
        raise ConversionError(
            f"orientation is tilted {tilt:.3g} rad out of the fixture plane (tolerance "
            f"{tilt_tolerance:.3g} rad); the workpiece must rotate about the fixture z axis")
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def pose_to_planar(pose: Pose, tilt_tolerance: float = TILT_TOLERANCE_RAD
                   ) -> tuple[float, float, float]:
    """(x m, y m, yaw rad) of a geometry_msgs/Pose; position.z is ignored."""
    p, q = pose.position, pose.orientation
    return planar_pose((p.x, p.y, p.z, q.x, q.y, q.z, q.w), tilt_tolerance)


def planar_pose(values: Sequence[float], tilt_tolerance: float = TILT_TOLERANCE_RAD
                ) -> tuple[float, float, float]:
    """(x m, y m, yaw rad) of the 7 numbers of a geometry_msgs/Pose: position x, y, z
    (z ignored) and orientation x, y, z, w."""
    px, py, pz, qx, qy, qz, qw = values
    _coordinates((px, py, pz), "pose position")
    yaw = quaternion_to_yaw(qx, qy, qz, qw, tilt_tolerance)
    return (float(px), float(py), yaw)


#: Plain CDR (XCDR1) encapsulation ids, the first two bytes of a serialized message:
#: big-endian and little-endian. Anything else is left to rclpy's deserializer.
_CDR_BYTE_ORDER = {b"\x00\x00": ">", b"\x00\x01": "<"}
_POSE_DOUBLES = 7  # geometry_msgs/Pose: position x, y, z; orientation x, y, z, w


def pose_stamped_fields(data: bytes) -> tuple[str, tuple[int, int], tuple[float, ...]] | None:
    """(frame_id, (sec, nanosec), the 7 numbers of the pose) of a serialized
    geometry_msgs/PoseStamped, read directly from its plain-CDR bytes; None when the
    bytes are not exactly that layout (another encapsulation, a wrong length, no string
    terminator, bad UTF-8): the caller then uses rclpy's deserializer.

    Layout after the 4-byte encapsulation header (offsets from the payload start,
    8-byte values aligned to 8): int32 sec, uint32 nanosec, uint32 n, n bytes of
    frame_id with its NUL, padding, 7 float64. 13-15 times cheaper than
    ``rclpy.serialization.deserialize_message`` (benchmarks/node_decode.py); checked
    against it for any frame, stamp and values (test_node_conversions.py)."""
    order = _CDR_BYTE_ORDER.get(bytes(data[:2]))
    if order is None or len(data) < 16:
        return None
    sec, nanosec, n = struct.unpack_from(order + "iII", data, 4)
    start = 4 + ((12 + n + 7) & ~7)  # the first float64, aligned in the payload
    if n < 1 or start + 8 * _POSE_DOUBLES != len(data) or data[15 + n] != 0:
        return None
    try:
        frame_id = bytes(data[16:15 + n]).decode("utf-8")
    except UnicodeDecodeError:
        return None
    return frame_id, (sec, nanosec), struct.unpack_from(f"{order}{_POSE_DOUBLES}d", data,
                                                         start)


def yaw_to_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """(x, y, z, w) of the rotation by ``yaw`` about z."""
    return (0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0))


def fixels_from_pose_array(msg: PoseArray) -> list[tuple[float, float]]:
    """Fixel positions (x, y) in m from a PoseArray (orientations and z are ignored)."""
    if len(msg.poses) == 0:
        raise ConversionError("fixel message has no poses; at least one fixel is needed")
    out = []
    for k, pose in enumerate(msg.poses):
        p = pose.position
        _coordinates((p.x, p.y, p.z), f"fixel {k + 1} position")
        out.append((float(p.x), float(p.y)))
    return out


def wrench_to_planar(wrench: Wrench, length_scale: float = 1.0,
                     tolerance: float = OUT_OF_PLANE_TOLERANCE) -> tuple[float, float, float]:
    """(fx N, fy N, tz N m) of a geometry_msgs/Wrench; refuses out-of-plane parts.

    ``length_scale`` (m) makes force and torque comparable; see the module docstring.
    A wrench whose largest component is beyond WRENCH_RESCALE_ABOVE (or below its
    inverse) comes back multiplied by an exact power of two: every cone test and margin
    is invariant under positive scaling, and the squares stay finite.
    """
    f, t = wrench.force, wrench.torque
    fx, fy, fz, tx, ty, tz = f.x, f.y, f.z, t.x, t.y, t.z
    if not math.isfinite(fx + fy + fz + tx + ty + tz):  # cheap test first (hot path)
        _finite((fx, fy, fz, tx, ty, tz), "wrench")
    big = max(abs(fx), abs(fy), abs(fz), abs(tx), abs(ty), abs(tz))
    if big > WRENCH_RESCALE_ABOVE or 0.0 < big < 1.0 / WRENCH_RESCALE_ABOVE:
        # Cones are invariant under positive scaling: rescale by an exact power of two so
        # that squares neither overflow (1e200 N) nor underflow (1e-200 N).
        k = -math.frexp(big)[1]
        fx, fy, fz, tx, ty, tz = (math.ldexp(v, k) for v in (fx, fy, fz, tx, ty, tz))
    inv_l = 1.0 / length_scale if length_scale > 0 else 1.0
    inplane2 = fx * fx + fy * fy + (tz * inv_l) ** 2
    outplane2 = fz * fz + (tx * inv_l) ** 2 + (ty * inv_l) ** 2
    if outplane2 > 0.0 and math.sqrt(outplane2) > tolerance * math.sqrt(inplane2):
        raise ConversionError(
            f"wrench has out-of-plane components (force.z={fz:.6g} N, torque.x={tx:.6g} "
            f"N m, torque.y={ty:.6g} N m) beyond the tolerance {tolerance:g} relative to "
            "its in-plane part (force.x, force.y, torque.z); only planar wrenches are "
            "checked")
    return (fx, fy, tz)


def planar_to_wrench(g: Sequence[float]) -> Wrench:
    """geometry_msgs/Wrench from (fx, fy, tz)."""
    w = Wrench()
    w.force.x, w.force.y, w.torque.z = (float(v) for v in g)
    return w


def rows_flat(a: np.ndarray) -> array.array:
    """A (k, 3) array as a flat row-major ``array('d')`` (for float64[] fields: the
    generated setters take an array('d') as it is, a list is checked value by value)."""
    flat = array.array("d")
    flat.frombytes(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    return flat


def rows_from_flat(flat: Sequence[float]) -> np.ndarray:
    """Inverse of :func:`rows_flat`: a (k, 3) array."""
    return np.asarray(flat, dtype=float).reshape(-1, 3)


def newest_stamp(*stamps: tuple[int, int] | None) -> tuple[int, int] | None:
    """The latest of some (sec, nanosec) stamps; None when there is none."""
    given = [tuple(s) for s in stamps if s is not None]
    return max(given) if given else None


def cone_message(mode: str, status: int, message: str, cone: Any, *, frame_id: str,
                 stamp: tuple[int, int] | None, inputs_version: int) -> WrenchCone:
    """The published form of one (snapshot, mode): wrenchcone_ros/msg/WrenchCone.

    ``cone`` is the core's Cone (or None). The rows are filled only when ``status`` is OK
    (then ``feasible`` is true); otherwise every array is empty and ``feasible`` false,
    which the message definition says means "no wrench is consistent".
    """
    msg = WrenchCone()
    msg.header.frame_id = frame_id
    msg.header.stamp = time_to_msg(stamp)
    msg.mode = mode
    msg.status = int(status)
    msg.message = message
    msg.inputs_version = int(inputs_version)
    if cone is not None:
        msg.length_scale = float(cone.length_scale)
    if status == WrenchCone.OK and cone is not None:
        msg.feasible = bool(cone.feasible)
        msg.inequalities = rows_flat(cone.F)
        msg.equalities = rows_flat(cone.equalities)
        msg.generators = rows_flat(cone.G)
        msg.lineality = rows_flat(cone.lineality)
    return msg


def message_rows(msg: WrenchCone) -> tuple[np.ndarray, np.ndarray] | None:
    """(F (k, 3), E (e, 3)) of a published cone, or None when no wrench is consistent
    (status not OK or an infeasible mode)."""
    if msg.status != WrenchCone.OK or not msg.feasible:
        return None
    return rows_from_flat(msg.inequalities), rows_from_flat(msg.equalities)


def time_to_msg(sec_nsec: tuple[int, int] | None) -> Time:
    t = Time()
    if sec_nsec is not None:
        t.sec, t.nanosec = int(sec_nsec[0]), int(sec_nsec[1])
    return t
