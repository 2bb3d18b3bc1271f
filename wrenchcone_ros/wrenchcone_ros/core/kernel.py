# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The planar method compiled (numba): many modes of one pose in one call.

This is :mod:`.cone3d` and the float path of :mod:`.planar` transcribed to numba's
nopython mode, step for step (same formulas, same tolerances, same branch order), so
that a batch of modes costs a few microseconds each instead of a few hundred (the pure
path is ~98 % interpreter and small-array dispatch; docs/performance.md). The numpy
code stays the reference: :func:`wrenchcone_ros.core.batch.wrench_cones` uses it when
numba is missing, when asked to (``engine="numpy"`` or ``WRENCHCONE_ENGINE=numpy``) and
for every mode the kernel declines. test/core/test_kernel.py checks kernel == reference
on every scene family.

The transcription is deliberate, and the one place where the core repeats its own
logic: numba compiles only its own subset of Python, so the kernel restates the steps
of :mod:`.cone3d` and :mod:`.planar` rather than calling them (`duplicates` pairs the two
texts; the equality tests above are what keeps them the same).

The kernel declines a mode (status != 0) exactly where the reference leaves the float
path: nearly parallel acceleration rows (``constraints.nearly_parallel``, status 1: the
reference computes that cone exactly) and a failed cone3d self-check (``Cone3Error``,
status 2: the reference redoes it, then exact cddlib). A declined mode is recomputed by
the reference, so the answer never depends on the kernel's handling of those cases.

Input of :func:`planar_batch`: ``A`` = J_hat^T (2n x 3, row k the coefficients of
acceleration k over xdd_hat), ``kappa`` (M_hat = diag(1, 1, kappa)), ``mu`` (n,), and
per mode (CSR-packed over the modes) Table 2 as index lists: the inequality rows, their
signs and strict flags, the equality rows, the loaded fixels and their friction-edge
signs (:func:`wrenchcone_ros.core.constraints._plan`). Output per mode: status, the open
mode's feasibility, and the cone's F, E, rays, lines (nondimensional, F and rays sorted
as ``cones._sorted_rows`` sorts them).

