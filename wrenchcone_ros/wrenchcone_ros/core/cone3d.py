# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Float polyhedral cones in R^3 without cddlib: both representations from either one.

A :class:`Cone3` holds, for a closed convex polyhedral cone K in R^3, with the conventions
of :mod:`wrenchcone_ros.core.cones`:

* ``F`` (m x 3): unit rows, ``K = {x : F x <= 0, E x = 0}``, irredundant, orthogonal to E;
* ``E`` (e x 3): orthonormal rows, present exactly when K has an empty interior;
* ``rays`` (p x 3): unit extreme rays, orthogonal to ``lines``, irredundant;
* ``lines`` (l x 3): orthonormal basis of the lineality space.

Special cones: R^3 has only ``lines`` = a basis of R^3; {0} has only ``E`` = a basis of
R^3; a half-space has one F row, one ray and two lines; a ray has one F row, one ray and
two E rows; a line has one line and two E rows; a half-plane one F row, one ray, one line
and one E row; a plane two lines and one E row; a 2-D wedge two F rows, two rays and one
E row; a wedge + line two F rows, two rays and one line.

Algorithm (docs/cone3d.md). :func:`from_generators` (K = pos(rays) + span(lines)):

1. rows are normalised (zero rows dropped). The lines' span B: one line as is, two by a
   Gram-Schmidt step on l2 -+ l1, more by an SVD (rank cut-off ``CONE3_ANGLE_TOLERANCE``).
   The rays are projected onto the complement Q of B (rays within that angle of B are
   dropped). K = span(B) + K_Q, K_Q a cone in Q;
2. dim Q = 1: K_Q is {0}, a ray or the line (signs of the projections); dim Q = 2: one
   angular sort of the rays in Q (Python floats) gives {0}, a ray, a line, a wedge, a
   half-plane or the plane (the largest gap between consecutive directions against pi);
3. dim Q = 3 (no lines): two rays and three rays in general position are done on Python
   floats. Otherwise every ordered pair of rays gives a candidate normal
   n = r_i x r_j / |r_i x r_j| (all of them from one matrix product); pairs with a sine
   below 1e-2 are recomputed as r_i x (r_j -+ r_i): the difference of nearly
   (anti)parallel unit vectors is exact, so n is accurate to a few eps whatever the
   angle. Pairs with a sine <= ``CONE3_ANGLE_TOLERANCE`` are parallel and give none. n is
   a facet normal iff every ray has ``r . n <= CONE3_FACET_TOLERANCE``. Generic pointed
   cone (>= 3 facets, each through exactly its own two rays, as many rays on two facets
   as facets): done. Else n and -n both facets means a planar set (step 2 in that plane,
   E = n); otherwise candidates closer than twice the tolerance are merged. No facet:
   R^3. One: a half-space. Two: a wedge + the line where they meet. Three or more: a
   pointed cone whose extreme rays are the (deduplicated) rays on two facets.

:func:`from_inequalities` (K = {x : D x >= 0, Eq x = 0}) is the same computation on the
polar cone K° = pos(-D) + span(Eq): the facets of K are the extreme rays of K°, the
equalities of K the lines of K°, the rays of K the facets of K°, the lines of K the
equalities of K°.

