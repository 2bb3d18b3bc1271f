# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The Scene type: a workpiece at a pose and its fixels, with the contact geometry of
:mod:`wrenchcone_ros.core.geometry` computed on first use (docs/theory.md, "Model and
conventions").

Scenes are read from YAML files and dicts by :mod:`.scene_yaml`
(:func:`~.scene_yaml.load_scene`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from functools import cached_property

import numpy as np

from .geometry import (
    ContactArrays,
    ContactFrame,
    Disc,
    Fixel,
    Polygon,
    SceneError,
    Workpiece,
    _bounded,
    _disc_closest,
    _polygon_closest,
    _pose,
    _positive,
    fast_contact_arrays,
)
from .numbers import FLOAT, Arithmetic
from .tolerances import (
    CONTACT_TOLERANCE_M,
    COORDINATE_RESOLUTION_ULPS,
    MAX_FRICTION,
)


@dataclass(frozen=True)
class Scene:
    """Everything a wrench cone depends on: the workpiece at its pose and the fixels.

    Immutable; :meth:`with_pose` and ``dataclasses.replace`` make changed copies. The
    contact geometry (gaps, closest points, the contact frames (n_i, t_i) of the paper's
    section 2) is computed from these fields on first use.

    Parameters
    ----------
    workpiece : Workpiece
        The workpiece (mass, inertia, shape, com).
    fixels : tuple of Fixel
        The fixels, at least one, in the order of a mode's letters (fixel 1 first).
    friction : float
        The Coulomb friction coefficient mu (dimensionless, >= 0) of every fixel without
        its own.
    pose : tuple of 3 float
        The workpiece frame in the world frame: x (m), y (m), theta (rad).
    contact_tolerance : float
        m: a fixel with ``|gap| <= tol`` touches the workpiece (the tolerance applied is
        ``effective_contact_tolerance``).
    modes : tuple of str
        Modes the scene file names (for the node's monitored modes and the CLI).

    Raises
    ------
    SceneError
        An invalid field, a fixel inside the workpiece (a gap below ``-tol``), or a
        coordinate or angle outside the verified range (MAX_COORDINATE_M,
        MAX_ANGLE_RAD), with what is allowed.
    """

    workpiece: Workpiece
    fixels: tuple[Fixel, ...]
    friction: float
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    contact_tolerance: float = CONTACT_TOLERANCE_M
    modes: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        mu = _bounded(self.friction, "friction", MAX_FRICTION, "(dimensionless)")
        if mu < 0:
            raise SceneError(f"friction must be >= 0, got {self.friction!r}")
        object.__setattr__(self, "friction", mu)
        object.__setattr__(self, "pose", _pose(self.pose))
        object.__setattr__(self, "contact_tolerance", _positive(
            self.contact_tolerance, "contact_tolerance", "m"))
        fixels = tuple(self.fixels)
        if not fixels:
            raise SceneError("a scene needs at least one fixel")
        for k, fx in enumerate(fixels):
            if not isinstance(fx, Fixel):
                raise SceneError(f"fixel {k + 1} must be a Fixel, got {fx!r}")
        object.__setattr__(self, "fixels", fixels)
        modes = self.modes
        if isinstance(modes, str):
            modes = (modes,)
        object.__setattr__(self, "modes", tuple(modes))
        _ = self.contact_arrays  # validate geometry now: penetrations, vertex normals

    # --- derived quantities ---------------------------------------------------------
    @property
    def n_fixels(self) -> int:
        """The number of fixels, n."""
        return len(self.fixels)

    def mu(self, i: int) -> float:
        """Friction coefficient at fixel i (0-based).

        Parameters
        ----------
        i : int
            The fixel's index (0-based).

        Returns
        -------
        float
            Its own friction coefficient, or the scene's.
        """
        f = self.fixels[i].friction
        return self.friction if f is None else f

    @cached_property
    def com_world(self) -> np.ndarray:
        """Centre of mass in the world frame (m)."""
        x, y, th = self.pose
        cx, cy = self.workpiece.com
        c, s = math.cos(th), math.sin(th)
        return np.array([x + c * cx - s * cy, y + s * cx + c * cy])

    @cached_property
    def length_scale(self) -> float:
        """Characteristic length L (m) of the workpiece (:attr:`Workpiece.length_scale`,
        at least MIN_LENGTH_SCALE_M): g_hat = (f_x, f_y, tau / L)."""
        return self.workpiece.length_scale

    @cached_property
    def contact_arrays(self) -> ContactArrays:
        """Float contact geometry of all fixels as arrays (validated).

        Computed by the contact-geometry function the engine module registers
        (:func:`~wrenchcone_ros.core.geometry.use_contact_geometry`: the default
        engine's, the same doubles as the reference), else, or where it refuses a fixel,
        from the reference
        :meth:`contact_frames`, which raises the worded SceneError.
        """
        out = fast_contact_arrays(self)
        if out is None:
            return ContactArrays.of(self.contacts)
        return out

    @cached_property
    def fixel_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Fixel positions (n x 2), radii (n,) and polygon vertices (m x 2; 0 rows for a
        disc) as arrays: pose-independent, carried over by :meth:`with_pose`."""
        shape = self.workpiece.shape
        verts = (np.zeros((0, 2)) if isinstance(shape, Disc)
                 else np.array(shape.vertices, dtype=float))
        return (np.array([f.position for f in self.fixels], dtype=float).reshape(-1, 2),
                np.array([f.radius for f in self.fixels], dtype=float), verts)

    @cached_property
    def fixel_friction(self) -> np.ndarray:
        """The friction coefficient of each fixel, (n,), read-only (:meth:`mu` of each):
        pose-independent, carried over by :meth:`with_pose`."""
        mu = np.array([self.friction if f.friction is None else f.friction
                       for f in self.fixels], dtype=float)
        mu.setflags(write=False)
        return mu

    @cached_property
    def contacts(self) -> tuple[ContactFrame, ...]:
        """Float contact frames of all fixels (validated)."""
        arrays = self.__dict__.get("contact_arrays")
        if arrays is not None:
            return arrays.frames()
        return self.contact_frames(FLOAT)

    @cached_property
    def effective_contact_tolerance(self) -> float:
        """The contact tolerance actually applied (m): ``contact_tolerance``, raised to
        COORDINATE_RESOLUTION_ULPS units in the last place of the largest world coordinate
        when that is coarser (about 1.5e-8 m at 1e7 m from the origin). A tolerance below
        what a double can resolve would make the contact state depend on how the same
        numbers are rounded (float vs exact arithmetic)."""
        x, y, _ = self.pose
        resolution = COORDINATE_RESOLUTION_ULPS * math.ulp(max(abs(x), abs(y),
                                                              self._fixel_extent))
        return max(self.contact_tolerance, resolution)

    @cached_property
    def _fixel_extent(self) -> float:
        """The largest |coordinate| of a fixel position (m), 0 without fixels: the
        pose-free part of :attr:`effective_contact_tolerance`."""
        return max((abs(v) for f in self.fixels for v in f.position), default=0.0)

    @cached_property
    def in_contact(self) -> tuple[bool, ...]:
        return tuple(self.contact_arrays.in_contact.tolist())

    @cached_property
    def gaps(self) -> tuple[float, ...]:
        return tuple(self.contact_arrays.gap.tolist())

    def contact_frames(self, ar: Arithmetic) -> tuple[ContactFrame, ...]:
        """Closest points, gaps, frames and moment arms of all fixels in arithmetic ``ar``.

        The geometry is done in the workpiece frame relative to the com, so world offsets
        cost only the unavoidable rounding of ``f_i - pose``.

        Parameters
        ----------
        ar : Arithmetic
            Float or exact arithmetic (:func:`~wrenchcone_ros.core.numbers.arithmetic`).

        Returns
        -------
        tuple of ContactFrame
            One per fixel, in fixel order.

        Raises
        ------
        SceneError
            A fixel penetrates the workpiece by more than the contact tolerance, or its
            closest point is not defined.
        """
        x, y, th = (ar.convert(v) for v in self.pose)
        c, s = ar.cos_sin(th)
        com = tuple(ar.convert(v) for v in self.workpiece.com)
        shape = self.workpiece.shape
        tol = self.effective_contact_tolerance
        pts = None
        if isinstance(shape, Polygon):
            pts = [tuple(ar.convert(v) for v in p) for p in shape.vertices]
        frames = []
        for i, fixel in enumerate(self.fixels):
            fx, fy = (ar.convert(v) for v in fixel.position)
            dx, dy = fx - x, fy - y
            f_w = (c * dx + s * dy, -s * dx + c * dy)  # R(theta)^T (f - pose)
            try:
                if pts is None:
                    q, signed, nw, vertex, edge = _disc_closest(
                        ar.convert(shape.radius), f_w, ar)
                else:
                    q, signed, nw, vertex, edge = _polygon_closest(pts, f_w, ar, tol)
            except SceneError as exc:
                raise SceneError(f"fixel {i + 1}: {exc}") from None
            gap = float(signed) - fixel.radius
            if gap < -tol:
                raise SceneError(
                    f"fixel {i + 1} at ({fixel.position[0]:.6g}, {fixel.position[1]:.6g}) m "
                    f"penetrates the workpiece by {-gap:.6g} m (contact tolerance "
                    f"{tol:.3g} m); fixels must lie outside or on the boundary")
            tw = (-nw[1], nw[0])
            rx, ry = q[0] - com[0], q[1] - com[1]
            # r x t is the same at every point of a straight edge: take it at the edge's
            # first vertex, so fixels on one edge get identical tangential rows by
            # construction (not rows that differ by rounding, see constraints.nearly_parallel)
            ax, ay = (rx, ry) if edge is None else (pts[edge][0] - com[0], pts[edge][1] - com[1])
            p = np.array([x + c * q[0] - s * q[1], y + s * q[0] + c * q[1]],
                         dtype=object if ar.exact else float)
            n = np.array([c * nw[0] - s * nw[1], s * nw[0] + c * nw[1]],
                         dtype=object if ar.exact else float)
            t = np.array([-n[1], n[0]], dtype=n.dtype)
            frames.append(ContactFrame(
                index=i, p=p, gap=gap, n=n, t=t,
                r_n=rx * nw[1] - ry * nw[0], r_t=ax * tw[1] - ay * tw[0],
                in_contact=abs(gap) <= tol, vertex=vertex, edge=edge))
        return tuple(frames)

    # --- functional updates ---------------------------------------------------------
    def with_pose(self, x: float, y: float, theta: float) -> Scene:
        """The same scene at another pose: only the pose is validated again (the rest
        was when this scene was made), and what does not depend on the pose (length
        scale, fixel arrays) is carried over; the contact geometry is computed (and
        validated) for the new pose as in the constructor.

        Parameters
        ----------
        x, y : float
            The workpiece frame's origin in the world frame (m).
        theta : float
            Its rotation (rad).

        Returns
        -------
        Scene
            The scene at the new pose.

        Raises
        ------
        SceneError
            The pose is outside the verified range, or a fixel penetrates the workpiece there.
        """
        new = object.__new__(Scene)
        values = {k: self.__dict__[k] for k in _SCENE_FIELDS}
        values["pose"] = _pose((x, y, theta))
        values.update((k, self.__dict__[k]) for k in _POSE_FREE if k in self.__dict__)
        new.__dict__.update(values)
        _ = new.contact_arrays
        return new

    def with_fixels(self, positions: Sequence[Sequence[float]], radius: float = 0.0) -> Scene:
        """The same scene with other fixels, all of one radius (and the scene's friction).

        Parameters
        ----------
        positions : sequence of (x, y)
            The fixels' positions (m, world frame).
        radius : float, optional
            Their radius (m).

        Returns
        -------
        Scene
            The new scene.

        Raises
        ------
        SceneError
            A position is not valid, or a fixel penetrates the workpiece.
        """
        return replace(self, fixels=tuple(Fixel(tuple(p), radius) for p in positions))

    def to_dict(self) -> dict:
        """The YAML/dict form accepted by :func:`~.scene_yaml.load_scene`.

        Returns
        -------
        dict
            ``workpiece``, ``friction``, ``contact_tolerance``, ``fixels``, ``modes``.
        """
        shape = self.workpiece.shape
        if isinstance(shape, Disc):
            sd: dict = {"type": "disc", "radius": shape.radius}
        else:
            sd = {"type": "polygon", "vertices": [list(v) for v in shape.vertices]}
        fixels = []
        for f in self.fixels:
            d: dict = {"position": list(f.position), "radius": f.radius}
            if f.friction is not None:
                d["friction"] = f.friction
            fixels.append(d)
        return {
            "workpiece": {"mass": self.workpiece.mass, "inertia": self.workpiece.inertia,
                          "com": list(self.workpiece.com), "shape": sd,
                          "pose": list(self.pose)},
            "friction": self.friction,
            "contact_tolerance": self.contact_tolerance,
            "fixels": fixels,
            "modes": list(self.modes),
        }


_SCENE_FIELDS = tuple(f.name for f in fields(Scene))
#: Cached properties of a Scene that do not depend on its pose (Scene.with_pose).
_POSE_FREE = ("length_scale", "fixel_arrays", "_fixel_extent", "fixel_friction")


__all__ = ["Scene"]
