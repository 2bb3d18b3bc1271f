# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Scene geometry: shapes, the workpiece, fixels, and the contact geometry between them
(closest points, gaps, contact frames); the errors of a scene's values.

The Scene type (:mod:`.scene`) puts these together at a pose; :mod:`.scene_yaml` reads
scenes from YAML files and dicts.

Conventions (docs/theory.md, "Model and conventions"; REP-103: metres, kilograms,
radians, right-handed):

* The workpiece frame is placed in the world (fixture) frame by ``pose = (x, y, theta)``.
  Shapes, the centre of mass (com) and polygon vertices are given in the workpiece frame;
  fixels in the world frame.
* A disc is centred at the workpiece-frame origin. A polygon is simple, its vertices
  counter-clockwise, convex or not.
* Fixel i at f_i, a point or a pin of radius rho_i. p_i is the point of the workpiece
  boundary closest to f_i; ``gap = signed distance(f_i, workpiece) - rho_i`` (negative
  inside). With tol = ``effective_contact_tolerance`` (the scene's contact_tolerance, at
  least 8 ulp of the largest world coordinate): ``|gap| <= tol`` is contact, ``gap > tol``
  is free, ``gap < -tol``
  is a penetration and an input error.
* n_i is the unit contact normal pointing from the fixel into the workpiece (the direction
  in which the fixel can push it), t_i = n_i rotated by +90 degrees.
  On an edge (or the disc) n_i is the inward surface normal at p_i. When p_i is a polygon
  vertex, n_i is the direction from f_i to the vertex; a fixel centre closer than the
  contact tolerance to a vertex has no defined normal and is refused (give it a pin
  radius or move it off the vertex).
* Limits (tolerances.py): every length or coordinate (pose x, y, positions, vertices,
  com, radii, contact tolerance) within +-MAX_COORDINATE_M (1e9 m), |theta| <=
  MAX_ANGLE_RAD, mass and inertia in [MIN_MASS_INERTIA, MAX_MASS_INERTIA], friction <=
  MAX_FRICTION, the workpiece's characteristic length (largest distance from its com to
  its shape) at least MIN_LENGTH_SCALE_M (1e-12 m). Finite but absurd values (1e200 m,
  a disc of 1e-300 m) would overflow or underflow later; they are refused here with a
  SceneError naming the value and the limit.
* Fixels may coincide; each is an independent contact (their modes may then conflict,
  which shows up as an infeasible mode, not an error).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from .numbers import Arithmetic, Scalar
from .tolerances import (
    MAX_ANGLE_RAD,
    MAX_COORDINATE_M,
    MAX_FRICTION,
    MAX_MASS_INERTIA,
    MIN_LENGTH_SCALE_M,
    ACCEPTED_INERTIA_RATIO,
    AGREEMENT_ANGLE_RAD,
    MIN_MASS_INERTIA,
    VERIFIED_INERTIA_RATIO,
)


def _within(k: float, lo: float, hi: float) -> bool:
    """lo <= k <= hi up to a relative 1e-9: the studies' edge cases are lo and hi as
    rounded from k m L^2, so they stay inside."""
    return lo * (1 - 1e-9) <= k <= hi * (1 + 1e-9)


class SceneError(ValueError):
    """An invalid scene: says what was wrong and what is allowed."""


class UnverifiedRangeWarning(UserWarning):
    """A scene the core accepts but outside :data:`.tolerances.VERIFIED_INERTIA_RATIO`:
    answers near a cone's boundary may disagree between functions (directions, classify,
    check) by more than :data:`.tolerances.AGREEMENT_ANGLE_RAD`."""


