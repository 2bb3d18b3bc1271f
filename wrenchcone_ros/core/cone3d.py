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

1. rows are normalised (zero rows dropped); the lines' span B comes from an SVD (rank
   cut-off ``CONE3_ANGLE_TOLERANCE``), the rays are projected onto the complement Q of B
   (rays within that angle of B are dropped). K = span(B) + K_Q, K_Q a cone in Q;
2. dim Q = 1: K_Q is {0}, a ray or the line; dim Q = 2: one angular sort of the rays in Q
   gives {0}, a ray, a line, a wedge, a half-plane or the plane (the largest gap between
   consecutive directions against pi);
3. dim Q = 3 (no lines): every pair of non-parallel rays gives a candidate normal
   n = a x b / |a x b| (vectorised over all pairs), computed as a x (b -+ a): the
   difference of nearly (anti)parallel unit vectors is exact, so n is accurate to a few
   eps whatever the angle between a and b. If all rays are within
   ``CONE3_FACET_TOLERANCE`` of some candidate's plane, K is planar (step 2 in that
   plane, its normal is E). Otherwise the candidates with every ray on one side (within
   the tolerance) are the facets (either sign), merged when closer than twice it.
   No facet: R^3. One: a half-space (lineality = its plane). Two: a wedge + line (the
   line is their intersection). Three or more: a pointed cone whose extreme rays are the
   (deduplicated) rays on two facets.

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

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .tolerances import CONE3_ANGLE_TOLERANCE, CONE3_FACET_TOLERANCE

__all__ = ["Cone3", "Cone3Error", "from_generators", "from_inequalities"]

_EMPTY = np.zeros((0, 3))
_EYE = np.eye(3)
_TWO_PI = 2.0 * np.pi
_YZX, _ZXY = np.array([1, 2, 0]), np.array([2, 0, 1])


class Cone3Error(RuntimeError):
    """The float result failed its self-check: redo the conversion in exact arithmetic."""


@dataclass(frozen=True, eq=False)
class Cone3:
    """A polyhedral cone in R^3 in both representations (module docstring)."""

    F: np.ndarray
    E: np.ndarray
    rays: np.ndarray
    lines: np.ndarray

    @property
    def dim(self) -> int:
        """Dimension of the linear hull."""
        return 3 - self.E.shape[0]

    def polar(self) -> Cone3:
        """The polar cone {y : y . x <= 0 for all x in the cone} (a swap of the fields)."""
        return Cone3(self.rays, self.lines, self.F, self.E)


# --- small helpers ---------------------------------------------------------------------
def _rows(a) -> np.ndarray:
    a = np.asarray(a, dtype=float)
    if a.size == 0:
        return _EMPTY
    a = a.reshape(-1, 3)
    if not np.all(np.isfinite(a)):
        raise ValueError("cone3d: generators and constraints must be finite")
    return a