Verification: every result is checked cheaply before it is returned (the generators are
on the right side of every facet by construction; a pointed cone must have as many facets
as extreme rays, each ray on exactly two facets and each facet through exactly two rays;
a wedge + line needs rays along both directions of its line; a half-space needs rays
positively spanning its plane; merged facets must be close to the facet kept). A failed
check raises :class:`Cone3Error` (a ``RuntimeError``, like cddlib's float failures): the
caller then redoes the conversion with exact cddlib (:mod:`wrenchcone_ros.core.cones`,
``exact=True``).

Float only. Tolerances are the dimensionless ``CONE3_*`` constants of
:mod:`wrenchcone_ros.core.tolerances` (angles between unit vectors). The result is the
exact cone of an input perturbed by about those angles: inputs whose degeneracies are
exact (coplanar rays, r and -r, duplicates) or clearly absent (separations well above
1e-10 rad) agree with exact cddlib; between the two, the answer is a nearby cone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .tolerances import CONE3_ANGLE_TOLERANCE, CONE3_FACET_TOLERANCE

__all__ = ["Cone3", "Cone3Error", "from_generators", "from_inequalities"]

_ANG = CONE3_ANGLE_TOLERANCE
_TOL = CONE3_FACET_TOLERANCE
#: Not a tolerance (it changes nothing but rounding): pairs with |a x b| below this sine
#: get the cross product recomputed as a x (b -+ a). Above it the plain cross product is
#: already accurate to 3*sqrt(3)*eps/1e-2 < 1e-13 relative, far inside the tolerance.
_ACCURATE_SINE = 1e-2
#: Squared row norms inside this range are normalised directly; others (zero, tiny, huge,
#: non-finite rows) take the careful path.
_N2_LO, _N2_HI = 1e-280, 1e280

_EMPTY = np.zeros((0, 3))
_EYE = np.eye(3)
_EMPTY.flags.writeable = False  # returned as they are: read-only, so no caller can alter them
_EYE.flags.writeable = False
_TWO_PI = 2.0 * math.pi
_YZX, _ZXY = np.array([1, 2, 0]), np.array([2, 0, 1])


class Cone3Error(RuntimeError):
    """The float result failed its self-check: redo the conversion in exact arithmetic."""


@dataclass(frozen=True, eq=False)
class Cone3:
    """A polyhedral cone in R^3 in both representations (module docstring).

    Parameters
    ----------
    F : numpy.ndarray
        Unit inequality rows (F x <= 0), shape (k, 3).
    E : numpy.ndarray
        Orthonormal equality rows (E x = 0), shape (m, 3).
    rays : numpy.ndarray
        Unit extreme rays modulo the lineality space, shape (r, 3).
    lines : numpy.ndarray
        Orthonormal basis of the lineality space, shape (l, 3).
    """

    F: np.ndarray
    E: np.ndarray
    rays: np.ndarray
    lines: np.ndarray

    @property
    def dim(self) -> int:
        """Dimension of the linear hull."""
        return 3 - self.E.shape[0]

    def polar(self) -> Cone3:
        """The polar cone {y : y . x <= 0 for all x in the cone} (a swap of the fields).

        Returns
        -------
        Cone3
            The polar cone.
        """
        return Cone3(self.rays, self.lines, self.F, self.E)


# --- public API ----------------------------------------------------------------------------
def from_generators(rays, lines=()) -> Cone3:
    """The cone pos(rays) + span(lines) in both representations (module docstring).

    Parameters
    ----------
    rays : array_like, shape (k, 3)
        Generators; zero rows are dropped.
    lines : array_like, shape (m, 3)
        Directions of the lines in the cone.

    Returns
    -------
    Cone3
        Its extreme rays, lineality, facets and equalities (unit rows).

    Raises
    ------
    Cone3Error
        The float result fails its self-check (then use exact cddlib).
    ValueError
        Input that is not finite.
    """
    return _from_unit(_unit_rows(rays), _unit_rows(lines) if len(lines) else _EMPTY)


def from_inequalities(ineq, eq=()) -> Cone3:
    """The cone {x : ineq @ x >= 0, eq @ x = 0} in both representations.

    Computed as the polar of pos(-ineq) + span(eq) (module docstring).

    Parameters
    ----------
    ineq : array_like, shape (k, 3)
        Inequality rows (``ineq @ x >= 0``).
    eq : array_like, shape (m, 3)
        Equality rows (``eq @ x = 0``).

    Returns
    -------
    Cone3

    Raises
    ------
    Cone3Error
        The float result fails its self-check (then use exact cddlib).
    ValueError
        Input that is not finite.
    """
    return _from_unit(-_unit_rows(ineq), _unit_rows(eq) if len(eq) else _EMPTY).polar()


# --- input ---------------------------------------------------------------------------------
def _unit_rows(a) -> np.ndarray:
    """Rows of a (anything reshapeable to (k, 3)) scaled to unit length; zero rows dropped."""
    if isinstance(a, np.ndarray) and a.ndim == 2 and a.shape[1] == 3 and a.dtype == float:
        k = a.shape[0]
    else:
        a = np.asarray(a, dtype=float)
        if a.ndim != 2 or a.shape[1] != 3:
            a = a.reshape(-1, 3)
        k = a.shape[0]
    if k == 0:
        return _EMPTY
    if k <= 8:  # on Python floats: cheaper than five numpy calls
        out = []
        for x, y, z in a.tolist():
            n2 = x * x + y * y + z * z
            if not _N2_LO < n2 < _N2_HI:  # also NaN
                return _unit_rows_careful(a)
            n = math.sqrt(n2)
            out.append((x / n, y / n, z / n))
        return np.array(out)
    n2 = np.einsum("ij,ij->i", a, a)
    if n2.min() > _N2_LO and n2.max() < _N2_HI:  # False for NaN
        return a / np.sqrt(n2)[:, None]
    return _unit_rows_careful(a)


def _unit_rows_careful(a: np.ndarray) -> np.ndarray:
    """_unit_rows for zero, tiny, huge or non-finite rows."""
    if not np.isfinite(a).all():
        raise ValueError("cone3d: generators and constraints must be finite")
    m = np.abs(a).max(axis=1)  # scale by the largest entry first: no over- or underflow
    keep = m > 0
    a = a[keep] / m[keep, None]
    return a / np.sqrt(np.einsum("ij,ij->i", a, a))[:, None]


# --- small vector helpers on Python floats (numpy calls cost microseconds each) -----------
def _cross3(a, b) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _unit3(a) -> tuple[float, float, float]:
    n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return (a[0] / n, a[1] / n, a[2] / n)


def _cross_accurate(a, b) -> tuple[float, float, float]:
    """a x b for unit a, b as a x (b -+ a): accurate to a few eps even when a ~ +-b."""
    sg = 1.0 if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0 else -1.0
    return _cross3(a, (b[0] - sg * a[0], b[1] - sg * a[1], b[2] - sg * a[2]))


def _complement(u) -> np.ndarray:
    """Two orthonormal rows (w, u x w) orthogonal to the unit vector u."""
    x, y, z = u.tolist()
    ax, ay, az = abs(x), abs(y), abs(z)
    if ax <= ay and ax <= az:
        w = (1.0 - x * x, -x * y, -x * z)  # e_x minus its component along u
    elif ay <= az:
        w = (-y * x, 1.0 - y * y, -y * z)
    else:
        w = (-z * x, -z * y, 1.0 - z * z)
    w = _unit3(w)
    return np.array([w, _cross3((x, y, z), w)])


#: [r]_x = r @ _SKEW reshaped to 3 x 3: the cross-product matrix, [r]_x v = r x v.
_SKEW = np.zeros((3, 9))
_SKEW[2, 1], _SKEW[1, 2], _SKEW[2, 3], _SKEW[0, 5], _SKEW[1, 6], _SKEW[0, 7] = -1, 1, 1, -1, -1, 1


@lru_cache(maxsize=128)
def _pair_index(p: int):
    """Ordered pairs (i, j), i != j, of p rows; the flat indices of (r_i x r_j)_k in the
    (p, 3, p) array of all cross products; the index of each pair's reverse (j, i)."""
    ii, jj = np.nonzero(~np.eye(p, dtype=bool))
    flat = (3 * ii[:, None] + np.arange(3)) * p + jj[:, None]
    rev = np.argsort(jj * p + ii, kind="stable")
    return ii, jj, flat, rev


# --- lines: K = span(B) + K_Q with Q the complement of B ------------------------------------
def _line_basis(L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(B, C): orthonormal bases of span(L) and of its orthogonal complement."""
    q = L.shape[0]
    if q == 1:
        return L, _complement(L[0])
    if q == 2:
        a, b = L.tolist()
        sg = 1.0 if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0 else -1.0
        d = (b[0] - sg * a[0], b[1] - sg * a[1], b[2] - sg * a[2])  # exact when a ~ +-b
        t = d[0] * a[0] + d[1] * a[1] + d[2] * a[2]
        d = (d[0] - t * a[0], d[1] - t * a[1], d[2] - t * a[2])
        if math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= _ANG:  # the sine
            return L[:1], _complement(L[0])
        d = _unit3(d)
        return np.array([a, d]), np.array([_unit3(_cross3(a, d))])
    _, sv, vt = np.linalg.svd(L)
    rank = int((sv > _ANG * sv[0]).sum())
    return vt[:rank], vt[rank:]


def _from_unit(R: np.ndarray, L: np.ndarray) -> Cone3:
    """pos(R) + span(L) for unit rows R and L."""
    if L.shape[0] == 0:
        return _cone3(R)
    B, C = _line_basis(L)
    if C.shape[0] == 0:
        return Cone3(_EMPTY, _EMPTY, _EMPTY, _EYE)
    if C.shape[0] == 1:  # two lines: K_Q is {0}, a ray or the line along c
        pos = neg = False
        if R.shape[0]:
            x = R @ C[0]
            pos, neg = float(x.max()) > _ANG, float(x.min()) < -_ANG
        if pos and neg:
            return Cone3(_EMPTY, _EMPTY, _EMPTY, _EYE)
        if pos or neg:
            c = C if pos else -C
            return Cone3(-c, _EMPTY, c, B)
        return Cone3(_EMPTY, C, _EMPTY, B)
    return _planar(R @ C.T if R.shape[0] else None, C, _EMPTY, B)


def _rows_or_empty(rows: list) -> np.ndarray:
    return np.array(rows) if rows else _EMPTY


def _planar(X, P: np.ndarray, E_out: np.ndarray, lines_in: np.ndarray) -> Cone3:
    """The cone generated by the rays with local coordinates X (rows (x, y) in the basis
    P of a plane; rows shorter than the angle tolerance dropped), plus the equalities
    E_out and the lines lines_in: one angular sort, on Python floats.

    The largest gap between consecutive directions decides: 2 pi (one direction) a ray,
    more than pi a wedge bounded by the rays at the gap, pi (within the angle tolerance)
    a half-plane, or a line if two gaps are pi, less than pi the whole plane.
    """
    pts = []
    for x, y in (X.tolist() if X is not None else ()):
        n = math.hypot(x, y)
        if n > _ANG:
            pts.append((math.atan2(y, x), x / n, y / n))
    F2, E2, R2, L2 = [], [], [], []  # local 2-D rows
    if not pts:
        E2 = [(1.0, 0.0), (0.0, 1.0)]
    else:
        pts.sort()
        p = len(pts)
        gaps = [pts[i + 1][0] - pts[i][0] for i in range(p - 1)]
        gaps.append(pts[0][0] + _TWO_PI - pts[-1][0])
        k = max(range(p), key=gaps.__getitem__)
        big = gaps[k]
        u2 = pts[k][1:]  # last direction before the largest gap (counter-clockwise)
        u1 = pts[(k + 1) % p][1:]  # first direction after it
        if big >= _TWO_PI - _ANG:  # one direction: a ray
            F2, E2, R2 = [(-u2[0], -u2[1])], [(-u2[1], u2[0])], [u2]
        elif big > math.pi + _ANG:  # a pointed wedge from u1 counter-clockwise to u2
            F2, R2 = [(u1[1], -u1[0]), (-u2[1], u2[0])], [u1, u2]
        elif big >= math.pi - _ANG:
            v = (u1[0] - u2[0], u1[1] - u2[1])  # u1 ~ -u2: the line, averaged
            n = math.hypot(*v)
            v = (v[0] / n, v[1] / n)
            w = (-v[1], v[0])  # counter-clockwise from u1: into the half-plane
            if sum(g >= math.pi - _ANG for g in gaps) >= 2:  # two opposite directions
                E2, L2 = [w], [v]
            else:
                F2, R2, L2 = [(-w[0], -w[1])], [w], [v]
        else:  # the whole plane
            L2 = [(1.0, 0.0), (0.0, 1.0)]
    (a0, a1, a2), (b0, b1, b2) = P.tolist()

    def lift(rows):
        return [(x * a0 + y * b0, x * a1 + y * b1, x * a2 + y * b2) for x, y in rows]

    E = lift(E2)
    L = lift(L2)
    if E_out.shape[0]:
        E = E_out.tolist() + E
    if lines_in.shape[0]:
        L = lines_in.tolist() + L
    return Cone3(_rows_or_empty(lift(F2)), _rows_or_empty(E), _rows_or_empty(lift(R2)),
                 _rows_or_empty(L))


# --- rays only: pos(R) in R^3 ---------------------------------------------------------------
def _cone3(R: np.ndarray) -> Cone3:
    """pos(R) for unit rays R in R^3 (no lines)."""
    p = R.shape[0]
    if p == 0:
        return Cone3(_EMPTY, _EYE, _EMPTY, _EMPTY)
    if p == 1:
        return Cone3(-R, _complement(R[0]), R, _EMPTY)
    if p <= 3:  # on Python floats (a numpy call costs microseconds); None means "not
        # that case, or too close to a degeneracy to tell": the general path decides
        quick = _two_rays(R) if p == 2 else _simplicial(R)
        if quick is not None:
            return quick
    ii, jj, flat, rev = _pair_index(p)
    # every cross product r_i x r_j (both orders: the candidate normal and its opposite)
    C = ((R @ _SKEW).reshape(3 * p, 3) @ R.T).take(flat)
    s = np.sqrt(np.einsum("ij,ij->i", C, C))
    par = None  # pairs of parallel or anti-parallel rays, if any
    if s.min() < _ACCURATE_SINE:
        k = np.flatnonzero(s < _ACCURATE_SINE)
        a, b = R[ii[k]], R[jj[k]]
        # a x (b -+ a): the difference of nearly (anti)parallel unit vectors is exact, so
        # the normal is accurate to a few eps relative whatever the angle
        d = b - np.where(np.einsum("ij,ij->i", a, b) < 0, -1.0, 1.0)[:, None] * a
        Ck = a[:, _YZX] * d[:, _ZXY] - a[:, _ZXY] * d[:, _YZX]
        sk = np.sqrt(np.einsum("ij,ij->i", Ck, Ck))
        C[k], s[k] = Ck, sk
        if sk.min() <= _ANG:
            par = s <= _ANG
            if par.all():  # rank <= 1: all rays are +-u
                u = R[:1]
                if float((R @ u[0]).min()) < 0:  # both ways: a line
                    return Cone3(_EMPTY, _complement(u[0]), _EMPTY, u)
                return Cone3(-u, _complement(u[0]), u, _EMPTY)
            s[par] = 1.0  # their normals are meaningless: excluded below
    N = C / s[:, None]
    V = R @ N.T  # (p, pairs): signed distance of each ray to each candidate plane
    ok = V.max(axis=0) <= _TOL  # every ray on the inner side: a facet normal
    if par is not None:
        ok &= ~par
    F = N[ok]
    m = F.shape[0]
    if m == 0:
        return Cone3(_EMPTY, _EMPTY, _EMPTY, _EYE)
    T = V[:, ok] >= -_TOL  # (p, m): ray on facet
    if par is None and m >= 3 and np.count_nonzero(T) == 2 * m:
        # the generic pointed cone: every facet through exactly two rays (the pair that
        # made it: never fewer), as many rays on two facets as facets (also its self-check;
        # a planar set fails it, having a candidate through all p >= 3 rays)
        ext = [k for k, c in enumerate(T.sum(axis=1).tolist()) if c == 2]
        if len(ext) == m:
            return Cone3(F, _EMPTY, R[ext], _EMPTY)
    flat = ok & ok[rev]  # n and -n both facet normals
    if flat.any():  # all rays in one plane: its best-conditioned normal
        n = N[np.flatnonzero(flat)[np.argmax(s[flat])]]
        P = _complement(n)
        return _planar(R @ P.T, P, n[None], _EMPTY)
    F = _merge(F, s[ok])
    m = F.shape[0]
    if m == 1:
        return _halfspace(R, F[0])
    if m == 2:
        return _wedge_line(R, F)
    return _pointed(R, F, ii, jj, par)


def _two_rays(R: np.ndarray) -> Cone3 | None:
    """Two non-parallel rays: the 2-D wedge between them (None when parallel)."""
    a, b = R.tolist()
    c = _cross_accurate(a, b)
    sn = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
    if sn <= _ANG:
        return None
    n = (c[0] / sn, c[1] / sn, c[2] / sn)
    F = np.array([_unit3(_cross3(a, n)), _unit3(_cross3(n, b))])
    return Cone3(F, np.array([n]), R, _EMPTY)


def _simplicial(R: np.ndarray) -> Cone3 | None:
    """Three rays each farther than the tolerance from the plane of the other two: the
    simplicial cone (None otherwise: the general path decides)."""
    r = R.tolist()
    F = []
    sign = 0.0
    for i in range(3):
        a, b, o = r[i], r[(i + 1) % 3], r[(i + 2) % 3]
        c = _cross_accurate(a, b)
        sn = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
        if sn <= _ANG:
            return None
        c = (c[0] / sn, c[1] / sn, c[2] / sn)
        d = c[0] * o[0] + c[1] * o[1] + c[2] * o[2]  # distance of o from the plane (a, b)
        if abs(d) <= _TOL or d * sign < 0:
            return None
        sign = d
        F.append(c)
    F = np.array(F)
    return Cone3(-F if sign > 0 else F, _EMPTY, R, _EMPTY)


def _merge(F: np.ndarray, sc: np.ndarray) -> np.ndarray:
    """Candidates describing the same facet (closer than twice the tolerance) merged; the
    best-conditioned (largest |a x b|) one is kept."""
    m = F.shape[0]
    if m == 1:
        return F
    F = F[np.argsort(-sc, kind="stable")]
    a, b = np.nonzero(F @ F.T > 0.5)  # coarse screen, refined with the differences
    diff = F[a] - F[b]
    same = np.zeros((m, m), dtype=bool)
    same[a, b] = np.einsum("ij,ij->i", diff, diff) <= (2.0 * _TOL) ** 2
    rep = same.argmax(axis=1)  # first (best-conditioned) candidate it coincides with
    if not (rep[rep] == rep).all():
        raise Cone3Error("cone3d: facet candidates form a chain (ambiguous merge)")
    return F[rep == np.arange(m)]


def _halfspace(R: np.ndarray, f: np.ndarray) -> Cone3:
    """One facet f: a half-space, whose plane the rays on it must positively span."""
    P = _complement(f)
    on = np.abs(R @ f) <= _TOL
    if _planar(R[on] @ P.T, P, _EMPTY, _EMPTY).lines.shape[0] != 2:
        raise Cone3Error("cone3d: one facet, but the rays on it do not span its plane")
    return Cone3(f[None], _EMPTY, -f[None], P)


def _wedge_line(R: np.ndarray, F: np.ndarray) -> Cone3:
    """Two facets: a wedge + the line where they meet (rays must run both ways along it)."""
    f1, f2 = F.tolist()
    ell = _cross_accurate(f1, f2)
    n = math.sqrt(ell[0] ** 2 + ell[1] ** 2 + ell[2] ** 2)
    if n <= _ANG:
        raise Cone3Error("cone3d: two opposite facets in a full-dimensional cone")
    ell = np.array(ell) / n
    on = (np.abs(R @ F.T) <= _TOL).all(axis=1)
    t = R[on] @ ell
    if not ((t > 0).any() and (t < 0).any()):
        raise Cone3Error("cone3d: two facets, but no rays along both ways of their line")
    u1 = np.array(_unit3(_cross3(ell, f1)))
    if u1 @ F[1] > 0:
        u1 = -u1
    u2 = np.array(_unit3(_cross3(ell, f2)))
    if u2 @ F[0] > 0:
        u2 = -u2
    return Cone3(F, _EMPTY, np.array([u1, u2]), ell[None])


def _pointed(R: np.ndarray, F: np.ndarray, ii, jj, par) -> Cone3:
    """Three or more facets: a pointed cone; extreme rays are the rays on two facets, one
    of each set of parallel copies; checked like the generic case."""
    p = R.shape[0]
    keep = np.ones(p, dtype=bool)
    if par is not None:
        k = np.flatnonzero(par & (ii < jj))
        dup = np.einsum("ij,ij->i", R[ii[k]], R[jj[k]]) > 0
        keep[jj[k[dup]]] = False  # a later copy of a direction
    T = np.abs(R @ F.T) <= _TOL  # (p, m): ray on facet
    ext = keep & (T.sum(axis=1) >= 2)
    Te = T[ext]
    m = F.shape[0]
    if Te.shape[0] != m or not ((Te.sum(axis=1) == 2).all() and (Te.sum(axis=0) == 2).all()):
        raise Cone3Error(
            f"cone3d: pointed cone with {m} facets and {Te.shape[0]} rays on two facets")
    return Cone3(F, _EMPTY, R[ext], _EMPTY)