def _finite(value: Any, what: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{what} must be a number, got {value!r}") from None
    if isinstance(value, bool) or not math.isfinite(x):
        raise SceneError(f"{what} must be a finite number, got {value!r}")
    return x


def _bounded(value: Any, what: str, limit: float, unit: str) -> float:
    """A finite number with |x| <= limit (tolerances.py names every limit)."""
    x = _finite(value, what)
    if abs(x) > limit:
        raise SceneError(f"{what} must be within +-{limit:g} {unit}, got {value!r}")
    return x


def _length(value: Any, what: str) -> float:
    """A length or coordinate (m): finite, |x| <= MAX_COORDINATE_M."""
    return _bounded(value, what, MAX_COORDINATE_M, "m")


def _positive(value: Any, what: str, unit: str, high: float = MAX_COORDINATE_M,
              low: float = 0.0) -> float:
    x = _finite(value, what)
    if x <= 0 or x < low:
        least = f" (at least {low:g})" if low else ""
        raise SceneError(f"{what} must be > 0 {unit}{least}, got {value!r}")
    if x > high:
        raise SceneError(f"{what} must be <= {high:g} {unit}, got {value!r}")
    return x


def _pose(p: Any) -> tuple[float, float, float]:
    """A pose [x m, y m, theta rad]: coordinates within MAX_COORDINATE_M, |theta| within
    MAX_ANGLE_RAD."""
    if type(p) is tuple and len(p) == 3:
        x, y, th = p
        if (type(x) is float and type(y) is float and type(th) is float
                and abs(x) <= MAX_COORDINATE_M and abs(y) <= MAX_COORDINATE_M
                and abs(th) <= MAX_ANGLE_RAD):
            # plain floats in range (nan fails the comparisons): what the checks below
            # return, without their calls (Scene.with_pose runs this once per pose)
            return p
    if isinstance(p, (str, bytes)) or not isinstance(p, Sequence) or len(p) != 3:
        raise SceneError(f"pose must be [x m, y m, theta rad], got {p!r}")
    return (_length(p[0], "pose[0] (x)"), _length(p[1], "pose[1] (y)"),
            _bounded(p[2], "pose[2] (theta)", MAX_ANGLE_RAD, "rad"))


def _point(value: Any, what: str) -> tuple[float, float]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != 2:
        raise SceneError(f"{what} must be a pair [x, y] in metres, got {value!r}")
    return (_length(value[0], f"{what}[0]"), _length(value[1], f"{what}[1]"))


@dataclass(frozen=True)
class Disc:
    """A disc centred at the workpiece frame's origin.

    Parameters
    ----------
    radius : float
        m, > 0.

    Raises
    ------
    SceneError
        The radius is not a positive finite number.
    """

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "disc radius", "m"))


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def _segments_intersect(p1, p2, q1, q2) -> bool:
    """Closed segments p1p2 and q1q2 share a point (orientation test)."""

    def orient(a, b, c) -> float:
        return _cross(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1])

    def on_seg(a, b, c) -> bool:
        return (min(a[0], b[0]) <= c[0] <= max(a[0], b[0])
                and min(a[1], b[1]) <= c[1] <= max(a[1], b[1]))

    d1, d2 = orient(q1, q2, p1), orient(q1, q2, p2)
    d3, d4 = orient(p1, p2, q1), orient(p1, p2, q2)
    if ((d1 > 0) != (d2 > 0)) and ((d3 > 0) != (d4 > 0)) and 0 not in (d1, d2, d3, d4):
        return True
    return ((d1 == 0 and on_seg(q1, q2, p1)) or (d2 == 0 and on_seg(q1, q2, p2))
            or (d3 == 0 and on_seg(p1, p2, q1)) or (d4 == 0 and on_seg(p1, p2, q2)))


@dataclass(frozen=True)
class Polygon:
    """A simple polygon in the workpiece frame.

    Parameters
    ----------
    vertices : tuple of (x, y)
        m, at least 3, counter-clockwise, no edge crossing another.

    Raises
    ------
    SceneError
        Fewer than 3 vertices, a repeated vertex, a coordinate that is not finite or
        beyond MAX_COORDINATE_M, a self-intersecting or zero-area outline, or clockwise
        order.
    """

    vertices: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        v = self.vertices
        if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < 3:
            raise SceneError(
                f"polygon vertices must be a list of at least 3 [x, y] pairs, got {v!r}")
        pts = tuple(_point(p, f"polygon vertex {k}") for k, p in enumerate(v))
        object.__setattr__(self, "vertices", pts)
        n = len(pts)
        if len(set(pts)) != n:
            raise SceneError("polygon vertices must be distinct (a vertex is repeated)")
        # simple and non-degenerate first: the orientation of a self-intersecting or
        # zero-area outline means nothing (a bow-tie has signed area 0)
        for i in range(n):
            for j in range(i + 1, n):
                if j == i + 1 or (i == 0 and j == n - 1):
                    continue  # adjacent edges share a vertex
                if _segments_intersect(pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n]):
                    raise SceneError(
                        f"polygon is not simple: edge {i} crosses edge {j} (edge k joins "
                        "vertex k to vertex k + 1)")
        area2 = sum(_cross(*pts[k], *pts[(k + 1) % n]) for k in range(n))
        if area2 == 0:
            raise SceneError("polygon is degenerate: zero area (its vertices lie on one "
                             "line)")
        if area2 < 0:
            raise SceneError(
                "polygon vertices must be counter-clockwise (signed area > 0); they are "
                f"clockwise: signed area {area2 / 2:.6g} m^2 (reverse their order)")


