# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Force regions: the forces at a point that give a contact mode together with a fixed
extra wrench (a spring preload, the gravity of a tilted tray).

With no extra wrench the region is the 2-D cone of force directions
(:func:`.directions.force_directions`); with one it is a convex polygon, possibly
unbounded, computed in rational arithmetic (:func:`force_region`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

import cdd
import numpy as np

from .batch import mode_union
from .cones import _matrix
from .directions import _nondim_basis, force_basis
from .numbers import to_exact
from .scene import Scene
from .tolerances import CONE_TOLERANCE


# --- force regions ----------------------------------------------------------------------
@dataclass(frozen=True)
class ForceRegion:
    """The forces f (N, fixture frame) at a point with ``offset + B f`` consistent with one
    concrete mode: {f : A f <= b, A_eq f = b_eq}, a convex polygon, possibly unbounded,
    = conv(vertices) + cone(rays) + span(lines) (pycddlib, exact arithmetic on the float
    rows). Rows are the cone's nondimensional facets and equalities traced on the plane:
    A = F_hat S B, b = -F_hat S offset (and likewise for the equalities).

    Parameters
    ----------
    mode : str
        The concrete mode.
    A : numpy.ndarray
        Inequality rows, (k, 2), each scaled like a unit facet row.
    b : numpy.ndarray
        Their right-hand sides, (k,).
    A_eq : numpy.ndarray
        Equality rows, (e, 2).
    b_eq : numpy.ndarray
        Their right-hand sides, (e,).
    vertices : numpy.ndarray
        (v, 2), N.
    rays : numpy.ndarray
        (r, 2).
    lines : numpy.ndarray
        (l, 2).
    offset : tuple of 3 float
        The fixed extra wrench (fx N, fy N, tz N m).
    B : numpy.ndarray
        The force basis, 3 x 2 (:func:`.directions.force_basis`).
    length_scale : float
        L (m).
    """

    mode: str
    A: np.ndarray
    b: np.ndarray
    A_eq: np.ndarray
    b_eq: np.ndarray
    vertices: np.ndarray
    rays: np.ndarray
    lines: np.ndarray
    offset: tuple[float, float, float]
    B: np.ndarray
    length_scale: float

    @property
    def bounded(self) -> bool:
        """Whether the region is a polygon (no ray, no line)."""
        return self.rays.shape[0] == 0 and self.lines.shape[0] == 0

    def contains(self, f: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        """f meets every row within ``tol`` times |S (offset + B f)| (CONE_TOLERANCE, the
        tolerance of :meth:`Cone.contains`, dimensionless).

        Parameters
        ----------
        f : sequence of 2 float
            A force (N, fixture frame).
        tol : float, optional
            Dimensionless tolerance.

        Returns
        -------
        bool
            True inside.
        """
        f = np.asarray(f, dtype=float).reshape(2)
        g = np.asarray(self.offset) + self.B @ f
        scale = tol * float(np.linalg.norm(g * np.array([1.0, 1.0, 1.0 / self.length_scale])))
        return bool(np.all(self.A @ f - self.b <= scale)
                    and np.all(np.abs(self.A_eq @ f - self.b_eq) <= scale))

    def to_dict(self) -> dict:
        """The region as JSON-able data.

        Returns
        -------
        dict
            ``mode``, ``A``, ``b``, ``A_eq``, ``b_eq``, ``vertices``, ``rays``, ``lines``.
        """
        return {k: (getattr(self, k).tolist() if isinstance(getattr(self, k), np.ndarray)
                    else getattr(self, k))
                for k in ("mode", "A", "b", "A_eq", "b_eq", "vertices", "rays", "lines")}


def _polygon(A: np.ndarray, b: np.ndarray, A_eq: np.ndarray, b_eq: np.ndarray):
    """Vertices, rays, lines of {A f <= b, A_eq f = b_eq} (cddlib GMP; rows of Fractions);
    None when empty."""
    rows = [[bi, *(-x for x in a)] for a, bi in zip(A.tolist(), b.tolist())]
    rows += [[bi, *(-x for x in a)] for a, bi in zip(A_eq.tolist(), b_eq.tolist())]
    if not rows:
        return np.zeros((1, 2)), np.zeros((0, 2)), np.eye(2)
    mat = _matrix(rows, range(A.shape[0], len(rows)), cdd.RepType.INEQUALITY, True)
    gen = cdd.gmp.copy_generators(cdd.gmp.polyhedron_from_matrix(mat))
    verts, rays, lines = [], [], []
    for k, row in enumerate(gen.array):
        if k in gen.lin_set:
            lines.append([float(row[1]), float(row[2])])
        elif row[0] != 0:
            verts.append([float(row[1] / row[0]), float(row[2] / row[0])])
        else:
            rays.append([float(row[1]), float(row[2])])
    if not verts:
        # cddlib lists no vertex for a cone (every b = 0): the apex, the origin, is implied
        if not (rays or lines) or any(x < 0 for x in b) or any(x != 0 for x in b_eq):
            return None
        verts = [[0.0, 0.0]]

    def arr(x):
        return np.array(x, dtype=float).reshape(-1, 2)

    return arr(verts), arr(rays), arr(lines)


def force_region(scene: Scene, mode: str, point: Sequence[float] | None = None,
                 offset: Sequence[float] = (0.0, 0.0, 0.0)) -> list[ForceRegion]:
    """The forces f (N) at ``point`` such that ``offset + wrench(f)`` is consistent with
    ``mode``: one convex :class:`ForceRegion` per feasible concrete mode whose region is
    not empty (a wildcard mode gives the union of the list; a concrete mode at most one).

    ``offset`` (fx N, fy N, tz N m about the com, fixture frame) is a fixed extra wrench:
    a spring preload, gravity of a tilted tray. With offset 0 the region is the 2-D cone
    of :func:`.directions.force_directions`. The polygon is computed in rational arithmetic from the
    exact cone, the exact basis and the offset's floats taken exactly: float facet traces
    that are parallel in exact arithmetic would otherwise meet at spurious far vertices.
    Rows are returned as floats, each scaled like a unit facet row of the cone (F_hat).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The mode, wildcards allowed.
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    offset : sequence of 3 float, optional
        A fixed extra wrench (fx N, fy N, tz N m).

    Returns
    -------
    list of ForceRegion
        One per feasible concrete mode with a nonempty region.

    Raises
    ------
    ValueError
        ``offset`` is not three finite numbers, or a bad point.
    ModeError
        The mode is not valid for the scene's contacts.
    """
    o = np.asarray(offset, dtype=float).reshape(3)
    if not np.all(np.isfinite(o)):
        raise ValueError(f"offset must be three finite numbers (N, N, N m), got {list(offset)}")
    B = force_basis(scene, point)
    B_hat = _nondim_basis(scene, force_basis(scene, point, exact=True), True)
    L = to_exact(scene.length_scale)
    o_hat = np.array([Fraction(o[0]), Fraction(o[1]), Fraction(o[2]) / L], dtype=object)
    out = []
    for cone in mode_union(scene, mode, exact=True).pieces:
        rep = cone.exact_rep
        F = np.array(rep.F, dtype=object).reshape(-1, 3)
        E = np.array(rep.E, dtype=object).reshape(-1, 3)
        A, A_eq, b, b_eq = F @ B_hat, E @ B_hat, -(F @ o_hat), -(E @ o_hat)
        poly = _polygon(A, b, A_eq, b_eq)
        if poly is None:
            continue

        def unit(M, v, rows):
            n = np.array([math.sqrt(sum(float(x) ** 2 for x in r)) for r in rows])
            Mf = np.array(M, dtype=float).reshape(-1, 2) / n.reshape(-1, 1) if len(n) else \
                np.zeros((0, 2))
            return Mf, np.array(v, dtype=float).reshape(-1) / n if len(n) else np.zeros(0)

        (Af, bf), (Aef, bef) = unit(A, b, F), unit(A_eq, b_eq, E)
        out.append(ForceRegion(cone.mode, Af, bf, Aef, bef, *poly, tuple(o.tolist()), B,
                               float(scene.length_scale)))
    return out


__all__ = ["ForceRegion", "force_region"]
