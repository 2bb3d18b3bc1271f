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

Published cone layout (std_msgs/Float64MultiArray), see :func:`cone_to_multiarray`:
rows of 4 numbers ``(c_fx, c_fy, c_tz, kind)``; ``kind`` says what the row means.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, PoseArray, Wrench
from std_msgs.msg import Float64MultiArray, MultiArrayDimension

from wrenchcone_ros.core.tolerances import MAX_COORDINATE_M



def _import_services():
    """The generated service types (wrenchcone_ros.srv), wherever the package runs from.

    The srv modules exist only in the colcon install tree. When the source tree shadows
    it on sys.path (``python -m ...`` from the repository root), extend the package's
    search path to the other ``wrenchcone_ros`` directories on sys.path (the install
    tree, via PYTHONPATH from install/setup.bash) and try again.
    """
    try:
        from wrenchcone_ros import srv
    except ImportError:
        import pkgutil

        import wrenchcone_ros

        wrenchcone_ros.__path__ = pkgutil.extend_path(wrenchcone_ros.__path__,
                                                      "wrenchcone_ros")
        from wrenchcone_ros import srv
    return srv.CheckWrench, srv.ClassifyWrench, srv.GetCone


CheckWrench, ClassifyWrench, GetCone = _import_services()

#: Default out-of-plane tolerance for wrenches (relative, dimensionless).
OUT_OF_PLANE_TOLERANCE = 1e-6
#: Default tilt tolerance for poses (rad).
TILT_TOLERANCE_RAD = 1e-4
#: Wrenches with a component beyond this (N or N m), or all below its inverse, are
#: rescaled by a power of two before use (cone tests are scale-invariant).
WRENCH_RESCALE_ABOVE = 1e100
#: A pose quaternion must have norm 1 within this (absolute) tolerance.
QUATERNION_NORM_TOLERANCE = 1e-3

#: ``kind`` column values of the published cone rows.
KIND_INEQUALITY = 0.0  # c . g <= 0 required
KIND_EQUALITY = 1.0  # c . g == 0 required
KIND_INFEASIBLE = 2.0  # the mode is impossible: NO wrench is consistent (c is NaN)
KIND_INVALID = 3.0  # the mode is not valid for the current inputs (c is NaN)
KIND_STALE = 4.0  # the inputs are older than the node's timeout: no cone is vouched for
MARKER_KINDS = (KIND_INFEASIBLE, KIND_INVALID, KIND_STALE)
COLUMNS_LABEL = "fx,fy,tz,kind"
ROWS_LABEL = "rows"


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
    _coordinates((p.x, p.y, p.z), "pose position")
    yaw = quaternion_to_yaw(q.x, q.y, q.z, q.w, tilt_tolerance)
    return (float(p.x), float(p.y), yaw)


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


def rows_flat(a: np.ndarray) -> list[float]:
    """A (k, 3) array as a flat row-major list of floats (for float64[] fields)."""
    return [float(v) for v in np.asarray(a, dtype=float).reshape(-1)]


def rows_from_flat(flat: Sequence[float]) -> np.ndarray:
    """Inverse of :func:`rows_flat`: a (k, 3) array."""
    return np.asarray(flat, dtype=float).reshape(-1, 3)


def _multiarray(rows: np.ndarray) -> Float64MultiArray:
    n = rows.shape[0]
    msg = Float64MultiArray()
    msg.layout.dim = [
        MultiArrayDimension(label=ROWS_LABEL, size=n, stride=4 * n),
        MultiArrayDimension(label=COLUMNS_LABEL, size=4, stride=4),
    ]
    msg.layout.data_offset = 0
    msg.data = [float(v) for v in rows.reshape(-1)]
    return msg


def cone_to_multiarray(F: np.ndarray, E: np.ndarray) -> Float64MultiArray:
    """The published form of a feasible cone: inequality rows, then equality rows.

    Layout: dim[0] ``rows`` (k + e), dim[1] ``fx,fy,tz,kind`` (4); row-major. Each row is
    ``(c_fx, c_fy, c_tz, kind)`` with kind 0 (inequality, c . g <= 0) or 1 (equality,
    c . g = 0). A feasible cone with no rows is all of R^3 (every wrench consistent).
    """
    F = np.asarray(F, dtype=float).reshape(-1, 3)
    E = np.asarray(E, dtype=float).reshape(-1, 3)
    rows = np.zeros((F.shape[0] + E.shape[0], 4))
    rows[: F.shape[0], :3] = F
    rows[: F.shape[0], 3] = KIND_INEQUALITY
    rows[F.shape[0]:, :3] = E
    rows[F.shape[0]:, 3] = KIND_EQUALITY
    return _multiarray(rows)


def marker_multiarray(kind: float) -> Float64MultiArray:
    """One row ``(NaN, NaN, NaN, kind)``: the infeasible (2), invalid (3) or stale (4)
    marker.

    NaN coefficients make every naive ``F g <= 0`` test fail, so a consumer that ignores
    the kind column still reads "nothing is consistent", never "anything goes".
    """
    return _multiarray(np.array([[math.nan, math.nan, math.nan, float(kind)]]))


def multiarray_to_rows(msg: Float64MultiArray) -> tuple[np.ndarray, np.ndarray, float | None]:
    """Parse a published cone: (F (k, 3), E (e, 3), marker kind or None).

    The marker is KIND_INFEASIBLE, KIND_INVALID or KIND_STALE when the message carries
    one; then F and E are empty and no wrench may be treated as consistent.
    """
    dims = msg.layout.dim
    if len(dims) != 2 or dims[1].size != 4 or dims[1].label != COLUMNS_LABEL:
        raise ConversionError(f"not a wrenchcone cone message (layout {dims!r})")
    a = np.asarray(msg.data, dtype=float)[msg.layout.data_offset:].reshape(-1, 4)
    kinds = a[:, 3]
    marker = None
    special = kinds[np.isin(kinds, MARKER_KINDS)]
    if special.size:
        marker = float(special[0])
    return (a[kinds == KIND_INEQUALITY, :3], a[kinds == KIND_EQUALITY, :3], marker)


def time_to_msg(sec_nsec: tuple[int, int] | None) -> Time:
    t = Time()
    if sec_nsec is not None:
        t.sec, t.nanosec = int(sec_nsec[0]), int(sec_nsec[1])
    return t