Shape = Disc | Polygon


@dataclass(frozen=True)
class Workpiece:
    """A rigid planar workpiece.

    Parameters
    ----------
    mass : float
        kg, > 0.
    inertia : float
        kg m^2, about the centre of mass, > 0.
    shape : Disc or Polygon
        In the workpiece frame.
    com : tuple of 2 float
        The centre of mass (m, workpiece frame).

    Raises
    ------
    SceneError
        A mass or inertia outside [MIN_MASS_INERTIA, MAX_MASS_INERTIA]
        (core/tolerances.py), a com that is not two finite numbers, or an
        I / (m L^2) outside ACCEPTED_INERTIA_RATIO.

    Warns
    -----
    UnverifiedRangeWarning
        I / (m L^2) outside VERIFIED_INERTIA_RATIO (accepted, with a caveat).
    """

    mass: float
    inertia: float
    shape: Shape
    com: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", _positive(
            self.mass, "workpiece mass", "kg", MAX_MASS_INERTIA, MIN_MASS_INERTIA))
        object.__setattr__(self, "inertia", _positive(
            self.inertia, "workpiece inertia", "kg m^2", MAX_MASS_INERTIA, MIN_MASS_INERTIA))
        object.__setattr__(self, "com", _point(self.com, "workpiece com"))
        if not isinstance(self.shape, (Disc, Polygon)):
            raise SceneError(f"workpiece shape must be a Disc or Polygon, got {self.shape!r}")
        L = self.length_scale
        if not L >= MIN_LENGTH_SCALE_M:
            raise SceneError(
                f"the workpiece's characteristic length (largest distance from its com to "
                f"its shape) is {L:.6g} m; it must be at least {MIN_LENGTH_SCALE_M:g} m "
                "(wrenches are compared as (f_x, f_y, tau / L))")
        k, (lo, hi) = self.inertia_ratio, ACCEPTED_INERTIA_RATIO
        if not _within(k, lo, hi):
            raise SceneError(
                f"the workpiece's I/(m L^2) is {k:.3g} (inertia {self.inertia:g} kg m^2, "
                f"mass {self.mass:g} kg, L = {L:.6g} m, the largest distance from its com "
                f"to its shape); it must lie in [{lo:g}, {hi:g}], the range over which the "
                "answers are checked (a rigid body has I/(m L^2) <= 1)")
        caveat = self.numerics_caveat
        if caveat is not None:
            warnings.warn(caveat, UnverifiedRangeWarning, stacklevel=3)

    @property
    def inertia_ratio(self) -> float:
        """I / (m L^2), dimensionless: the rotational stiffness of the problem (the
        nondimensional mass matrix is diag(1, 1, I / (m L^2)))."""
        L = self.length_scale
        return self.inertia / (self.mass * L * L)

    @property
    def numerics_caveat(self) -> str | None:
        """One line when :attr:`inertia_ratio` is outside
        :data:`~.tolerances.VERIFIED_INERTIA_RATIO`, else None."""
        lo, hi = VERIFIED_INERTIA_RATIO
        k = self.inertia_ratio
        if _within(k, lo, hi):
            return None
        return (f"I/(m L^2) = {k:.3g} is outside the verified range [{lo:g}, {hi:g}]: "
                "answers near a cone's boundary may disagree between functions "
                f"(directions, classify, check) by more than {AGREEMENT_ANGLE_RAD:g} rad; "
                "a rigid body has I/(m L^2) <= 1")

    @cached_property
    def length_scale(self) -> float:
        """Characteristic length L (m): largest distance from the com to the shape
        (computed once: the constructor's checks compute it first).

        Used to nondimensionalise wrenches: g_hat = (f_x, f_y, tau / L).
        """
        shape, (cx, cy) = self.shape, self.com
        if isinstance(shape, Disc):
            return math.hypot(cx, cy) + shape.radius
        return max(math.hypot(x - cx, y - cy) for x, y in shape.vertices)


