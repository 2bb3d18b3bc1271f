# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Polyhedral cones in R^3: both representations, canonical form, membership and margin.

A cone is stored in the nondimensional wrench space g_hat = (f_x, f_y, tau / L) (see
:mod:`wrenchcone_ros.core.dynamics`) and exposed to users in SI units:

* ``F`` (k x 3): inequality rows, ``F g <= 0``. Each row is a unit vector in the
  nondimensional metric: ``F = F_hat S``, ``S = diag(1, 1, 1/L)``, ``|F_hat_i| = 1``.
  When the cone has equalities, the rows of F_hat are orthogonal to them.
* ``equalities`` (e x 3): ``E g = 0`` (rows orthonormal in the same metric). Present
  exactly when the cone has an empty interior.
* ``G`` (p x 3): extreme rays as rows (unit length in the nondimensional metric, then
  mapped back: ``G = G_hat S^-1``), taken modulo the lineality space.
* ``lineality`` (l x 3): orthonormal basis (nondimensional metric) of the lines in the cone.

Special cones: all of R^3 has no F, no equalities, lineality = identity; {0} has
equalities = identity and nothing else; a half-space has one F row, one ray and a
2-dimensional lineality. An *infeasible* mode (no wrench realises the open mode,
docs/theory.md, "Closure versus the mode itself") is reported with ``feasible = False``
and the representation of {0}; ``contains`` is then False for every wrench and
``closure`` keeps the paper's (misleading) closure cone for diagnostics.