def _unit(a: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length (scaled by their max entry first: no overflow), zero
    rows dropped."""
    if a.shape[0] == 0:
        return _EMPTY
    m = np.abs(a).max(axis=1)
    keep = m > 0
    if not keep.all():
        a, m = a[keep], m[keep]
    a = a / m[:, None]
    return a / np.sqrt(np.einsum("ij,ij->i", a, a))[:, None]


def _complement(u: np.ndarray) -> np.ndarray:
    """Two orthonormal rows orthogonal to the unit vector u (u, w1, w2 right-handed)."""
    k = int(np.argmin(np.abs(u)))
    a = np.zeros(3)
    a[k] = 1.0
    w1 = a - u[k] * u
    w1 /= np.linalg.norm(w1)
    return np.array([w1, np.cross(u, w1)])


@lru_cache(maxsize=256)
def _pairs(p: int) -> tuple[np.ndarray, np.ndarray]:
    i, j = np.triu_indices(p, 1)
    return i, j


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a x b for unit vectors, accurate to a few eps relative even when a ~ +-b."""
    return np.cross(a, b - a if a @ b >= 0 else b + a)


def _perp2(u: np.ndarray) -> np.ndarray:
    """u rotated by +90 degrees (2-D rows)."""
    return np.stack([-u[..., 1], u[..., 0]], axis=-1)


# --- cones in R^1 and R^2 (local coordinates) -------------------------------------------
# Each returns (F, E, rays, lines) in the local coordinates, conventions as in R^3.
_E1, _E2 = np.eye(1), np.eye(2)
_Z1, _Z2 = np.zeros((0, 1)), np.zeros((0, 2))


def _cone1(x: np.ndarray):
    """Cone in R^1 generated by the signs of x (nonzero entries)."""
    pos, neg = bool((x > 0).any()), bool((x < 0).any())
    if pos and neg:
        return _Z1, _Z1, _Z1, _E1
    if pos:
        return -_E1, _Z1, _E1, _Z1
    if neg:
        return _E1, _Z1, -_E1, _Z1
    return _Z1, _E1, _Z1, _Z1


def _cone2(X: np.ndarray):
    """Cone in R^2 generated by the unit rows of X: one angular sort."""
    p = X.shape[0]
    if p == 0:
        return _Z2, _E2, _Z2, _Z2
    theta = np.arctan2(X[:, 1], X[:, 0])
    order = np.argsort(theta)
    ts = theta[order]
    gaps = np.empty(p)
    gaps[:-1] = ts[1:] - ts[:-1]
    gaps[-1] = ts[0] + _TWO_PI - ts[-1]
    k = int(np.argmax(gaps))
    big = gaps[k]
    tol = CONE3_ANGLE_TOLERANCE
    u2 = X[order[k]]  # last direction before the largest gap (counter-clockwise)
    u1 = X[order[(k + 1) % p]]  # first direction after it
    if big >= _TWO_PI - tol:  # one direction: a ray
        return -u2[None], _perp2(u2)[None], u2[None], _Z2
    if big > np.pi + tol:  # a pointed wedge from u1 counter-clockwise to u2
        F = np.array([[u1[1], -u1[0]], [-u2[1], u2[0]]])
        return F, _Z2, np.array([u1, u2]), _Z2
    if big >= np.pi - tol:
        n_pi = int((gaps >= np.pi - tol).sum())
        v = u1 - u2
        v /= np.linalg.norm(v)  # u1 ~ -u2: the line, averaged
        if n_pi >= 2:  # only two opposite directions: a line
            return _Z2, _perp2(v)[None], _Z2, v[None]
        w = _perp2(v)  # the half-plane's inner direction (counter-clockwise from u1)
        return -w[None], _Z2, w[None], v[None]
    return _Z2, _Z2, _Z2, _E2  # the whole plane


def _lift(local, basis: np.ndarray, E_out: np.ndarray, lines_in: np.ndarray) -> Cone3:
    """A local cone (coordinates in the rows of ``basis``) as a Cone3 in R^3, plus the
    equalities E_out (complement of the basis) and the lines lines_in (already in R^3)."""
    F, E, R, L = local
    E3 = E @ basis
    L3 = L @ basis
    E3 = np.vstack([E_out, E3]) if E_out.shape[0] else E3
    L3 = np.vstack([lines_in, L3]) if lines_in.shape[0] else L3
    return Cone3(F @ basis, E3.reshape(-1, 3), R @ basis, L3.reshape(-1, 3))


# --- full-rank rays in R^3 -----------------------------------------------------------------
def _cone3(R: np.ndarray) -> Cone3:
    """pos(R) for unit rays R in R^3 (no lines)."""
    p = R.shape[0]
    if p == 0:
        return Cone3(_EMPTY, _EYE, _EMPTY, _EMPTY)
    if p == 1:
        u = R[0]
        return Cone3(-u[None], _complement(u), u[None], _EMPTY)
    ii, jj = _pairs(p)
    Ri, Rj = R[ii], R[jj]
    dot = np.einsum("ij,ij->i", Ri, Rj)
    # a x b computed as a x (b -+ a): the difference of nearly (anti)parallel unit vectors
    # is exact, so the normal is accurate to a few eps relative for every angle
    Dm = Rj - np.where(dot < 0, -1.0, 1.0)[:, None] * Ri
    C = Ri[:, _YZX] * Dm[:, _ZXY] - Ri[:, _ZXY] * Dm[:, _YZX]
    s = np.sqrt(np.einsum("ij,ij->i", C, C))
    par = s <= CONE3_ANGLE_TOLERANCE
    if par.all():  # rank <= 1: all rays are +-u
        u = R[0]
        return _lift(_cone1(R @ u), u[None], _complement(u), _EMPTY)
    nz = ~par
    sn = s[nz]
    N = C[nz] / sn[:, None]
    band = np.full(sn.shape, CONE3_FACET_TOLERANCE)
    V = R @ N.T  # (p, m)
    plus = V.max(axis=0) <= band
    minus = V.min(axis=0) >= -band
    flat = plus & minus
    if flat.any():  # all rays in one plane: its best-conditioned normal
        n = N[np.flatnonzero(flat)[np.argmax(sn[flat])]]
        P = _complement(n)
        X = _unit2(R @ P.T)
        return _lift(_cone2(X), P, n[None], _EMPTY)
    Fc = np.vstack([N[plus], -N[minus]])
    bc = np.concatenate([band[plus], band[minus]])
    sc = np.concatenate([sn[plus], sn[minus]])
    m = Fc.shape[0]
    if m == 0:
        return Cone3(_EMPTY, _EMPTY, _EMPTY, _EYE)
    F, bF = _merge(Fc, bc, sc)
    m = F.shape[0]
    if m == 1:
        return _halfspace(R, F[0], bF[0])
    if m == 2:
        return _wedge_line(R, F, bF)
    return _pointed(R, F, bF, jj, par, dot)


def _unit2(X: np.ndarray) -> np.ndarray:
    """Unit 2-D rows; rows shorter than the angle tolerance dropped."""
    n = np.sqrt(np.einsum("ij,ij->i", X, X))
    keep = n > CONE3_ANGLE_TOLERANCE
    return X[keep] / n[keep, None]


def _merge(Fc: np.ndarray, bc: np.ndarray, sc: np.ndarray):
    """Candidates describing the same facet (closer than the sum of their bands) merged;
    the best-conditioned (largest |a x b|) one is kept."""
    order = np.argsort(-sc, kind="stable")
    Fc, bc = Fc[order], bc[order]
    m = Fc.shape[0]
    if m == 1:
        return Fc, bc
    G = Fc @ Fc.T
    close = G > 0.5  # coarse screen, refined with the differences themselves
    a, b = np.nonzero(close)
    d = np.sqrt(np.einsum("ij,ij->i", Fc[a] - Fc[b], Fc[a] - Fc[b]))
    same = np.zeros((m, m), dtype=bool)
    same[a, b] = d <= bc[a] + bc[b]
    rep = np.argmax(same, axis=1)  # first (best-conditioned) candidate it coincides with
    if not np.all(rep[rep] == rep):
        raise Cone3Error("cone3d: facet candidates form a chain (ambiguous merge)")
    keep = rep == np.arange(m)
    return Fc[keep], bc[keep]


def _halfspace(R: np.ndarray, f: np.ndarray, band: float) -> Cone3:
    """One facet f: a half-space, whose plane the rays on it must positively span."""
    P = _complement(f)
    on = np.abs(R @ f) <= band
    F2, E2, R2, L2 = _cone2(_unit2(R[on] @ P.T))
    if L2.shape[0] != 2:
        raise Cone3Error("cone3d: one facet, but the rays on it do not span its plane")
    return Cone3(f[None], _EMPTY, -f[None], P)


def _wedge_line(R: np.ndarray, F: np.ndarray, bF: np.ndarray) -> Cone3:
    """Two facets: a wedge + the line where they meet (rays must run both ways along it)."""
    f1, f2 = F
    ell = _cross(f1, f2)
    n = np.linalg.norm(ell)
    if n <= CONE3_ANGLE_TOLERANCE:
        raise Cone3Error("cone3d: two opposite facets in a full-dimensional cone")
    ell /= n
    on = (np.abs(R @ f1) <= bF[0]) & (np.abs(R @ f2) <= bF[1])
    t = R[on] @ ell
    if not ((t > 0).any() and (t < 0).any()):
        raise Cone3Error("cone3d: two facets, but no rays along both ways of their line")
    u1 = np.cross(ell, f1)
    u1 /= np.linalg.norm(u1)
    if u1 @ f2 > 0:
        u1 = -u1
    u2 = np.cross(ell, f2)
    u2 /= np.linalg.norm(u2)
    if u2 @ f1 > 0:
        u2 = -u2
    return Cone3(F.copy(), _EMPTY, np.array([u1, u2]), ell[None])


def _pointed(R, F, bF, jj, par, dot) -> Cone3:
    """Three or more facets: a pointed cone; extreme rays are the rays on two facets."""
    p = R.shape[0]
    keep = np.ones(p, dtype=bool)
    dup = par & (dot > 0)
    if dup.any():
        keep[jj[dup]] = False  # a later copy of a direction
    T = np.abs(R @ F.T) <= bF  # (p, m): ray on facet
    deg = T.sum(axis=1)
    ext = keep & (deg >= 2)
    Te = T[ext]
    m = F.shape[0]
    if Te.shape[0] != m or not (np.all(Te.sum(axis=1) == 2) and np.all(Te.sum(axis=0) == 2)):
        raise Cone3Error(
            f"cone3d: pointed cone with {m} facets and {Te.shape[0]} rays on two facets")
    return Cone3(F, _EMPTY, R[ext], _EMPTY)


# --- public API ----------------------------------------------------------------------------
def from_generators(rays, lines=()) -> Cone3:
    """The cone pos(rays) + span(lines) in both representations (module docstring).

    Raises :class:`Cone3Error` when the float result fails its self-check (then use exact
    cddlib) and ValueError for non-finite input.
    """
    R = _unit(_rows(rays))
    L = _unit(_rows(lines))
    q = L.shape[0]
    if q == 0:
        return _cone3(R)
    if q == 1:
        B = L
        C = _complement(L[0])
    else:
        _, sv, vt = np.linalg.svd(L)
        rank = int((sv > CONE3_ANGLE_TOLERANCE * sv[0]).sum())
        if rank == 3:
            return Cone3(_EMPTY, _EMPTY, _EMPTY, _EYE)
        B, C = vt[:rank], vt[rank:]
    X = _unit2(R @ C.T) if R.shape[0] else np.zeros((0, C.shape[0]))
    if C.shape[0] == 1:
        return _lift(_cone1(X[:, 0]), C, _EMPTY, B)
    return _lift(_cone2(X), C, _EMPTY, B)


def from_inequalities(ineq, eq=()) -> Cone3:
    """The cone {x : ineq @ x >= 0, eq @ x = 0} in both representations, computed as the
    polar of pos(-ineq) + span(eq) (module docstring). Raises like :func:`from_generators`.
    """
    return from_generators(-_rows(ineq), _rows(eq)).polar()