@dataclass(frozen=True)
class Fixel:
    """A fixture contact: a point or a round pin, fixed in the world (fixture) frame.

    Parameters
    ----------
    position : tuple of 2 float
        m, world frame.
    radius : float
        m, >= 0: 0 for a point, the pin's radius otherwise.
    friction : float or None
        This fixel's friction coefficient; None: the scene's.

    Raises
    ------
    SceneError
        A position that is not two finite numbers or a negative radius.
    """

    position: tuple[float, float]
    radius: float = 0.0
    friction: float | None = None  # overrides the scene's friction coefficient

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _point(self.position, "fixel position"))
        r = _length(self.radius, "fixel radius")
        if r < 0:
            raise SceneError(f"fixel radius must be >= 0 m, got {self.radius!r}")
        object.__setattr__(self, "radius", r)
        if self.friction is not None:
            mu = _bounded(self.friction, "fixel friction", MAX_FRICTION, "(dimensionless)")
            if mu < 0:
                raise SceneError(f"fixel friction must be >= 0, got {self.friction!r}")
            object.__setattr__(self, "friction", mu)


@dataclass(frozen=True)
class ContactFrame:
    """Geometry of one fixel (docs/theory.md conventions), in the chosen arithmetic.

    ``p``, ``n``, ``t`` are world-frame; ``r_n`` and ``r_t`` are the moments about the
    com of unit forces along n and t at p (N m per N): ``r x n`` and ``r x t``.

    Parameters
    ----------
    index : int
        The fixel's index (0-based).
    p : numpy.ndarray
        The closest point of the workpiece to the fixel (m, world frame).
    gap : float
        The signed distance between fixel and workpiece (m; negative: penetration).
    n : numpy.ndarray
        The unit contact normal n_i, pointing into the workpiece (world frame).
    t : numpy.ndarray
        The unit tangent t_i, n_i rotated by +90 degrees.
    r_n : Scalar
        r x n (N m per N).
    r_t : Scalar
        r x t (N m per N).
    in_contact : bool
        Whether ``|gap|`` is within the contact tolerance.
    vertex : bool
        Whether the closest point is a polygon vertex.
    edge : int or None, optional
        The polygon edge k (vertices k, k+1) whose interior holds p.
    """

    index: int
    p: np.ndarray
    gap: float
    n: np.ndarray
    t: np.ndarray
    r_n: Scalar
    r_t: Scalar
    in_contact: bool
    vertex: bool  # closest point is a polygon vertex
    edge: int | None = None  # polygon edge k (vertices k, k+1) whose interior holds p


@dataclass(frozen=True)
class ContactArrays:
    """The float :class:`ContactFrame` of every fixel as arrays, row i fixel i: what the
    batch engine and the node's per-pose work read (no per-fixel Python objects).

    ``p``, ``n`` (n x 2, world frame), ``gap``, ``r_n``, ``r_t`` (n,), ``in_contact``,
    ``vertex`` (n,) bool, ``edge`` (n,) int, -1 where the closest point is no edge's
    interior. Read-only arrays."""

    p: np.ndarray
    gap: np.ndarray
    n: np.ndarray
    r_n: np.ndarray
    r_t: np.ndarray
    in_contact: np.ndarray
    vertex: np.ndarray
    edge: np.ndarray

    @staticmethod
    def of(frames: Sequence[ContactFrame]) -> ContactArrays:
        """The arrays of float contact frames (the reference path)."""
        out = ContactArrays(
            p=np.array([f.p for f in frames], dtype=float).reshape(-1, 2),
            gap=np.array([f.gap for f in frames], dtype=float),
            n=np.array([f.n for f in frames], dtype=float).reshape(-1, 2),
            r_n=np.array([f.r_n for f in frames], dtype=float),
            r_t=np.array([f.r_t for f in frames], dtype=float),
            in_contact=np.array([f.in_contact for f in frames], dtype=bool),
            vertex=np.array([f.vertex for f in frames], dtype=bool),
            edge=np.array([-1 if f.edge is None else f.edge for f in frames],
                          dtype=np.int64))
        out.freeze()
        return out

    def freeze(self) -> None:
        """Make every array read-only."""
        for a in (self.p, self.gap, self.n, self.r_n, self.r_t, self.in_contact,
                  self.vertex, self.edge):
            a.setflags(write=False)  # as a.flags.writeable = False, in half the time

    def frames(self) -> tuple[ContactFrame, ...]:
        """The same geometry as ContactFrame objects (float)."""
        out = []
        for i, (p, gap, n, r_n, r_t, inc, vtx, e) in enumerate(zip(
                self.p.tolist(), self.gap.tolist(), self.n.tolist(), self.r_n.tolist(),
                self.r_t.tolist(), self.in_contact.tolist(), self.vertex.tolist(),
                self.edge.tolist())):
            nv = np.array(n)
            out.append(ContactFrame(index=i, p=np.array(p), gap=gap, n=nv,
                                    t=np.array([-nv[1], nv[0]]), r_n=r_n, r_t=r_t,
                                    in_contact=inc, vertex=vtx,
                                    edge=None if e < 0 else e))
        return tuple(out)