Margin: for a wrench g with unit nondimensional direction u = g_hat / |g_hat|, the
signed Euclidean distance from u to the boundary of the cone, positive inside: inside
a full-dimensional cone it is min_i(-F_hat_i u); outside it is -dist(u, cone) (closed
form over the cone's faces, :class:`_Query`, checked against a non-negative
least-squares projection onto the generators). Members of a cone with an
empty interior have margin 0 (they lie on its boundary). All of R^3 gives +1, an
infeasible mode gives -1, g = 0 gives 0. Hence margin is in [-1, 1], dimensionless and
invariant to the units and magnitude of g.
"""

from __future__ import annotations

from collections.abc import Sequence
import math
from dataclasses import dataclass, field, replace
from functools import cached_property, update_wrapper
from fractions import Fraction
from typing import Any

import cdd
import cdd.gmp
import numpy as np

from . import cone3d, stats
from .tolerances import CONE_TOLERANCE, RANK_TOLERANCE

_EMPTY = np.zeros((0, 3))


def _lib(exact: bool):
    return cdd.gmp if exact else cdd


def _matrix(rows: list, lin_set, rep_type, exact: bool):
    """A cddlib matrix; the exact library gets Fractions (floats converted exactly)."""
    if exact:
        rows = [[Fraction(x) for x in r] for r in rows]
        return cdd.gmp.matrix_from_array(rows, lin_set=lin_set, rep_type=rep_type)
    return cdd.matrix_from_array(rows, lin_set=lin_set, rep_type=rep_type)


def _rows(a: Any) -> list[list]:
    return [list(r) for r in a]


#: How often a float conversion (cddlib, or cone3d in cone_from_hrep/cone_from_vrep) failed
#: and was redone exactly on the same data (docs/numerics.md); lives in :mod:`.stats`.
FALLBACKS = stats.FALLBACKS


def _with_exact_fallback(fn):
    """Run a float cddlib conversion; if cddlib reports a numerical inconsistency, redo it
    in exact arithmetic on the same (float) input and return floats."""

    def wrapper(a, b, exact: bool):
        if exact:
            return fn(a, b, True)
        FALLBACKS["float_calls"] += 1
        try:
            return fn(a, b, False)
        except RuntimeError:
            FALLBACKS["exact_fallbacks"] += 1
            out = fn(a, b, True)
            return tuple(_scaled_floats(part) for part in out)

    return update_wrapper(wrapper, fn)


def _nonzero(row: Sequence) -> bool:
    return any(x != 0 for x in row)


@_with_exact_fallback
def hrep_to_vrep(ineq: Sequence, eq: Sequence, exact: bool) -> tuple[list, list]:
    """Generators of {x : d.x >= 0 for d in ineq, e.x = 0 for e in eq} (cddlib).

    In float, a conversion that cddlib reports as numerically inconsistent is redone in
    exact arithmetic on the same input (counted in ``FALLBACKS``).

    Parameters
    ----------
    ineq : sequence of rows
        The rows d of the inequalities d . x >= 0.
    eq : sequence of rows
        The rows e of the equalities e . x = 0.
    exact : bool
        Convert in exact rational arithmetic (cddlib's GMP mode) rather than float.

    Returns
    -------
    rays : list of list
        The extreme rays, rows in the input's number type.
    lines : list of list
        A basis of the lineality space, rows in the input's number type.
    """
    dim = 3 if not (len(ineq) or len(eq)) else len((list(ineq) + list(eq))[0])
    rows = [[0, *d] for d in ineq if _nonzero(d)] + [[0, *e] for e in eq if _nonzero(e)]
    n_ineq = sum(1 for d in ineq if _nonzero(d))
    if not rows:
        eye = [[1 if i == j else 0 for j in range(dim)] for i in range(dim)]
        return [], eye
    lib = _lib(exact)
    mat = _matrix(rows, range(n_ineq, len(rows)), cdd.RepType.INEQUALITY, exact)
    gen = lib.copy_generators(lib.polyhedron_from_matrix(mat))
    rays, lines = [], []
    for k, row in enumerate(gen.array):
        if row[0] != 0 or not _nonzero(row[1:]):
            continue  # the apex
        (lines if k in gen.lin_set else rays).append(list(row[1:]))
    return rays, lines


@_with_exact_fallback
def vrep_to_hrep(rays: Sequence, lines: Sequence, exact: bool) -> tuple[list, list]:
    """Face normals of pos(rays) + span(lines) (cddlib): the cone is {F x <= 0, E x = 0}.

    In float, a conversion that cddlib reports as numerically inconsistent is redone in
    exact arithmetic on the same input (counted in ``FALLBACKS``).

    Parameters
    ----------
    rays : sequence of rows
        The generators; zero rows are dropped.
    lines : sequence of rows
        Directions of lines in the cone.
    exact : bool
        Convert in exact rational arithmetic (cddlib's GMP mode) rather than float.

    Returns
    -------
    F : list of list
        The inequality rows (F x <= 0), possibly redundant.
    E : list of list
        The equality rows (E x = 0).
    """
    gens = [list(r) for r in rays if _nonzero(r)]
    lin = [list(r) for r in lines if _nonzero(r)]
    if not gens and not lin:
        dim = len(rays[0]) if len(rays) else (len(lines[0]) if len(lines) else 3)
        return [], [[1 if i == j else 0 for j in range(dim)] for i in range(dim)]
    dim = len((gens + lin)[0])
    rows = [[1] + [0] * dim] + [[0, *r] for r in gens] + [[0, *r] for r in lin]
    lib = _lib(exact)
    mat = _matrix(rows, range(1 + len(gens), len(rows)), cdd.RepType.GENERATOR, exact)
    h = lib.copy_inequalities(lib.polyhedron_from_matrix(mat))
    F, E = [], []
    for k, row in enumerate(h.array):
        a = list(row[1:])
        if not _nonzero(a):
            continue  # the trivial row 1 >= 0
        if k in h.lin_set:
            E.append(a)
        else:
            F.append([-x for x in a])
    return F, E


# --- float post-processing ----------------------------------------------------------
def _scaled_floats(rows: Sequence) -> list[list[float]]:
    """Float rows, each scaled by its largest |entry| first (an exact row may have entries
    beyond the float range, e.g. from denormal inputs; the direction is what matters)."""
    out = []
    for r in rows:
        m = max((abs(x) for x in r), default=0)
        out.append([float(x / m) if m else 0.0 for x in r])
    return out


def _to_float(rows: Sequence) -> np.ndarray:
    if not len(rows):
        return _EMPTY.copy()
    return np.array(_scaled_floats(rows), dtype=float).reshape(-1, 3)


def _orthonormal_rows(rows: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the row space (SVD; rank from a relative cut-off)."""
    if rows.shape[0] == 0:
        return _EMPTY.copy()
    _, s, vt = np.linalg.svd(rows, full_matrices=False)
    rank = int(np.sum(s > s[0] * RANK_TOLERANCE)) if s.size and s[0] > 0 else 0
    basis = vt[:rank]
    # a sign convention that makes the basis reproducible: first nonzero entry positive
    for k in range(rank):
        j = int(np.argmax(np.abs(basis[k]) > RANK_TOLERANCE))
        if basis[k, j] < 0:
            basis[k] = -basis[k]
    return basis


def _unit_rows_orthogonal_to(rows: np.ndarray, basis: np.ndarray) -> np.ndarray:
    if rows.shape[0] == 0:
        return _EMPTY.copy()
    if basis.shape[0]:
        rows = rows - (rows @ basis.T) @ basis
    norms = np.linalg.norm(rows, axis=1)
    keep = norms > RANK_TOLERANCE
    return rows[keep] / norms[keep, None]


@dataclass(frozen=True)
class ExactRep:
    """Exact (Fraction) canonical representation in nondimensional coordinates.

    Parameters
    ----------
    F : tuple of tuple of Fraction
        The inequality rows (F g_hat <= 0).
    E : tuple of tuple of Fraction
        The equality rows (E g_hat = 0).
    G : tuple of tuple of Fraction
        The extreme rays.
    lines : tuple of tuple of Fraction
        A basis of the lineality space.
    """

    F: tuple[tuple[Fraction, ...], ...]
    E: tuple[tuple[Fraction, ...], ...]
    G: tuple[tuple[Fraction, ...], ...]
    lines: tuple[tuple[Fraction, ...], ...]


@dataclass(frozen=True)
class Cone:
    """The cone of wrenches consistent with one augmented contact mode.

    A wrench g = (fx N, fy N, tz N m) is consistent with the mode iff ``F g <= 0`` and
    ``E g = 0`` (Balkcom and Trinkle, 2002, Theorem 1: the cone's face representation);
    equivalently g is a non-negative combination of the generators G plus a vector of
    the lineality space. The arrays ending in ``_hat`` are in the nondimensional metric
    ``g_hat = (fx, fy, tz / L)``, where every row is a unit vector; ``F``, ``equalities``,
    ``G`` and ``lineality`` are the same rows in SI units.

    Parameters
    ----------
    mode : str
        The mode, one letter per fixel.
    feasible : bool
        Whether some wrench realises the open mode; an infeasible mode's cone contains
        nothing (its closure is :attr:`closure`).
    F_hat, E_hat, G_hat, L_hat : numpy.ndarray
        Faces, equalities, generators and a basis of the lineality space, (k, 3) each,
        nondimensional.
    length_scale : float
        L (m): the largest distance from the com to the workpiece's shape.
    method : str
        The algorithm that computed the cone (``planar`` or ``paper``).
    exact : bool
        Whether it was computed in exact rational arithmetic.
    exact_rep : ExactRep or None
        The exact rows, when ``exact``.
    closure : Cone or None
        For an infeasible mode, the closed cone Theorem 1 gives (for inspection only).
    """

    mode: str
    feasible: bool
    F_hat: np.ndarray
    E_hat: np.ndarray
    G_hat: np.ndarray
    L_hat: np.ndarray
    length_scale: float
    method: str
    exact: bool
    exact_rep: ExactRep | None = None
    closure: Cone | None = field(default=None, repr=False)

    # --- SI views -------------------------------------------------------------------
    @cached_property
    def _s(self) -> np.ndarray:
        return np.array([1.0, 1.0, 1.0 / self.length_scale])

    @cached_property
    def _rows(self) -> np.ndarray:
        """F stacked on E and -E (SI), for a single matrix product in contains()."""
        return np.vstack([self.F, self.equalities, -self.equalities])

    @cached_property
    def F(self) -> np.ndarray:
        """Inequality rows: g consistent iff F g <= 0 (and equalities g = 0); read-only
        (computed once; the batch engine computes a batch's at once)."""
        F = self.F_hat * self._s
        F.flags.writeable = False
        return F

    @property
    def equalities(self) -> np.ndarray:
        """Equality rows: E g = 0 for every g in the cone."""
        return self.E_hat * self._s

    @property
    def G(self) -> np.ndarray:
        """Extreme rays (rows), modulo the lineality space."""
        return self.G_hat / self._s

    @property
    def lineality(self) -> np.ndarray:
        """Basis (rows) of the largest linear subspace contained in the cone."""
        return self.L_hat / self._s

    @property
    def full_dimensional(self) -> bool:
        """Whether the cone is feasible and spans all of wrench space (no equality row)."""
        return self.feasible and self.E_hat.shape[0] == 0

    def nondimensional(self, g: Sequence[float]) -> np.ndarray:
        """g_hat = S g = (f_x, f_y, tau / L).

        Parameters
        ----------
        g : sequence of 3 float
            (fx N, fy N, tz N m).

        Returns
        -------
        numpy.ndarray
            g_hat, shape (3,).
        """
        g = np.asarray(g, dtype=float).reshape(3)
        return g * self._s

    # --- queries --------------------------------------------------------------------
    @property
    def prepared(self) -> _Query:
        """The cone's float rows as :meth:`check` and :func:`margins_at` read them.

        Returns
        -------
        _Query
            Prepared once per cone (unit rows, rays, projections; nondimensional).
        """
        return self._query

    @cached_property
    def _query(self) -> _Query:
        return _Query(self)

    def check(self, g: Sequence[float]) -> tuple[bool, float]:
        """``(contains(g), margin(g))`` in one pass (the hot path of the node).

        Parameters
        ----------
        g : sequence of 3 float
            (fx N, fy N, tz N m), fixture frame.

        Returns
        -------
        contains : bool
            As :meth:`contains` with the default tolerance.
        margin : float
            As :meth:`margin`.

        Raises
        ------
        ValueError
            g is not finite.
        """
        return self._query.check(g)

    def contains(self, g: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        """Whether the wrench g is consistent with the mode.

        Parameters
        ----------
        g : sequence of 3 float
            (fx N, fy N, tz N m), fixture frame.
        tol : float
            Dimensionless: ``F_hat u <= tol`` and ``|E_hat u| <= tol`` for the unit
            nondimensional direction u of g (default CONE_TOLERANCE, core/tolerances.py).

        Returns
        -------
        bool
            Membership of the closed cone; always False for an infeasible mode.

        Raises
        ------
        ValueError
            g is not finite.
        """
        if tol == CONE_TOLERANCE:
            return self._query.check(g)[0]
        if not self.feasible:
            return False
        g = np.asarray(g, dtype=float).reshape(3)
        gh = g * self._s
        norm = math.sqrt(gh @ gh)
        if not math.isfinite(norm):
            raise ValueError(f"wrench must be finite, got {g.tolist()}")
        rows = self._rows
        return norm == 0 or rows.shape[0] == 0 or float((rows @ g).max()) <= tol * norm

    def margin(self, g: Sequence[float]) -> float:
        """The signed distance of g's direction to the cone's boundary.

        Parameters
        ----------
        g : sequence of 3 float
            (fx N, fy N, tz N m), fixture frame.

        Returns
        -------
        float
            Dimensionless, in [-1, 1]: the Euclidean distance of the unit nondimensional
            direction u of g to the cone's boundary, positive inside, negative outside
            (invariant to units and to the wrench's magnitude); -1 for an infeasible mode.

        Raises
        ------
        ValueError
            g is not finite.
        """
        return self._query.check(g)[1]

    def check_many(self, G: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(contains_many(G), margin_many(G))`` in one pass over an (N, 3) array.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3) (or one wrench of shape (3,)), SI units.

        Returns
        -------
        contains : numpy.ndarray
            bool, shape (N,).
        margins : numpy.ndarray
            float, shape (N,).

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        return self._query.check_many(G)

    def contains_many(self, G: Any, tol: float = CONE_TOLERANCE) -> np.ndarray:
        """:meth:`contains` of every row of the (N, 3) array G (bool array of length N),
        vectorised; elementwise identical to the scalar calls (the same floating-point
        operations in the same order). Raises ValueError if a row is not finite.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3), SI units.
        tol : float, optional
            As in :meth:`contains`.

        Returns
        -------
        numpy.ndarray
            bool, shape (N,).

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        if tol == CONE_TOLERANCE:
            return self._query.check_many(G, margins=False)[0]
        G = _wrench_rows(G)
        if not self.feasible:
            return np.zeros(G.shape[0], dtype=bool)
        gh = G * self._s
        norm = np.sqrt(_dot_rows(gh, gh))
        _require_finite(norm, G)
        rows = self._rows
        if rows.shape[0] == 0:
            return np.ones(G.shape[0], dtype=bool)
        return (norm == 0) | ((G @ rows.T).max(axis=1) <= tol * norm)

    def margin_many(self, G: Any) -> np.ndarray:
        """:meth:`margin` of every row of the (N, 3) array G (float array of length N),
        vectorised; elementwise identical to the scalar calls.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3), SI units.

        Returns
        -------
        numpy.ndarray
            float, shape (N,), each in [-1, 1].

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        return self._query.check_many(G)[1]

    def distance(self, u: np.ndarray) -> float:
        """Euclidean distance from a nondimensional vector u to the cone, by non-negative
        least squares on the generators: the general (slower) reference that the
        closed form of :class:`_Query` is tested against.

        Parameters
        ----------
        u : numpy.ndarray
            A nondimensional vector, shape (3,).

        Returns
        -------
        float
            The distance from u to the cone (0 inside).
        """
        gens = [self.G_hat, self.L_hat, -self.L_hat]
        A = np.vstack(gens).T
        if A.shape[1] == 0:
            return float(np.linalg.norm(u))
        from scipy.optimize import nnls  # lazy: scipy.optimize takes 0.6 s to import

        _, res = nnls(A, np.asarray(u, dtype=float))
        return float(res)

    def to_dict(self) -> dict:
        """The cone as JSON-able data.

        Returns
        -------
        dict
            ``mode``, ``feasible``, ``F``, ``equalities``, ``G``, ``lineality`` (SI
            units, lists of rows), ``length_scale`` (m), ``method``, ``exact``.
        """
        return {
            "mode": self.mode,
            "feasible": self.feasible,
            "F": self.F.tolist(),
            "equalities": self.equalities.tolist(),
            "G": self.G.tolist(),
            "lineality": self.lineality.tolist(),
            "length_scale": self.length_scale,
            "method": self.method,
            "exact": self.exact,
        }


def _t(rows: np.ndarray) -> tuple[tuple[float, float, float], ...]:
    return tuple((float(a), float(b), float(c)) for a, b, c in np.asarray(rows).reshape(-1, 3))


def _wrench_rows(G: Any) -> np.ndarray:
    G = np.asarray(G, dtype=float)
    if G.ndim == 1 and G.shape[0] == 3:
        G = G[None, :]
    if G.ndim != 2 or G.shape[1] != 3:
        raise ValueError(f"wrenches must be an (N, 3) array of (f_x, f_y, tau), got shape "
                         f"{G.shape}")
    return G


def _dot_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise a . b as (a0 b0 + a1 b1) + a2 b2: the scalar code's order of operations."""
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def _require_finite(norm: np.ndarray, G: np.ndarray) -> None:
    bad = ~np.isfinite(norm)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ValueError(f"wrench must be finite, got {G[k].tolist()} (row {k})")


_EYE3 = np.eye(3)
_EYE3.flags.writeable = False


Hat = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]  # F_hat, E_hat, G_hat, L_hat


def margin_geometries(hats: Sequence[Hat]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The geometry of the margin outside each of several cones (see :class:`_Query`),
    from their unit nondimensional rows ``(F_hat, E_hat, G_hat, L_hat)``: per cone, the
    unit extreme rays orthogonal to the lineality space (k, 3), and the projections onto
    the planes of its faces (m, 3, 3): ``I - f f^T`` for each facet normal f of a
    full-dimensional cone, else ``I - E^T E`` (the cone's own span).

    The one definition: :class:`_Query` (one cone) and the node's compiled check_wrench
    lane (every monitored cone of a snapshot) use it. The rows of all cones are handled
    in one numpy pass: a cone at a time cost about 9 us, most of it numpy's per-call
    overhead, which the lane paid for every monitored cone of every pose.

    Parameters
    ----------
    hats : sequence of tuple of numpy.ndarray
        Per cone, its ``(F_hat, E_hat, G_hat, L_hat)``.

    Returns
    -------
    list of tuple of numpy.ndarray
        Per cone, ``(unit rays (k, 3), projections (m, 3, 3))``.
    """
    if not hats:
        return []
    # without a lineality space, G minus its (zero) projection onto it is G itself
    rays = np.concatenate([G - G @ (L.T @ L) if L.shape[0] else G for _, _, G, L in hats])
    norms = np.linalg.norm(rays, axis=1)
    keep = norms > RANK_TOLERANCE
    unit = rays / np.where(keep, norms, 1.0)[:, None]
    F_all = np.concatenate([F for F, _, _, _ in hats])
    facet_planes = _EYE3 - F_all[:, :, None] * F_all[:, None, :]
    ray_ends = np.cumsum([G.shape[0] for _, _, G, _ in hats])
    facet_ends = np.cumsum([F.shape[0] for F, _, _, _ in hats])
    out = []
    ray_start = facet_start = 0
    for (_, E, _, _), ray_end, facet_end in zip(hats, ray_ends, facet_ends):
        cone_keep = keep[ray_start:ray_end]
        cone_rays = unit[ray_start:ray_end]
        if not cone_keep.all():
            cone_rays = cone_rays[cone_keep]
        if E.shape[0] == 0:
            planes = facet_planes[facet_start:facet_end]
        else:
            planes = (_EYE3 - E.T @ E)[None]
        out.append((cone_rays, planes))
        ray_start, facet_start = ray_end, facet_end
    return out


def margin_geometry(F_hat: np.ndarray, E_hat: np.ndarray, G_hat: np.ndarray,
                    L_hat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`margin_geometries` of one cone.

    Parameters
    ----------
    F_hat, E_hat, G_hat, L_hat : numpy.ndarray
        The cone's unit nondimensional rows.

    Returns
    -------
    tuple of numpy.ndarray
        The unit rays (k, 3) and the projections (m, 3, 3).
    """
    return margin_geometries([(F_hat, E_hat, G_hat, L_hat)])[0]


class _Query:
    """contains() and margin() of a Cone, precomputed as plain floats (a few microseconds).

    The margin of a wrench outside the cone is minus the distance of its unit
    nondimensional direction u to the cone. In R^3 the nearest point of a polyhedral cone
    lies in the relative interior of one of its faces, so the distance is the smallest
    |u - p| over the projections p of u onto (a) the apex, (b) the lineality space and
    each extreme ray plus it (clamped to t >= 0), (c) each facet plane and the cone's own
    span, when p lies in the cone. test/core/test_cones.py checks this against the NNLS
    distance (:meth:`Cone.distance`) on every kind of cone and on every mode of several
    scenes.
    """

    def __init__(self, cone: Cone) -> None:
        self.feasible = bool(cone.feasible)
        self.inv_l = 1.0 / float(cone.length_scale)
        self.F, self.E = _t(cone.F_hat), _t(cone.E_hat)  # E rows are orthonormal
        # the arrays, not the cone: no reference cycle through Cone._query
        self._hat = (cone.F_hat, cone.E_hat, cone.G_hat, cone.L_hat)

    # The geometry of the margin outside the cone (lineality, unit rays, face
    # projections) is built on first use: a wrench inside the cone needs only F and E,
    # and building it all took most of a one-off check on a fresh cone (the node's
    # check_wrench on a new pose: 85-130 us of 90-135).
    @cached_property
    def L(self) -> tuple[tuple[float, float, float], ...]:
        return _t(self._hat[3])  # orthonormal rows

    @cached_property
    def _geometry(self) -> tuple[np.ndarray, np.ndarray]:
        return margin_geometry(*self._hat)

    @cached_property
    def rays(self) -> tuple[tuple[float, float, float], ...]:
        return _t(self._geometry[0])

    @cached_property
    def projections(self) -> tuple[tuple[tuple[float, float, float], ...], ...]:
        return tuple(_t(P) for P in self._geometry[1])

    def check(self, g: Sequence[float]) -> tuple[bool, float]:
        if not self.feasible:
            return False, -1.0
        x, y, z = float(g[0]), float(g[1]), float(g[2]) * self.inv_l
        norm = math.sqrt(x * x + y * y + z * z)
        if not math.isfinite(norm):
            raise ValueError(f"wrench must be finite, got {[float(v) for v in g]}")
        if norm == 0:
            return True, 0.0
        x, y, z = x / norm, y / norm, z / norm
        F, E = self.F, self.E
        if not F and not E:
            return True, 1.0
        fmax, emax = self._extremes(x, y, z)
        contains = fmax <= CONE_TOLERANCE and emax <= CONE_TOLERANCE
        if fmax <= 0.0 and emax == 0.0:
            return contains, (0.0 if E else 0.0 - fmax)  # 0 - 0.0 is +0.0
        return contains, self._margin_outside(x, y, z)

    def arrays(self) -> tuple[np.ndarray, ...]:
        """The rows :meth:`check` reads, as float arrays: F (k, 3), E (e, 3), L (l, 3),
        the unit rays (r, 3) and the face projections (m, 9, each 3x3 row by row), the
        same doubles as the tuples; the margin's geometry only for a cone that needs it
        (feasible, with rows). The compiled checks (``Engine.cone_checks``) pack them."""
        F, E, _G, L = (np.asarray(a, dtype=float).reshape(-1, 3) for a in self._hat)
        if not self.feasible or (not len(F) and not len(E)):
            empty = np.zeros((0, 3))
            return F, E, L, empty, np.zeros((0, 9))
        rays, projections = self._geometry
        return (F, E, L, np.asarray(rays, dtype=float).reshape(-1, 3),
                np.asarray(projections, dtype=float).reshape(-1, 9))

    @cached_property
    def _outside(self) -> tuple:
        """The constants of the margin outside the cone, flat: L, the unit rays, and each
        face projection as one 9-tuple (row by row)."""
        return (self.L, self.rays,
                tuple(tuple(v for row in P for v in row) for P in self.projections))

    def margin_unit(self, x: float, y: float, z: float) -> float:
        """``check(g)[1]`` of a feasible cone with rows, from the unit nondimensional
        direction (x, y, z) of g: the same float operations in the same order as
        :meth:`check` (so the same double), written out for speed (no generators,
        projections unrolled); :func:`margins_at` calls it."""
        fmax, emax = self._extremes(x, y, z)
        if fmax <= 0.0 and emax == 0.0:
            return 0.0 if self.E else 0.0 - fmax
        return self._margin_outside(x, y, z)

    def _extremes(self, x: float, y: float, z: float) -> tuple[float, float]:
        """(the largest F row . u, the largest |E row . u|) of a unit nondimensional
        direction u = (x, y, z), as max() takes them (the first largest; -inf and 0 for
        no rows), written out for speed: :meth:`check` and :meth:`margin_unit`."""
        fmax = -math.inf
        for a, b, c in self.F:
            v = a * x + b * y + c * z
            if v > fmax:
                fmax = v
        emax = 0.0
        for a, b, c in self.E:
            v = abs(a * x + b * y + c * z)
            if v > emax:
                emax = v
        return fmax, emax

    def _margin_outside(self, x: float, y: float, z: float) -> float:
        """The margin of a unit direction (x, y, z) outside the cone or on a facet (the
        rest of :meth:`margin_unit` and :meth:`check`): minus its distance to the
        nearest of the apex, the lineality space, a ray plus it, a facet's projection
        inside the cone (class docstring)."""
        F, E = self.F, self.E
        L, rays, projections = self._outside
        lin2 = 0.0  # v * v, not v ** 2: C's pow() can differ from the product in the
        for a, b, c in L:  # last bit, and check_many's numpy square is the product
            v = a * x + b * y + c * z
            lin2 = lin2 + v * v
        best2 = 1.0 - lin2
        if rays:
            t = None
            for a, b, c in rays:
                v = a * x + b * y + c * z
                if t is None or v > t:
                    t = v
            if t > 0:
                v = 1.0 - lin2 - t * t
                if v < best2:  # min(): the first smallest
                    best2 = v
        tol, sqrt = CONE_TOLERANCE, math.sqrt
        for p0, p1, p2, p3, p4, p5, p6, p7, p8 in projections:
            px = p0 * x + p1 * y + p2 * z
            py = p3 * x + p4 * y + p5 * z
            pz = p6 * x + p7 * y + p8 * z
            bound = tol * sqrt(px * px + py * py + pz * pz)
            inside = True
            for a, b, c in F:
                if a * px + b * py + c * pz > bound:
                    inside = False
                    break
            if inside:
                for a, b, c in E:
                    if abs(a * px + b * py + c * pz) > bound:
                        inside = False
                        break
            if inside:
                dx, dy, dz = x - px, y - py, z - pz
                v = dx * dx + dy * dy + dz * dz
                if v < best2:
                    best2 = v
        return 0.0 - sqrt(0.0 if 0.0 > best2 else best2)  # max(best2, 0.0)

    def check_many(self, G: Any, margins: bool = True) -> tuple[np.ndarray, np.ndarray | None]:
        """:meth:`check` of every row of G, vectorised with the same float operations in
        the same order (so the results are identical elementwise); ``margins=False``
        skips the margins (None)."""
        G = _wrench_rows(G)
        N = G.shape[0]
        if not self.feasible:
            return np.zeros(N, dtype=bool), np.full(N, -1.0)
        x, y, z = G[:, 0], G[:, 1], G[:, 2] * self.inv_l
        norm = np.sqrt(x * x + y * y + z * z)
        _require_finite(norm, G)
        zero = norm == 0
        safe = np.where(zero, 1.0, norm)
        x, y, z = x / safe, y / safe, z / safe
        if not self.F and not self.E:
            return np.ones(N, dtype=bool), np.where(zero, 0.0, 1.0)
        fmax = np.full(N, -np.inf)
        for a, b, c in self.F:
            fmax = np.maximum(fmax, a * x + b * y + c * z)
        emax = np.zeros(N)
        for a, b, c in self.E:
            emax = np.maximum(emax, np.abs(a * x + b * y + c * z))
        contains = (fmax <= CONE_TOLERANCE) & (emax <= CONE_TOLERANCE)
        if not margins:
            return contains | zero, None
        inside = (fmax <= 0.0) & (emax == 0.0)
        lin2 = np.zeros(N)
        for a, b, c in self.L:
            v = a * x + b * y + c * z
            lin2 = lin2 + v * v
        best2 = 1.0 - lin2
        t = np.zeros(N)
        for a, b, c in self.rays:
            t = np.maximum(t, a * x + b * y + c * z)
        best2 = np.where(t > 0, np.minimum(best2, 1.0 - lin2 - t * t), best2)
        for P in self.projections:
            px, py, pz = ((a * x + b * y + c * z) for a, b, c in P)
            ok = self._in_cone_many(px, py, pz)
            dx, dy, dz = x - px, y - py, z - pz
            best2 = np.where(ok, np.minimum(best2, dx * dx + dy * dy + dz * dz), best2)
        margin = 0.0 - np.sqrt(np.maximum(best2, 0.0))  # +0.0 on the boundary, as check
        margin = np.where(inside, 0.0 if self.E else 0.0 - fmax, margin)
        contains = contains | zero
        return contains, np.where(zero, 0.0, margin)

    def _in_cone_many(self, px: np.ndarray, py: np.ndarray, pz: np.ndarray) -> np.ndarray:
        bound = CONE_TOLERANCE * np.sqrt(px * px + py * py + pz * pz)
        ok = np.ones(px.shape[0], dtype=bool)
        for a, b, c in self.F:
            ok &= a * px + b * py + c * pz <= bound
        for a, b, c in self.E:
            ok &= np.abs(a * px + b * py + c * pz) <= bound
        return ok


def margins_at(cones: Sequence[Cone], g: Sequence[float]) -> list[float]:
    """``[c.margin(g) for c in cones]``, the same doubles, at a fraction of the cost.

    The wrench is read and normalised once for every run of cones with the same length
    scale (the cones of one scene), and each margin is computed by
    :meth:`_Query.margin_unit`: the scalar :meth:`Cone.margin`'s floating-point
    operations in the same order, without its per-call overhead (tested equal to it,
    ``==``, on random cones and wrenches). The direction searches call it for every
    direction they try.

    Parameters
    ----------
    cones : sequence of Cone
        The cones.
    g : sequence of 3 float
        (fx N, fy N, tz N m), fixture frame.

    Returns
    -------
    list of float
        One margin per cone, in order.

    Raises
    ------
    ValueError
        g is not finite (as :meth:`Cone.margin` raises it, at the first feasible cone).
    """
    g0, g1, g2 = float(g[0]), float(g[1]), float(g[2])
    out = []
    inv = norm = None
    x = y = z = 0.0
    for cone in cones:
        q = cone.prepared
        if not q.feasible:
            out.append(-1.0)
            continue
        if q.inv_l != inv:  # the same operations as _Query.check
            inv = q.inv_l
            x, y, z = g0, g1, g2 * inv
            norm = math.sqrt(x * x + y * y + z * z)
            if not math.isfinite(norm):
                inv = None
                raise ValueError(f"wrench must be finite, got {[float(v) for v in g]}")
            if norm != 0:
                x, y, z = x / norm, y / norm, z / norm
        if norm == 0:
            out.append(0.0)
        elif not q.F and not q.E:
            out.append(1.0)
        else:
            out.append(q.margin_unit(x, y, z))
    return out


def cone_from_hrep(F: Sequence, E: Sequence, *, mode: str, length_scale: float,
                   method: str, exact: bool) -> Cone:
    """Canonical Cone from a (possibly redundant) face representation in nondim coords.

    Float: :mod:`.cone3d` (self-checking; on a failed check the same data is converted
    exactly). Exact: cddlib GMP through the generators (two double-description
    conversions): cddlib's LP-based ``matrix_canonicalize`` is not used, its float
    version aborted the process (invalid free / SIGSEGV) on a nearly flat cone found by
    the stress cross-check (test_crosscheck.py, REGRESSION_CASES).

    Parameters
    ----------
    F : sequence of rows
        Inequality rows, F g_hat <= 0.
    E : sequence of rows
        Equality rows, E g_hat = 0.
    mode : str
        The mode the cone belongs to.
    length_scale : float
        L (m).
    method : str
        The method that computed the rows (``planar`` or ``paper``).
    exact : bool
        Whether the rows are exact (Fractions): convert with cddlib GMP.

    Returns
    -------
    Cone
        The canonical cone.
    """
    if not exact:
        ineq = -np.asarray(F, dtype=float).reshape(-1, 3)
        return _float_or_exact(lambda: cone3d.from_inequalities(
            ineq, np.asarray(E, dtype=float).reshape(-1, 3)), lambda: cone_from_hrep(
            F, E, mode=mode, length_scale=length_scale, method=method, exact=True),
            mode, length_scale, method)
    rays, lines = hrep_to_vrep([[-x for x in f] for f in F], E, exact)
    return cone_from_vrep(rays, lines, mode=mode, length_scale=length_scale, method=method,
                          exact=exact)


def cone_from_vrep(rays: Sequence, lines: Sequence, *, mode: str, length_scale: float,
                   method: str, exact: bool) -> Cone:
    """Canonical Cone from (possibly redundant) generators in nondim coords (float:
    :mod:`.cone3d` with an exact fallback, as :func:`cone_from_hrep`).

    Parameters
    ----------
    rays : sequence of rows
        Generators.
    lines : sequence of rows
        Directions of lines in the cone.
    mode : str
        The mode the cone belongs to.
    length_scale : float
        L (m).
    method : str
        The method that computed the rows (``planar`` or ``paper``).
    exact : bool
        Whether the rows are exact (Fractions): convert with cddlib GMP.

    Returns
    -------
    Cone
        The canonical cone.
    """
    if not exact:
        return _float_or_exact(lambda: cone3d.from_generators(
            np.asarray(rays, dtype=float).reshape(-1, 3),
            np.asarray(lines, dtype=float).reshape(-1, 3)), lambda: cone_from_vrep(
            rays, lines, mode=mode, length_scale=length_scale, method=method, exact=True),
            mode, length_scale, method)
    F, E = vrep_to_hrep(rays, lines, exact)
    rays_c, lines_c = hrep_to_vrep([[-x for x in f] for f in F], E, exact)
    return _assemble(F, E, rays_c, lines_c, mode=mode, length_scale=length_scale,
                     method=method, exact=exact)


def from_cone3(c: cone3d.Cone3, mode: str, length_scale: float, method: str) -> Cone:
    """A float Cone from a cone3d result (rows sorted, negative zeros cleared).

    Parameters
    ----------
    c : Cone3
        The cone in both representations, nondimensional.
    mode : str
        The mode the cone belongs to.
    length_scale : float
        L (m).
    method : str
        The method that computed it.

    Returns
    -------
    Cone
        The canonical float cone.
    """
    return Cone(mode, True, _sorted_rows(c.F + 0.0), c.E + 0.0, _sorted_rows(c.rays + 0.0),
                c.lines + 0.0, float(length_scale), method, False)


def _float_or_exact(convert, exact, mode, length_scale, method) -> Cone:
    FALLBACKS["float_calls"] += 1
    try:
        return from_cone3(convert(), mode, length_scale, method)
    except cone3d.Cone3Error:
        FALLBACKS["exact_fallbacks"] += 1
        return as_float(exact())


def _sorted_rows(rows: np.ndarray) -> np.ndarray:
    """Rows in a reproducible order (lexicographic, descending, on values rounded to 12
    decimals so that round-off does not reorder them) so methods compare row by row."""
    if rows.shape[0] < 2:
        return rows
    keys = [tuple(-round(x, 12) for x in r) for r in rows.tolist()]
    return rows[sorted(range(len(keys)), key=keys.__getitem__)]


def _assemble(F, E, rays, lines, *, mode, length_scale, method, exact) -> Cone:
    E_hat = _orthonormal_rows(_to_float(E))
    L_hat = _orthonormal_rows(_to_float(lines))
    F_hat = _sorted_rows(_unit_rows_orthogonal_to(_to_float(F), E_hat))
    G_hat = _sorted_rows(_unit_rows_orthogonal_to(_to_float(rays), L_hat))
    rep = None
    if exact:
        def fr(rows):
            return tuple(tuple(Fraction(x) for x in r) for r in rows)
        rep = ExactRep(fr(F), fr(E), fr(rays), fr(lines))
    return Cone(mode, True, F_hat, E_hat, G_hat, L_hat, float(length_scale), method, exact,
                rep)


def as_float(cone: Cone) -> Cone:
    """An exact result handed back by a float method (its floats, exact=False).

    Parameters
    ----------
    cone : Cone
        A cone, exact or float.

    Returns
    -------
    Cone
        The same cone (and closure) without the exact representation.
    """
    closure = as_float(cone.closure) if cone.closure is not None else None
    return replace(cone, exact=False, exact_rep=None, closure=closure)


def assembled_cone(mode: str, feasible: bool, F_hat: np.ndarray, E_hat: np.ndarray,
                   G_hat: np.ndarray, L_hat: np.ndarray, length_scale: float, method: str,
                   closure: Cone | None = None, *, F: np.ndarray | None = None,
                   s: np.ndarray | None = None) -> Cone:
    """A float Cone from fields already canonical (the batch engine's hot path): the same
    object the dataclass constructor makes, without its per-field frozen setattr calls.

    Parameters
    ----------
    mode : str
        The mode.
    feasible : bool
        Whether the open mode is possible.
    F_hat, E_hat, G_hat, L_hat : numpy.ndarray
        The canonical unit rows, nondimensional.
    length_scale : float
        L (m).
    method : str
        The method that computed the rows.
    closure : Cone or None, optional
        The closure of an infeasible mode.
    F : numpy.ndarray or None, optional
        The SI inequality rows when the caller has them (read-only, the same doubles as
        ``F_hat * s``): :attr:`Cone.F` is then not computed again.
    s : numpy.ndarray or None, optional
        With ``F``: the scale row [1, 1, 1 / L] (read-only), :attr:`Cone.nondimensional`'s.

    Returns
    -------
    Cone
        A float cone.
    """
    cone = object.__new__(Cone)
    attrs = {"mode": mode, "feasible": feasible, "F_hat": F_hat, "E_hat": E_hat,
             "G_hat": G_hat, "L_hat": L_hat, "length_scale": length_scale, "method": method,
             "exact": False, "exact_rep": None, "closure": closure}
    if F is not None:  # the cached properties Cone.F and Cone._s, already computed
        attrs["F"] = F
        attrs["_s"] = s
    _set_dict(cone, "__dict__", attrs)
    return cone


#: Sets an instance's __dict__ past a frozen dataclass's __setattr__ (assembled_cone).
_set_dict = object.__setattr__

_EMPTY_RO = np.zeros((0, 3))
_EYE_RO = np.eye(3)
_EMPTY_RO.flags.writeable = False
_EYE_RO.flags.writeable = False


def infeasible_float_cone(closure: Cone, s: np.ndarray | None = None) -> Cone:
    """:func:`infeasible_cone` for a float closure, sharing read-only constant arrays.

    Parameters
    ----------
    closure : Cone
        The closed cone Theorem 1 gives, float.
    s : numpy.ndarray or None, optional
        The scale row [1, 1, 1 / L] (read-only) when the caller has it: the cone's
        :attr:`Cone.F` (no rows) is then set, not computed.

    Returns
    -------
    Cone
        The infeasible cone.
    """
    return assembled_cone(closure.mode, False, _EMPTY_RO, _EYE_RO, _EMPTY_RO, _EMPTY_RO,
                          closure.length_scale, closure.method, closure,
                          F=None if s is None else _EMPTY_RO, s=s)


def infeasible_cone(closure: Cone) -> Cone:
    """The answer for a mode no wrench can realise: {0}'s representation, feasible False.

    Parameters
    ----------
    closure : Cone
        The closed cone Theorem 1 gives.

    Returns
    -------
    Cone
        Contains only the zero wrench; ``closure`` kept for inspection.
    """
    return Cone(closure.mode, False, _EMPTY.copy(), np.eye(3), _EMPTY.copy(), _EMPTY.copy(),
                closure.length_scale, closure.method, closure.exact, None, closure)