:func:`planar_all` is the robust "all" cone of one mode over the vertices of a
friction box (:mod:`.robust`): the acceleration cone once, the vertices' facets, one
conversion of their stack; its reference is the numpy path of :mod:`.robust` (each
vertex's cone, then their intersection), and test/core/test_robust.py checks the two equal.

:func:`contact_geometry` is the float path of ``Scene.contact_frames`` for every fixel
at once (the same operations in the same order, so the same doubles): the per-pose
geometry of the node's scene, which the Python loop over fixels and edges made its
largest per-pose cost (docs/performance.md). It also writes J_hat^T, the rows
``dynamics.float_rows`` builds from that geometry with numpy (the same doubles).

:func:`cone_checks` is ``cones._Query.check`` of many cones at many wrenches (the same
operations in the same order: the same doubles), which the direction searches call for
every direction they try (``engines.kernel_engine.PackedCones``).

The entry point :func:`planar_batch` is compiled with ``nogil=True``: it releases the
GIL while it runs, so in the node a large batch in one thread (a classification in the
slow lane, the publishing worker's monitored cones) does not stop the other threads'
Python (the fast lane's requests).

Compilation: ``cache=True``; numba writes its cache next to this file (``__pycache__``)
or, when that is read-only, in the user's cache directory (``NUMBA_CACHE_DIR`` overrides
both); docs/performance.md gives the measured compile and cache-load times.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .tolerances import (
    CONE3_ANGLE_TOLERANCE,
    CONE3_FACET_TOLERANCE,
    FEASIBILITY_TOLERANCE,
    PARALLEL_GUARD,
)

_ANG = CONE3_ANGLE_TOLERANCE
_TOL = CONE3_FACET_TOLERANCE
_ACCURATE_SINE = 1e-2  # as cone3d._ACCURATE_SINE (rounding only, not a tolerance)
_N2_LO, _N2_HI = 1e-280, 1e280
_TWO_PI = 2.0 * math.pi
_PI = math.pi

#: Status codes of planar_batch.
OK, ILL_CONDITIONED, CONE3_ERROR = 0, 1, 2


class KernelCone3Error(Exception):
    """Raised inside the kernel where cone3d raises Cone3Error (caught per mode)."""


@njit(cache=True)
def _empty():
    return np.zeros((0, 3))


@njit(cache=True)
def _eye():
    return np.eye(3)


@njit(cache=True)
def _unit_rows(a):
    """cone3d._unit_rows: rows scaled to unit length, zero rows dropped."""
    k = a.shape[0]
    direct = True
    for i in range(k):
        n2 = a[i, 0] * a[i, 0] + a[i, 1] * a[i, 1] + a[i, 2] * a[i, 2]
        if not (_N2_LO < n2 < _N2_HI):
            direct = False
    out = np.empty((k, 3))
    if direct:
        for i in range(k):
            n = math.sqrt(a[i, 0] * a[i, 0] + a[i, 1] * a[i, 1] + a[i, 2] * a[i, 2])
            out[i, 0], out[i, 1], out[i, 2] = a[i, 0] / n, a[i, 1] / n, a[i, 2] / n
        return out
    m = 0
    for i in range(k):
        x, y, z = a[i, 0], a[i, 1], a[i, 2]
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
            raise KernelCone3Error("non-finite row")
        mx = max(abs(x), abs(y), abs(z))
        if mx > 0:
            x, y, z = x / mx, y / mx, z / mx
            n = math.sqrt(x * x + y * y + z * z)
            out[m, 0], out[m, 1], out[m, 2] = x / n, y / n, z / n
            m += 1
    return out[:m].copy()


@njit(cache=True)
def _cross3(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=True)
def _unit3(x, y, z):
    n = math.sqrt(x * x + y * y + z * z)
    return x / n, y / n, z / n


@njit(cache=True)
def _cross_accurate(a, b):
    """a x b for unit a, b as a x (b -+ a) (cone3d._cross_accurate)."""
    sg = 1.0 if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0 else -1.0
    return _cross3(a[0], a[1], a[2], b[0] - sg * a[0], b[1] - sg * a[1], b[2] - sg * a[2])


@njit(cache=True)
def _complement(u):
    """Two orthonormal rows (w, u x w) orthogonal to the unit vector u."""
    x, y, z = u[0], u[1], u[2]
    ax, ay, az = abs(x), abs(y), abs(z)
    if ax <= ay and ax <= az:
        w0, w1, w2 = 1.0 - x * x, -x * y, -x * z
    elif ay <= az:
        w0, w1, w2 = -y * x, 1.0 - y * y, -y * z
    else:
        w0, w1, w2 = -z * x, -z * y, 1.0 - z * z
    w0, w1, w2 = _unit3(w0, w1, w2)
    c0, c1, c2 = _cross3(x, y, z, w0, w1, w2)
    out = np.empty((2, 3))
    out[0, 0], out[0, 1], out[0, 2] = w0, w1, w2
    out[1, 0], out[1, 1], out[1, 2] = c0, c1, c2
    return out


@njit(cache=True)
def _row(x, y, z):
    out = np.empty((1, 3))
    out[0, 0], out[0, 1], out[0, 2] = x, y, z
    return out


@njit(cache=True)
def _clearly_rank_3(L):
    """Whether unit rows L certainly have numerical rank 3 in cone3d._line_basis's sense
    (singular values sv2 > CONE3_ANGLE_TOLERANCE * sv0). Three rows a, b, c with
    |det| = |(a x b) . c| > 3 sqrt(q) ANG suffice: sv2(L) >= sv2(a, b, c) >= |det| / 3
    (interlacing; unit rows) and sv0(L) <= sqrt(q). Not a tolerance of its own: when
    this is False the SVD decides, as in the reference."""
    q = L.shape[0]
    a = L[0]
    best, jb = -1.0, 0
    for j in range(1, q):
        c0, c1, c2 = _cross3(a[0], a[1], a[2], L[j, 0], L[j, 1], L[j, 2])
        n2 = c0 * c0 + c1 * c1 + c2 * c2
        if n2 > best:
            best, jb = n2, j
    n0, n1, n2 = _cross3(a[0], a[1], a[2], L[jb, 0], L[jb, 1], L[jb, 2])
    det = 0.0
    for j in range(1, q):
        det = max(det, abs(n0 * L[j, 0] + n1 * L[j, 1] + n2 * L[j, 2]))
    return det > 3.0 * math.sqrt(q) * _ANG * 10.0


@njit(cache=True)
def _line_basis(L):
    q = L.shape[0]
    if q == 1:
        return L.copy(), _complement(L[0])
    if q == 2:
        a, b = L[0], L[1]
        sg = 1.0 if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0 else -1.0
        d0, d1, d2 = b[0] - sg * a[0], b[1] - sg * a[1], b[2] - sg * a[2]
        t = d0 * a[0] + d1 * a[1] + d2 * a[2]
        d0, d1, d2 = d0 - t * a[0], d1 - t * a[1], d2 - t * a[2]
        if math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) <= _ANG:
            return L[:1].copy(), _complement(L[0])
        d0, d1, d2 = _unit3(d0, d1, d2)
        B = np.empty((2, 3))
        B[0] = a
        B[1, 0], B[1, 1], B[1, 2] = d0, d1, d2
        c0, c1, c2 = _cross3(a[0], a[1], a[2], d0, d1, d2)
        c0, c1, c2 = _unit3(c0, c1, c2)
        return B, _row(c0, c1, c2)
    if _clearly_rank_3(L):  # the SVD would give rank 3 (below): skip it
        return L[:0].copy(), np.zeros((0, 3))
    _, sv, vt = np.linalg.svd(L)
    rank = 0
    for s in sv:
        if s > _ANG * sv[0]:
            rank += 1
    return vt[:rank].copy(), vt[rank:].copy()


@njit(cache=True)
def _lift(rows2: np.ndarray, n: int, P: np.ndarray) -> np.ndarray:
    """The first ``n`` rows (x, y) of ``rows2``, in plane coordinates, lifted back to 3-D:
    x P[0] + y P[1] (P's two rows span the plane)."""
    a0, a1, a2 = P[0, 0], P[0, 1], P[0, 2]
    b0, b1, b2 = P[1, 0], P[1, 1], P[1, 2]
    out = np.empty((n, 3))
    for i in range(n):
        x, y = rows2[i, 0], rows2[i, 1]
        out[i, 0], out[i, 1], out[i, 2] = x * a0 + y * b0, x * a1 + y * b1, x * a2 + y * b2
    return out


@njit(cache=True)
def _stack(a, b):
    out = np.empty((a.shape[0] + b.shape[0], 3))
    out[:a.shape[0]] = a
    out[a.shape[0]:] = b
    return out


@njit(cache=True)
def _planar(X, P, E_out, lines_in):
    """cone3d._planar: the cone of the 2-D points X (coordinates in the basis P)."""
    k = X.shape[0]
    ang = np.empty(k)
    ux = np.empty(k)
    uy = np.empty(k)
    p = 0
    for i in range(k):
        x, y = X[i, 0], X[i, 1]
        n = math.hypot(x, y)
        if n > _ANG:
            ang[p], ux[p], uy[p] = math.atan2(y, x), x / n, y / n
            p += 1
    F2 = np.zeros((2, 2))
    E2 = np.zeros((2, 2))
    R2 = np.zeros((2, 2))
    L2 = np.zeros((2, 2))
    nf = ne = nr = nl = 0
    if p == 0:
        E2[0, 0], E2[1, 1] = 1.0, 1.0
        ne = 2
    else:
        # Python sorts the tuples (angle, x, y): angle first, ties by x then y
        order = np.argsort(ang[:p], kind="mergesort")
        for i in range(1, p):  # ties in angle (equal directions): order by (x, y)
            j = i
            while j > 0 and ang[order[j]] == ang[order[j - 1]] and (
                    ux[order[j]] < ux[order[j - 1]] or (ux[order[j]] == ux[order[j - 1]]
                                                        and uy[order[j]] < uy[order[j - 1]])):
                order[j], order[j - 1] = order[j - 1], order[j]
                j -= 1
        a = ang[order]
        gx = ux[order]
        gy = uy[order]
        gaps = np.empty(p)
        for i in range(p - 1):
            gaps[i] = a[i + 1] - a[i]
        gaps[p - 1] = a[0] + _TWO_PI - a[p - 1]
        kk = 0
        for i in range(1, p):
            if gaps[i] > gaps[kk]:
                kk = i
        big = gaps[kk]
        u2x, u2y = gx[kk], gy[kk]
        u1x, u1y = gx[(kk + 1) % p], gy[(kk + 1) % p]
        if big >= _TWO_PI - _ANG:
            F2[0, 0], F2[0, 1] = -u2x, -u2y
            E2[0, 0], E2[0, 1] = -u2y, u2x
            R2[0, 0], R2[0, 1] = u2x, u2y
            nf, ne, nr = 1, 1, 1
        elif big > _PI + _ANG:
            F2[0, 0], F2[0, 1] = u1y, -u1x
            F2[1, 0], F2[1, 1] = -u2y, u2x
            R2[0, 0], R2[0, 1] = u1x, u1y
            R2[1, 0], R2[1, 1] = u2x, u2y
            nf, nr = 2, 2
        elif big >= _PI - _ANG:
            vx, vy = u1x - u2x, u1y - u2y
            n = math.hypot(vx, vy)
            vx, vy = vx / n, vy / n
            wx, wy = -vy, vx
            two = 0
            for g in gaps:
                if g >= _PI - _ANG:
                    two += 1
            if two >= 2:
                E2[0, 0], E2[0, 1] = wx, wy
                L2[0, 0], L2[0, 1] = vx, vy
                ne, nl = 1, 1
            else:
                F2[0, 0], F2[0, 1] = -wx, -wy
                R2[0, 0], R2[0, 1] = wx, wy
                L2[0, 0], L2[0, 1] = vx, vy
                nf, nr, nl = 1, 1, 1
        else:
            L2[0, 0], L2[1, 1] = 1.0, 1.0
            nl = 2
    F = _lift(F2, nf, P)
    R = _lift(R2, nr, P)
    E = _lift(E2, ne, P)
    L = _lift(L2, nl, P)
    return F, _stack(E_out, E), R, _stack(lines_in, L)


@njit(cache=True)
def _two_rays(R):
    """cone3d._two_rays: (found, cone)."""
    a, b = R[0], R[1]
    c0, c1, c2 = _cross_accurate(a, b)
    sn = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    if sn <= _ANG:
        return False, (_empty(), _empty(), _empty(), _empty())
    n0, n1, n2 = c0 / sn, c1 / sn, c2 / sn
    F = np.empty((2, 3))
    x, y, z = _cross3(a[0], a[1], a[2], n0, n1, n2)
    F[0, 0], F[0, 1], F[0, 2] = _unit3(x, y, z)
    x, y, z = _cross3(n0, n1, n2, b[0], b[1], b[2])
    F[1, 0], F[1, 1], F[1, 2] = _unit3(x, y, z)
    return True, (F, _row(n0, n1, n2), R.copy(), _empty())


@njit(cache=True)
def _simplicial(R):
    """cone3d._simplicial: (found, cone)."""
    F = np.empty((3, 3))
    sign = 0.0
    for i in range(3):
        a, b, o = R[i], R[(i + 1) % 3], R[(i + 2) % 3]
        c0, c1, c2 = _cross_accurate(a, b)
        sn = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        if sn <= _ANG:
            return False, (_empty(), _empty(), _empty(), _empty())
        c0, c1, c2 = c0 / sn, c1 / sn, c2 / sn
        d = c0 * o[0] + c1 * o[1] + c2 * o[2]
        if abs(d) <= _TOL or d * sign < 0:
            return False, (_empty(), _empty(), _empty(), _empty())
        sign = d
        F[i, 0], F[i, 1], F[i, 2] = c0, c1, c2
    if sign > 0:
        F = -F
    return True, (F, _empty(), R.copy(), _empty())


@njit(cache=True)
def _merge(F, sc):
    m = F.shape[0]
    if m == 1:
        return F.copy()
    order = np.argsort(-sc, kind="mergesort")
    F = F[order]
    rep = np.empty(m, np.int64)
    for a in range(m):
        rep[a] = 0
        for b in range(m):
            dot = F[a, 0] * F[b, 0] + F[a, 1] * F[b, 1] + F[a, 2] * F[b, 2]
            if dot > 0.5:
                d0, d1, d2 = F[a, 0] - F[b, 0], F[a, 1] - F[b, 1], F[a, 2] - F[b, 2]
                if d0 * d0 + d1 * d1 + d2 * d2 <= (2.0 * _TOL) ** 2:
                    rep[a] = b
                    break
    for a in range(m):
        if rep[rep[a]] != rep[a]:
            raise KernelCone3Error("chain")
    keep = 0
    for a in range(m):
        if rep[a] == a:
            keep += 1
    out = np.empty((keep, 3))
    j = 0
    for a in range(m):
        if rep[a] == a:
            out[j] = F[a]
            j += 1
    return out


@njit(cache=True)
def _halfspace(R, f):
    P = _complement(f)
    cnt = 0
    for i in range(R.shape[0]):
        if abs(R[i, 0] * f[0] + R[i, 1] * f[1] + R[i, 2] * f[2]) <= _TOL:
            cnt += 1
    X = np.empty((cnt, 2))
    j = 0
    for i in range(R.shape[0]):
        if abs(R[i, 0] * f[0] + R[i, 1] * f[1] + R[i, 2] * f[2]) <= _TOL:
            X[j, 0] = R[i, 0] * P[0, 0] + R[i, 1] * P[0, 1] + R[i, 2] * P[0, 2]
            X[j, 1] = R[i, 0] * P[1, 0] + R[i, 1] * P[1, 1] + R[i, 2] * P[1, 2]
            j += 1
    sub = _planar(X, P, _empty(), _empty())
    if sub[3].shape[0] != 2:
        raise KernelCone3Error("half-space")
    return _row(f[0], f[1], f[2]), _empty(), _row(-f[0], -f[1], -f[2]), P


@njit(cache=True)
def _wedge_line(R, F):
    f1, f2 = F[0], F[1]
    e0, e1, e2 = _cross_accurate(f1, f2)
    n = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    if n <= _ANG:
        raise KernelCone3Error("opposite facets")
    e0, e1, e2 = e0 / n, e1 / n, e2 / n
    pos = neg = False
    for i in range(R.shape[0]):
        r = R[i]
        if (abs(r[0] * f1[0] + r[1] * f1[1] + r[2] * f1[2]) <= _TOL
                and abs(r[0] * f2[0] + r[1] * f2[1] + r[2] * f2[2]) <= _TOL):
            t = r[0] * e0 + r[1] * e1 + r[2] * e2
            if t > 0:
                pos = True
            if t < 0:
                neg = True
    if not (pos and neg):
        raise KernelCone3Error("wedge + line")
    x, y, z = _cross3(e0, e1, e2, f1[0], f1[1], f1[2])
    u10, u11, u12 = _unit3(x, y, z)
    if u10 * f2[0] + u11 * f2[1] + u12 * f2[2] > 0:
        u10, u11, u12 = -u10, -u11, -u12
    x, y, z = _cross3(e0, e1, e2, f2[0], f2[1], f2[2])
    u20, u21, u22 = _unit3(x, y, z)
    if u20 * f1[0] + u21 * f1[1] + u22 * f1[2] > 0:
        u20, u21, u22 = -u20, -u21, -u22
    rays = np.empty((2, 3))
    rays[0, 0], rays[0, 1], rays[0, 2] = u10, u11, u12
    rays[1, 0], rays[1, 1], rays[1, 2] = u20, u21, u22
    return F.copy(), _empty(), rays, _row(e0, e1, e2)


@njit(cache=True)
def _pointed(R, F, ii, jj, par, has_par):
    p = R.shape[0]
    m = F.shape[0]
    keep = np.ones(p, np.bool_)
    if has_par:
        for k in range(ii.shape[0]):
            if par[k] and ii[k] < jj[k]:
                a, b = R[ii[k]], R[jj[k]]
                if a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0:
                    keep[jj[k]] = False
    T = np.zeros((p, m), np.bool_)
    for i in range(p):
        for f in range(m):
            T[i, f] = abs(R[i, 0] * F[f, 0] + R[i, 1] * F[f, 1] + R[i, 2] * F[f, 2]) <= _TOL
    ext = np.zeros(p, np.bool_)
    ne = 0
    for i in range(p):
        if keep[i] and T[i].sum() >= 2:
            ext[i] = True
            ne += 1
    if ne != m:
        raise KernelCone3Error("pointed: count")
    col = np.zeros(m, np.int64)
    for i in range(p):
        if ext[i]:
            if T[i].sum() != 2:
                raise KernelCone3Error("pointed: ray")
            for f in range(m):
                if T[i, f]:
                    col[f] += 1
    for f in range(m):
        if col[f] != 2:
            raise KernelCone3Error("pointed: facet")
    return F.copy(), _empty(), R[ext].copy(), _empty()


@njit(cache=True)
def _cone3(R):
    """cone3d._cone3: pos(R) for unit rays R."""
    p = R.shape[0]
    if p == 0:
        return _empty(), _eye(), _empty(), _empty()
    if p == 1:
        return -R, _complement(R[0]), R.copy(), _empty()
    if p == 2:
        found, c = _two_rays(R)
        if found:
            return c
    elif p == 3:
        found, c = _simplicial(R)
        if found:
            return c
    npair = p * (p - 1)
    ii = np.empty(npair, np.int64)
    jj = np.empty(npair, np.int64)
    k = 0
    for i in range(p):
        for j in range(p):
            if i != j:
                ii[k], jj[k] = i, j
                k += 1
    rev = np.empty(npair, np.int64)  # index of (j, i)
    for k in range(npair):
        i, j = ii[k], jj[k]
        rev[k] = j * (p - 1) + (i if i < j else i - 1)
    C = np.empty((npair, 3))
    s = np.empty(npair)
    smin = np.inf
    for k in range(npair):
        a, b = R[ii[k]], R[jj[k]]
        c0, c1, c2 = _cross3(a[0], a[1], a[2], b[0], b[1], b[2])
        C[k, 0], C[k, 1], C[k, 2] = c0, c1, c2
        s[k] = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        smin = min(smin, s[k])
    par = np.zeros(npair, np.bool_)
    has_par = False
    if smin < _ACCURATE_SINE:
        skmin = np.inf
        for k in range(npair):
            if s[k] < _ACCURATE_SINE:
                c0, c1, c2 = _cross_accurate(R[ii[k]], R[jj[k]])
                C[k, 0], C[k, 1], C[k, 2] = c0, c1, c2
                s[k] = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
                skmin = min(skmin, s[k])
        if skmin <= _ANG:
            has_par = True
            allpar = True
            for k in range(npair):
                par[k] = s[k] <= _ANG
                if not par[k]:
                    allpar = False
            if allpar:
                u = R[0]
                both = False
                for i in range(p):
                    if R[i, 0] * u[0] + R[i, 1] * u[1] + R[i, 2] * u[2] < 0:
                        both = True
                if both:
                    return _empty(), _complement(u), _empty(), _row(u[0], u[1], u[2])
                return _row(-u[0], -u[1], -u[2]), _complement(u), _row(u[0], u[1], u[2]), \
                    _empty()
            for k in range(npair):
                if par[k]:
                    s[k] = 1.0
    N = np.empty((npair, 3))
    ok = np.zeros(npair, np.bool_)
    m = 0
    for k in range(npair):
        n0, n1, n2 = C[k, 0] / s[k], C[k, 1] / s[k], C[k, 2] / s[k]
        N[k, 0], N[k, 1], N[k, 2] = n0, n1, n2
        if par[k]:
            continue
        good = True
        for i in range(p):  # every ray on the inner side (stop at the first that is not)
            if R[i, 0] * n0 + R[i, 1] * n1 + R[i, 2] * n2 > _TOL:
                good = False
                break
        if good:
            ok[k] = True
            m += 1
    if m == 0:
        return _empty(), _empty(), _empty(), _eye()
    okidx = np.flatnonzero(ok)
    F = N[okidx]
    if not has_par and m >= 3:
        total = 0
        cnt = np.zeros(p, np.int64)
        for f in range(m):
            for i in range(p):
                if R[i, 0] * F[f, 0] + R[i, 1] * F[f, 1] + R[i, 2] * F[f, 2] >= -_TOL:
                    total += 1
                    cnt[i] += 1
        if total == 2 * m:
            ne = 0
            for i in range(p):
                if cnt[i] == 2:
                    ne += 1
            if ne == m:
                return F, _empty(), R[cnt == 2].copy(), _empty()
    best = -1
    for k in range(npair):
        if ok[k] and ok[rev[k]] and (best < 0 or s[k] > s[best]):
            best = k
    if best >= 0:
        n = N[best]
        P = _complement(n)
        X = np.empty((p, 2))
        for i in range(p):
            X[i, 0] = R[i, 0] * P[0, 0] + R[i, 1] * P[0, 1] + R[i, 2] * P[0, 2]
            X[i, 1] = R[i, 0] * P[1, 0] + R[i, 1] * P[1, 1] + R[i, 2] * P[1, 2]
        return _planar(X, P, _row(n[0], n[1], n[2]), _empty())
    F = _merge(F, s[okidx])
    m = F.shape[0]
    if m == 1:
        return _halfspace(R, F[0])
    if m == 2:
        return _wedge_line(R, F)
    return _pointed(R, F, ii, jj, par, has_par)


@njit(cache=True)
def _from_unit(R, L):
    """cone3d._from_unit: pos(R) + span(L) for unit rows."""
    if L.shape[0] == 0:
        return _cone3(R)
    B, C = _line_basis(L)
    if C.shape[0] == 0:
        return _empty(), _empty(), _empty(), _eye()
    if C.shape[0] == 1:
        pos = neg = False
        for i in range(R.shape[0]):
            x = R[i, 0] * C[0, 0] + R[i, 1] * C[0, 1] + R[i, 2] * C[0, 2]
            if x > _ANG:
                pos = True
            if x < -_ANG:
                neg = True
        if pos and neg:
            return _empty(), _empty(), _empty(), _eye()
        if pos or neg:
            c = C.copy() if pos else -C
            return -c, _empty(), c, B
        return _empty(), C, _empty(), B
    X = np.empty((R.shape[0], 2))
    for i in range(R.shape[0]):
        X[i, 0] = R[i, 0] * C[0, 0] + R[i, 1] * C[0, 1] + R[i, 2] * C[0, 2]
        X[i, 1] = R[i, 0] * C[1, 0] + R[i, 1] * C[1, 1] + R[i, 2] * C[1, 2]
    return _planar(X, C, _empty(), B)


@njit(cache=True)
def from_generators(rays, lines):
    """cone3d.from_generators: (F, E, rays, lines); raises KernelCone3Error."""
    L = _unit_rows(lines) if lines.shape[0] else _empty()
    return _from_unit(_unit_rows(rays), L)


@njit(cache=True)
def from_inequalities(ineq, eq):
    """cone3d.from_inequalities: (F, E, rays, lines) of {ineq x >= 0, eq x = 0}."""
    L = _unit_rows(eq) if eq.shape[0] else _empty()
    F, E, R, Lo = _from_unit(-_unit_rows(ineq), L)
    return R, Lo, F, E


@njit(cache=True)
def nearly_parallel(rows, angle):
    """constraints.nearly_parallel."""
    k = rows.shape[0]
    if k < 2:
        return False
    u = np.empty((k, 3))
    for i in range(k):
        n = math.sqrt(rows[i, 0] ** 2 + rows[i, 1] ** 2 + rows[i, 2] ** 2)
        u[i] = rows[i] / n
    lim = 1.0 - angle * angle
    for i in range(k):
        for j in range(k):
            if i == j:
                continue
            c = abs(u[i, 0] * u[j, 0] + u[i, 1] * u[j, 1] + u[i, 2] * u[j, 2])
            if c > lim:
                dm = math.sqrt((u[i, 0] - u[j, 0]) ** 2 + (u[i, 1] - u[j, 1]) ** 2
                               + (u[i, 2] - u[j, 2]) ** 2)
                dp = math.sqrt((u[i, 0] + u[j, 0]) ** 2 + (u[i, 1] + u[j, 1]) ** 2
                               + (u[i, 2] + u[j, 2]) ** 2)
                d = min(dm, dp)
                if 0 < d < angle:
                    return True
    return False


@njit(cache=True)
def _key_less(a, b):
    """Row a before row b in cones._sorted_rows' order (descending on 12 decimals)."""
    for c in range(3):
        ka, kb = -round(a[c], 12), -round(b[c], 12)
        if ka < kb:
            return True
        if ka > kb:
            return False
    return False


@njit(cache=True)
def _sorted_into(rows, out):
    """Rows (+ 0.0) sorted as cones._sorted_rows (stable insertion sort) into out."""
    m = rows.shape[0]
    idx = np.arange(m)
    for i in range(1, m):
        j = i
        while j > 0 and _key_less(rows[idx[j]], rows[idx[j - 1]]):
            idx[j], idx[j - 1] = idx[j - 1], idx[j]
            j -= 1
    for i in range(m):
        for c in range(3):
            out[i, c] = rows[idx[i], c] + 0.0


@njit(cache=True)
def _plan_rows(A, ineq_idx, ineq_dir, eq_idx):
    """Table 2's acceleration rows of one mode: (inequality rows (signed), equality rows)."""
    ki, ke = ineq_idx.shape[0], eq_idx.shape[0]
    ineq = np.empty((ki, 3))
    for r in range(ki):
        ineq[r] = A[ineq_idx[r]] * ineq_dir[r]
    eq = np.empty((ke, 3))
    for r in range(ke):
        eq[r] = A[eq_idx[r]]
    return ineq, eq


@njit(cache=True)
def _scaled(rows, kappa):
    """M_hat rows: (x, y, kappa z) for each row (the acceleration cone mapped by M_hat)."""
    out = np.empty((rows.shape[0], 3))
    for r in range(rows.shape[0]):
        out[r, 0], out[r, 1], out[r, 2] = rows[r, 0], rows[r, 1], rows[r, 2] * kappa
    return out


@njit(cache=True)
def _wrench_generators(A, mu, mx, f_idx, f_sgn):
    """Generators of W = M_hat X + (-J) C(mu): the rows of M_hat X (mx), then each loaded
    fixel's friction edge -(n_i + s_i mu_i t_i) (planar._planar_float)."""
    n = mu.shape[0]
    nx, nf = mx.shape[0], f_idx.shape[0]
    gens = np.empty((nx + nf, 3))
    gens[:nx] = mx
    for r in range(nf):
        i = f_idx[r]
        coef = f_sgn[r] * mu[i]
        for c in range(3):
            gens[nx + r, c] = -(A[i, c] + coef * A[n + i, c])
    return gens


@njit(cache=True)
def _open_feasible(ineq, ineq_strict, xr):
    """constraints.open_mode_feasible on X's rays: every strict row is > 0 on some ray."""
    for r in range(ineq.shape[0]):
        if not ineq_strict[r]:
            continue
        d = ineq[r]
        dn = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        hit = False
        for q in range(xr.shape[0]):
            g = xr[q]
            lhs = d[0] * g[0] + d[1] * g[1] + d[2] * g[2]
            gn = math.sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
            if lhs > FEASIBILITY_TOLERANCE * dn * gn:
                hit = True
                break
        if not hit:
            return False
    return True


@njit(cache=True)
def _mode_cone(A, kappa, mu, ineq_idx, ineq_dir, ineq_strict, eq_idx, f_idx, f_sgn):
    """One mode, planar._planar_float: (status, feasible, F, E, rays, lines)."""
    ineq, eq = _plan_rows(A, ineq_idx, ineq_dir, eq_idx)
    if nearly_parallel(_stack(ineq, eq), PARALLEL_GUARD):
        return ILL_CONDITIONED, False, _empty(), _empty(), _empty(), _empty()
    _, _, xr, xl = from_inequalities(ineq, eq)
    gens = _wrench_generators(A, mu, _scaled(xr, kappa), f_idx, f_sgn)
    F, E, G, L = from_generators(gens, _scaled(xl, kappa))
    return OK, _open_feasible(ineq, ineq_strict, xr), F, E, G, L


@njit(cache=True)
def _unpack(c):
    """One mode's packed plan (planar_batch): (ineq rows, signs, strict flags, eq rows,
    loaded fixels, edge signs)."""
    ki, ke, kf = c[0], c[1], c[2]
    o = 3
    ineq_idx = c[o:o + ki]
    ineq_dir = c[o + ki:o + 2 * ki].astype(np.float64)
    ineq_strict = c[o + 2 * ki:o + 3 * ki] != 0
    o += 3 * ki
    eq_idx = c[o:o + ke]
    o += ke
    return ineq_idx, ineq_dir, ineq_strict, eq_idx, c[o:o + kf], c[o + kf:o + 2 * kf].astype(
        np.float64)


@njit(cache=True)
def _unique_into(rows, m):
    """The first m rows without repeats (equal to 12 decimals), in ascending
    lexicographic order of their rounded values (robust._unique_rows)."""
    keys = np.empty((m, 3))
    for i in range(m):
        for c in range(3):
            keys[i, c] = round(rows[i, c], 12)
    idx = np.arange(m)
    for i in range(1, m):  # stable insertion sort on the keys
        j = i
        while j > 0:
            a, b = keys[idx[j]], keys[idx[j - 1]]
            less = a[0] < b[0] or (a[0] == b[0] and (a[1] < b[1] or (a[1] == b[1]
                                                                     and a[2] < b[2])))
            if not less:
                break
            idx[j], idx[j - 1] = idx[j - 1], idx[j]
            j -= 1
    out = np.empty((m, 3))
    p = 0
    for i in range(m):
        if p > 0:
            a, b = keys[idx[i]], keys[idx[i - 1]]
            if a[0] == b[0] and a[1] == b[1] and a[2] == b[2]:
                continue
        out[p] = rows[idx[i]]
        p += 1
    return out[:p]


@njit(cache=True, nogil=True)
def planar_all(A, kappa, mus, code):
    """The cone of the wrenches consistent with one mode at every friction vertex
    (robust "all", docs/theory.md): the intersection of the cones W(mu_v) = M_hat X +
    (-J) C(mu_v) for the rows mu_v of ``mus`` (V x n). X (the mode's acceleration cone,
    Table 2) does not depend on mu and is computed once; each W(mu_v) is converted to
    its facets, the facets of all vertices are stacked (repeats dropped) and converted
    once more. ``code`` is one mode's packed plan (planar_batch). Returns (status,
    feasible, F, E, rays, lines), F and rays sorted as planar_batch sorts them; status
    ILL_CONDITIONED or CONE3_ERROR as planar_batch (the caller then uses the reference)."""
    ineq_idx, ineq_dir, ineq_strict, eq_idx, f_idx, f_sgn = _unpack(code)
    ineq, eq = _plan_rows(A, ineq_idx, ineq_dir, eq_idx)
    if nearly_parallel(_stack(ineq, eq), PARALLEL_GUARD):
        return ILL_CONDITIONED, False, _empty(), _empty(), _empty(), _empty()
    try:
        _, _, xr, xl = from_inequalities(ineq, eq)
        feasible = _open_feasible(ineq, ineq_strict, xr)
        mx, ml = _scaled(xr, kappa), _scaled(xl, kappa)
        V = mus.shape[0]
        cap = V * (mx.shape[0] + f_idx.shape[0] + 4)
        Fs = np.empty((cap, 3))
        Es = np.empty((cap, 3))
        nf = ne = 0
        for v in range(V):
            F, E, _, _ = from_generators(_wrench_generators(A, mus[v], mx, f_idx, f_sgn), ml)
            Fs[nf:nf + F.shape[0]] = F
            Es[ne:ne + E.shape[0]] = E
            nf += F.shape[0]
            ne += E.shape[0]
        Fu, Eu = _unique_into(Fs, nf), _unique_into(Es, ne)
        F, E, G, L = from_inequalities(-Fu, Eu)
    except Exception:
        return CONE3_ERROR, False, _empty(), _empty(), _empty(), _empty()
    Fo = np.empty((F.shape[0], 3))
    Go = np.empty((G.shape[0], 3))
    _sorted_into(F, Fo)
    _sorted_into(G, Go)
    return OK, feasible, Fo, E + 0.0, Go, L + 0.0


@njit(cache=True, nogil=True)
def planar_batch(A, kappa, mu, ptr, code):
    """Every mode of the packed plan (module docstring). Mode k's plan is
    ``code[ptr[k]:ptr[k + 1]]`` = [ki, ke, kf, ineq rows (ki), their signs (ki, +-1),
    strict flags (ki, 0/1), eq rows (ke), loaded fixels (kf), edge signs (kf, +-1)].
    Returns (status, feasible, counts (m, 4): rows of F, E, rays, lines; rows (m, 4,
    maxr, 3))."""
    m = ptr.shape[0] - 1
    maxr = 2 * A.shape[0] + 4
    status = np.zeros(m, np.int8)
    feas = np.zeros(m, np.bool_)
    counts = np.zeros((m, 4), np.int64)
    rows = np.zeros((m, 4, maxr, 3))
    for k in range(m):
        ineq_idx, ineq_dir, ineq_strict, eq_idx, f_idx, f_sgn = _unpack(code[ptr[k]:ptr[k + 1]])
        try:
            st, fe, F, E, G, L = _mode_cone(A, kappa, mu, ineq_idx, ineq_dir, ineq_strict,
                                            eq_idx, f_idx, f_sgn)
        except Exception:
            status[k] = CONE3_ERROR
            continue
        status[k] = st
        if st != OK:
            continue
        feas[k] = fe
        counts[k, 0], counts[k, 1] = F.shape[0], E.shape[0]
        counts[k, 2], counts[k, 3] = G.shape[0], L.shape[0]
        _sorted_into(F, rows[k, 0])
        _sorted_into(G, rows[k, 2])
        for i in range(E.shape[0]):
            for q in range(3):
                rows[k, 1, i, q] = E[i, q] + 0.0
        for i in range(L.shape[0]):
            for q in range(3):
                rows[k, 3, i, q] = L[i, q] + 0.0
    return status, feas, counts, rows


# --- contact geometry ------------------------------------------------------------------
#: Status of contact_geometry: every fixel done, or the first fixel the reference refuses
#: (a fixel at the disc's centre, a fixel centre within the tolerance of a polygon vertex,
#: a penetration); the caller then runs the reference, which words the SceneError.
GEOMETRY_OK, GEOMETRY_REFUSED = 0, 1


@njit(cache=True, nogil=True)
def contact_geometry(x, y, c, s, comx, comy, radius, verts, fpos, frad, tol, L):
    """:meth:`wrenchcone_ros.core.scene.Scene.contact_frames` in float arithmetic for
    every fixel at once, the same operations in the same order (so the same doubles:
    test_kernel.py compares them bit for bit on every scene family), and the rows
    J_hat^T of :func:`wrenchcone_ros.core.dynamics.float_rows` (the same doubles).

    ``(x, y)`` and ``c, s`` = cos, sin of theta place the workpiece; ``comx, comy`` its
    com; the shape is the disc of ``radius`` when ``verts`` (m x 2, workpiece frame) has
    no rows, else that polygon; ``fpos`` (n x 2) and ``frad`` (n,) the fixels; ``tol``
    the effective contact tolerance (m); ``L`` the length scale (m). Returns (status,
    first refused fixel, p (n x 2), gap (n,), normal (n x 2), r_n (n,), r_t (n,),
    in_contact (n,), vertex (n,), edge (n,), -1 where none, J_hat^T (2n x 3): row i
    (n_i, r_n,i / L), row n + i (t_i, r_t,i / L) with t_i = n_i rotated by +90
    degrees)."""
    n = fpos.shape[0]
    m = verts.shape[0]
    A = np.empty((2 * n, 3))
    P = np.empty((n, 2))
    N = np.empty((n, 2))
    gap = np.empty(n)
    rn = np.empty(n)
    rt = np.empty(n)
    inc = np.zeros(n, np.bool_)
    vtx = np.zeros(n, np.bool_)
    edge = np.full(n, -1, np.int64)
    for i in range(n):
        dx, dy = fpos[i, 0] - x, fpos[i, 1] - y
        f0, f1 = c * dx + s * dy, -s * dx + c * dy  # R(theta)^T (f - pose)
        e = -1
        is_vertex = False
        if m == 0:  # scene._disc_closest
            dist = math.sqrt(f0 * f0 + f1 * f1)
            if dist == 0:
                return GEOMETRY_REFUSED, i, P, gap, N, rn, rt, inc, vtx, edge, A
            ox, oy = f0 / dist, f1 / dist
            q0, q1 = radius * ox, radius * oy
            signed = dist - radius
            nw0, nw1 = -ox, -oy
        else:  # scene._polygon_closest
            bd2, bq0, bq1, bs, bex, bey, bk = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1
            for k in range(m):
                x1, y1 = verts[k, 0], verts[k, 1]
                x2, y2 = verts[(k + 1) % m, 0], verts[(k + 1) % m, 1]
                ex, ey = x2 - x1, y2 - y1
                t = ((f0 - x1) * ex + (f1 - y1) * ey) / (ex * ex + ey * ey)
                if t < 0:
                    t = 0.0
                if t > 1:
                    t = 1.0
                qx, qy = x1 + t * ex, y1 + t * ey
                d2 = (f0 - qx) * (f0 - qx) + (f1 - qy) * (f1 - qy)
                if bk < 0 or d2 < bd2:
                    bd2, bq0, bq1, bs, bex, bey, bk = d2, qx, qy, t, ex, ey, k
            dist = math.sqrt(bd2)
            inside = False  # scene._inside_polygon
            for k in range(m):
                x1, y1 = verts[k, 0], verts[k, 1]
                x2, y2 = verts[(k + 1) % m, 0], verts[(k + 1) % m, 1]
                if (y1 > f1) != (y2 > f1):
                    xc = x1 + (f1 - y1) * (x2 - x1) / (y2 - y1)
                    if f0 < xc:
                        inside = not inside
            signed = -dist if inside else dist
            q0, q1 = bq0, bq1
            if 0 < bs < 1:
                le = math.sqrt(bex * bex + bey * bey)
                nw0, nw1 = -bey / le, bex / le
                e = bk
            else:
                if dist <= tol:
                    return GEOMETRY_REFUSED, i, P, gap, N, rn, rt, inc, vtx, edge, A
                nw0, nw1 = (q0 - f0) / dist, (q1 - f1) / dist
                is_vertex = True
        g = signed - frad[i]
        if g < -tol:
            return GEOMETRY_REFUSED, i, P, gap, N, rn, rt, inc, vtx, edge, A
        tw0, tw1 = -nw1, nw0
        rx, ry = q0 - comx, q1 - comy
        if e < 0:
            ax, ay = rx, ry
        else:  # r x t at the edge's first vertex (scene.contact_frames says why)
            ax, ay = verts[e, 0] - comx, verts[e, 1] - comy
        P[i, 0], P[i, 1] = x + c * q0 - s * q1, y + s * q0 + c * q1
        N[i, 0], N[i, 1] = c * nw0 - s * nw1, s * nw0 + c * nw1
        gap[i] = g
        rn[i] = rx * nw1 - ry * nw0
        rt[i] = ax * tw1 - ay * tw0
        inc[i] = abs(g) <= tol
        vtx[i] = is_vertex
        edge[i] = e
        # dynamics.float_rows: normal row (n, r x n / L), tangential row (t, r x t / L)
        A[i, 0], A[i, 1], A[i, 2] = N[i, 0], N[i, 1], rn[i] / L
        A[n + i, 0], A[n + i, 1], A[n + i, 2] = -N[i, 1], N[i, 0], rt[i] / L
    return GEOMETRY_OK, -1, P, gap, N, rn, rt, inc, vtx, edge, A


#: Status of :func:`cone_checks`: every wrench finite, or one whose nondimensional norm
#: is not (the caller raises the reference's ValueError).
CHECKS_OK, CHECKS_NOT_FINITE = 0, 1


@njit(cache=True, nogil=True)
def cone_checks(feasible, inv_l, F, f_off, E, e_off, L, l_off, R, r_off, P, p_off, G,
                tol, contains, margins):
    """``Cone.check`` of K packed cones at N wrenches: ``contains[n, k]`` and
    ``margins[n, k]`` of cone k at wrench G[n] (SI), the same float operations in the
    same order as ``cones._Query.check`` and ``_Query.check_many`` (so the same doubles).

    Cone k's rows are ``F[f_off[k]:f_off[k + 1]]`` (unit facet rows, nondimensional),
    likewise its equality rows E, lineality rows L, unit rays R and face projections P
    (9 values each, row by row); ``inv_l[k]`` = 1 / its length scale. Returns
    CHECKS_OK, or CHECKS_NOT_FINITE at the first wrench whose nondimensional norm is not
    finite (the rest of the output is then undefined).
    """
    N, K = G.shape[0], feasible.shape[0]
    for n in range(N):
        g0, g1, g2 = G[n, 0], G[n, 1], G[n, 2]
        for k in range(K):
            if not feasible[k]:
                contains[n, k] = False
                margins[n, k] = -1.0
                continue
            x, y, z = g0, g1, g2 * inv_l[k]
            norm = math.sqrt(x * x + y * y + z * z)
            if not math.isfinite(norm):
                return CHECKS_NOT_FINITE
            if norm == 0:
                contains[n, k] = True
                margins[n, k] = 0.0
                continue
            x, y, z = x / norm, y / norm, z / norm
            f0, f1, e0, e1 = f_off[k], f_off[k + 1], e_off[k], e_off[k + 1]
            if f0 == f1 and e0 == e1:
                contains[n, k] = True
                margins[n, k] = 1.0
                continue
            fmax = -math.inf
            for i in range(f0, f1):
                v = F[i, 0] * x + F[i, 1] * y + F[i, 2] * z
                if v > fmax:
                    fmax = v
            emax = 0.0
            for i in range(e0, e1):
                v = abs(E[i, 0] * x + E[i, 1] * y + E[i, 2] * z)
                if v > emax:
                    emax = v
            contains[n, k] = fmax <= tol and emax <= tol
            if fmax <= 0.0 and emax == 0.0:
                margins[n, k] = 0.0 if e1 > e0 else 0.0 - fmax
                continue
            # _Query._margin_outside
            lin2 = 0.0
            for i in range(l_off[k], l_off[k + 1]):
                v = L[i, 0] * x + L[i, 1] * y + L[i, 2] * z
                lin2 = lin2 + v * v
            best2 = 1.0 - lin2
            r0, r1 = r_off[k], r_off[k + 1]
            if r1 > r0:
                t = -math.inf
                for i in range(r0, r1):
                    v = R[i, 0] * x + R[i, 1] * y + R[i, 2] * z
                    if v > t:
                        t = v
                if t > 0:
                    v = 1.0 - lin2 - t * t
                    if v < best2:
                        best2 = v
            for j in range(p_off[k], p_off[k + 1]):
                px = P[j, 0] * x + P[j, 1] * y + P[j, 2] * z
                py = P[j, 3] * x + P[j, 4] * y + P[j, 5] * z
                pz = P[j, 6] * x + P[j, 7] * y + P[j, 8] * z
                bound = tol * math.sqrt(px * px + py * py + pz * pz)
                inside = True
                for i in range(f0, f1):
                    if F[i, 0] * px + F[i, 1] * py + F[i, 2] * pz > bound:
                        inside = False
                        break
                if inside:
                    for i in range(e0, e1):
                        if abs(E[i, 0] * px + E[i, 1] * py + E[i, 2] * pz) > bound:
                            inside = False
                            break
                if inside:
                    dx, dy, dz = x - px, y - py, z - pz
                    v = dx * dx + dy * dy + dz * dz
                    if v < best2:
                        best2 = v
            margins[n, k] = 0.0 - math.sqrt(0.0 if 0.0 > best2 else best2)
    return CHECKS_OK