def _disc_closest(radius: Scalar, f: tuple[Scalar, Scalar], ar: Arithmetic):
    """Closest boundary point, signed distance, inward normal, vertex flag and edge (None)
    for a disc (workpiece frame)."""
    dist = ar.sqrt(f[0] * f[0] + f[1] * f[1])
    if dist == 0:
        raise SceneError("a fixel is at the centre of the disc: contact normal undefined")
    ox, oy = f[0] / dist, f[1] / dist
    return (radius * ox, radius * oy), dist - radius, (-ox, -oy), False, None


def _inside_polygon(pts, f) -> bool:
    """Ray-crossing point-in-polygon (boundary points may go either way)."""
    inside = False
    n = len(pts)
    for k in range(n):
        (x1, y1), (x2, y2) = pts[k], pts[(k + 1) % n]
        if (y1 > f[1]) != (y2 > f[1]):
            x = x1 + (f[1] - y1) * (x2 - x1) / (y2 - y1)
            if f[0] < x:
                inside = not inside
    return inside


def _polygon_closest(pts, f, ar: Arithmetic, tol: float):
    """Closest boundary point, signed distance, inward normal, vertex flag and edge index
    (None at a vertex), workpiece frame. On an edge the normal is the edge's own (the same
    numbers for every fixel on that edge)."""
    best = None
    n = len(pts)
    for k in range(n):
        (x1, y1), (x2, y2) = pts[k], pts[(k + 1) % n]
        ex, ey = x2 - x1, y2 - y1
        s = ((f[0] - x1) * ex + (f[1] - y1) * ey) / (ex * ex + ey * ey)
        s = min(max(s, 0), 1)
        qx, qy = x1 + s * ex, y1 + s * ey
        dx, dy = f[0] - qx, f[1] - qy
        d2 = dx * dx + dy * dy  # products, not ** 2: C pow() is not always correctly rounded
        if best is None or d2 < best[0]:
            best = (d2, (qx, qy), s, ex, ey, k)
    d2, q, s, ex, ey, k = best
    dist = ar.sqrt(d2)
    signed = -dist if _inside_polygon(pts, f) else dist
    if 0 < s < 1:
        le = ar.sqrt(ex * ex + ey * ey)
        return q, signed, (-ey / le, ex / le), False, k
    if float(dist) <= tol:
        raise SceneError(
            f"the fixel centre is within the contact tolerance ({tol:.3g} m) of polygon "
            f"vertex ({float(q[0]):.6g}, {float(q[1]):.6g}): the contact normal is "
            "undefined at a vertex; give the fixel a pin radius or move it onto an edge")
    nx, ny = (q[0] - f[0]) / dist, (q[1] - f[1]) / dist
    return q, signed, (nx, ny), True, None


#: The function computing a scene's float contact arrays ahead of the reference (None: it
#: refuses): the engines register it (:mod:`.engines`), so that the data model, below
#: them, asks for it here and does not choose the engine.
_contact_geometry = None


def use_contact_geometry(fn) -> None:
    """Register the function that computes :attr:`.scene.Scene.contact_arrays`.

    Parameters
    ----------
    fn : callable or None
        ``fn(scene) -> ContactArrays | None`` (None: leave the scene to the reference
        :meth:`.scene.Scene.contact_frames`); None: the reference only.
    """
    global _contact_geometry
    _contact_geometry = fn


def fast_contact_arrays(scene: Any) -> ContactArrays | None:
    """A scene's float contact arrays from the registered function (:func:`use_contact_geometry`).

    Parameters
    ----------
    scene : wrenchcone_ros.core.Scene
        The scene.

    Returns
    -------
    ContactArrays or None
        The arrays, or None when no function is registered or it refuses the scene (the
        caller then computes the reference :meth:`.scene.Scene.contact_frames`).
    """
    return None if _contact_geometry is None else _contact_geometry(scene)


__all__ = ["Disc", "Polygon", "Shape", "Workpiece", "Fixel", "ContactFrame",
           "SceneError", "UnverifiedRangeWarning", "use_contact_geometry",
           "fast_contact_arrays"]
