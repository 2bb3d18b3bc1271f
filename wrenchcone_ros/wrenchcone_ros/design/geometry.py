# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Poses of a polygonal part touching three pins: closed-form solutions per contact
triple, and the first-order location test (the contact Jacobian).

A pin of radius r at c (plate frame) touches the part at pose (x, y, theta) when its
centre, seen in the part frame, P = R(-theta) (c - (x, y)), lies (each pin with its own
radius r_k: the three pins of a triple may differ, one :class:`Features` per radius)

* on the line of edge k moved out by r, inside the edge: n_k . P = n_k . a_k + r
  (n_k the outward unit normal of edge k from vertex a_k to a_k+1) -- an *edge* contact;
* on the circle of radius r about a convex vertex w: |P - w| = r -- a *vertex* contact
  (a pin cannot touch a reflex vertex alone; with r = 0 a vertex contact has no normal
  and is not used).

Three pins c_1, c_2, c_3 in the plate are a rigid triangle; in the part frame
P_k = P_1 + R(-theta) d_k, d_k = c_k - c_1. With C = cos theta, S = sin theta and
R(-theta) d = C d + S d' (d' = (d_y, -d_x)):

* three edge contacts: n_k . P_1 + C n_k . d_k + S n_k . d'_k = e_k, k = 1..3, are three
  linear equations in (P_1, C, S); their solutions are a line, cut by C^2 + S^2 = 1 in at
  most two points (:func:`solve_edges`);
* with a vertex contact, take it as pin 1: P_1 = w_1 + r (cos psi, sin psi). Each other
  contact is A_k(theta) cos psi + B_k(theta) sin psi + C_k(theta) = 0 with A, B, C linear
  in (1, C, S) (r = r_1 pin 1's radius; an edge: A, B = r n_k, C_k = n_k . (w_1 +
  R(-theta) d_k) - e_k, e_k with pin k's radius; a vertex w: with g = w_1 - w +
  R(-theta) d_k, |g + r u|^2 = r_k^2 reads 2 r u . g + |g|^2 + r^2 - r_k^2 = 0).
  Eliminating psi (Cramer, then cos^2 + sin^2 = 1):
  (B_2 C_3 - B_3 C_2)^2 + (A_3 C_2 - A_2 C_3)^2 = (A_2 B_3 - A_3 B_2)^2, a trigonometric
  polynomial of degree 4 in theta, i.e. a polynomial of degree 8 in u = tan(phi / 2),
  phi = theta - THETA_OFFSET (:func:`solve_vertex`): its real roots, then psi by Cramer.
  When pins 2 and 3 both touch edges of parallel normals the determinant vanishes
  identically; then C_3 - lambda C_2 = 0 (lambda = n_2 . n_3) gives theta in closed form
  and psi follows from one circle-line intersection.

Every root is polished by two Gauss-Newton steps on the three contact equations and
accepted only when, measured independently of the feature it was solved for (the
closest point of the whole polygon to each pin), every pin's gap is within
DESIGN_CONTACT_TOLERANCE_M and no pin penetrates (:func:`pin_gaps`). This is the
construction of Brost and Goldberg ("A complete algorithm for designing planar fixtures
using modular components", IEEE Trans. Robotics and Automation 12(1), 1996), with vertex
contacts added: no sampling.

Location (Asada and By, first order): the contact Jacobian N has one row
(n_k, (p_k - com) x n_k / L) per pin, n_k the unit normal from the pin into the part at
the contact point p_k and L the part's length scale. The pose is located when N has full
rank (the normals neither concurrent nor all parallel), well above round-off. Moving pin k by dc_k moves the
pose (com x, com y, L theta) by dq = N^-1 diag(n_k^T) dc; since diag(n_k^T) has
orthonormal rows, the worst pose error per unit pin error is ||N^-1||_2 = 1/sigma_min(N)
(:func:`locating_accuracy`, m per m).

Every contact a pin makes (:func:`pin_contacts`): a pin touches each edge and each
convex vertex whose gap is within the contact tolerance. Contacts at one point (an edge
touched at its end, and the vertex there) are one contact with the edge's normal and
both labels (``e2+v3``); contacts at distinct points (the two edges of a concave corner)
are distinct contacts, each a row of N (:func:`contacts_jacobian`). With more than three
rows the accuracy is 1 / sigma_3(N) = ||N^+||_2, the least-squares pose error per unit
contact displacement. A placement is located when sigma_3(N) > LOCATING_SIGMA_MIN and,
when every contact has an edge's normal, no exact (rational) computation finds those
edges all parallel (:func:`locate`): round-off cannot make parallel normals located.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .problem import LOCATING_SIGMA_MIN


#: Radians: the offset of the half-angle parametrisation u = tan((theta - offset) / 2),
#: an irrational angle so that no solution of an ordinary part sits at u = infinity.
THETA_OFFSET: float = 0.5 * (math.sqrt(5.0) - 1.0) * math.pi

#: Dimensionless: a root u of the degree-8 polynomial counts as real when
#: |Im u| <= ROOT_IMAG_TOLERANCE (1 + |u|) (double roots come out as close pairs); every
#: candidate is checked on the gaps afterwards.
ROOT_IMAG_TOLERANCE: float = 1e-5

#: Dimensionless, relative: coefficients (or determinants) below this times the scale
#: of their terms count as zero (an identically vanishing polynomial, a singular solve).
DEGENERACY_TOLERANCE: float = 1e-10


@dataclass(frozen=True)
class Features:
    """The contact features of a CCW polygon for pins of radius ``r``: edges 0..n-1
    (first vertex ``a``, outward unit normal ``normal``, offset ``e`` = n . a + r) and,
    when r > 0, the convex vertices (feature n + k is vertex k).

    Parameters
    ----------
    vertices : numpy.ndarray
        The polygon's vertices, (n, 2), m, part frame, counter-clockwise.
    normal : numpy.ndarray
        The edges' outward unit normals, (n, 2).
    e : numpy.ndarray
        The edges' offsets n . a + r (m), (n,).
    convex : numpy.ndarray
        The indices of the convex vertices usable as vertex features, (m,).
    r : float
        The pin radius (m).
    """

    vertices: np.ndarray  # (n, 2)
    normal: np.ndarray  # (n, 2) outward unit normals of the edges
    e: np.ndarray  # (n,)
    convex: np.ndarray  # (m,) indices of the convex vertices usable as vertex features
    r: float

    @staticmethod
    def of(vertices, r: float) -> Features:
        """The features of a polygon for pins of radius ``r``.

        Parameters
        ----------
        vertices : array_like
            The polygon's vertices, (n, 2), m, counter-clockwise.
        r : float
            The pin radius (m); with 0 no vertex is a feature.

        Returns
        -------
        Features
            The features.
        """
        V = np.asarray(vertices, dtype=float)
        E = np.roll(V, -1, axis=0) - V
        lens = np.hypot(E[:, 0], E[:, 1])
        normal = np.stack([E[:, 1], -E[:, 0]], axis=1) / lens[:, None]
        convex = convex_vertices(V) if r > 0 else np.zeros(0, dtype=int)
        return Features(V, normal, np.einsum("ij,ij->i", normal, V) + r, convex, float(r))

    @property
    def n_edges(self) -> int:
        """The number of edges, n."""
        return len(self.vertices)

    @property
    def codes(self) -> np.ndarray:
        """Every feature's code: 0..n-1 edges, n + k vertex k (convex only)."""
        return np.concatenate([np.arange(self.n_edges), self.n_edges + self.convex])

    def label(self, code: int) -> str:
        """A feature's label: ``e<k>`` for edge k, ``v<k>`` for vertex k.

        Parameters
        ----------
        code : int
            The feature's code.

        Returns
        -------
        str
            The label.
        """
        n = self.n_edges
        return f"e{code}" if code < n else f"v{code - n}"


def convex_vertices(vertices) -> np.ndarray:
    """The indices of a counter-clockwise polygon's convex vertices (a left turn there).

    Parameters
    ----------
    vertices : array_like
        The polygon's vertices, (n, 2), m, counter-clockwise.

    Returns
    -------
    numpy.ndarray
        The indices, ascending.
    """
    V = np.asarray(vertices, dtype=float)
    E = np.roll(V, -1, axis=0) - V
    prev = V - np.roll(V, 1, axis=0)
    return np.flatnonzero(prev[:, 0] * E[:, 1] - prev[:, 1] * E[:, 0] > 0)


def per_pin(F) -> tuple[Features, Features, Features]:
    """The features of each of three pins: ``F`` three times when it is one
    :class:`Features` (pins of one radius), else the three given (one per pin radius).

    Parameters
    ----------
    F : Features or sequence of 3 Features
        One for every pin, or one per pin (same polygon, each pin's radius).

    Returns
    -------
    tuple of 3 Features
        One per pin.

    Raises
    ------
    ValueError
        A sequence of other than three.
    """
    if isinstance(F, Features):
        return (F, F, F)
    Fs = tuple(F)
    if len(Fs) != 3:
        raise ValueError(f"give one Features or one per pin (3), got {len(Fs)}")
    return Fs


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return c, s


def _prime(d: np.ndarray) -> np.ndarray:
    """d' = (d_y, -d_x): R(-theta) d = C d + S d'."""
    return np.stack([d[..., 1], -d[..., 0]], axis=-1)


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


# --- closed forms ------------------------------------------------------------------------
def solve_edges(F, pins: np.ndarray, codes: np.ndarray) -> list[tuple[int, tuple]]:
    """Poses for rows of three edge contacts (module docstring). ``pins`` (3, 2) plate
    frame, ``codes`` (N, 3) edge codes; returns (row, (x, y, theta)) pairs.

    Parameters
    ----------
    F : Features or sequence of 3 Features
        The part's features for pins of one radius, or for each pin's radius.
    pins : numpy.ndarray
        The pins' centres, (3, 2), m, plate frame.
    codes : numpy.ndarray
        Edge codes, (N, 3).

    Returns
    -------
    list of (int, tuple)
        (row of ``codes``, (x m, y m, theta rad)) for every pose found.
    """
    out: list[tuple[int, tuple]] = []
    if len(codes) == 0:
        return out
    Fs = per_pin(F)
    F = Fs[0]
    n = F.normal[codes]  # (N, 3, 2)
    d = pins[None, :, :] - pins[None, 0:1, :]  # (1, 3, 2)
    d = np.broadcast_to(d, n.shape)
    M = np.concatenate([n, _dot(n, d)[..., None], _dot(n, _prime(d))[..., None]], axis=2)
    e = np.stack([Fs[k].e[codes[:, k]] for k in range(3)], axis=1)  # each pin's radius
    U, s, Vt = np.linalg.svd(M)
    ok = s[:, 2] > DEGENERACY_TOLERANCE * s[:, 0]
    for row in np.flatnonzero(ok):
        z0 = Vt[row, :3].T @ ((U[row].T @ e[row]) / s[row])
        v = Vt[row, 3]
        a = v[2] ** 2 + v[3] ** 2
        if a < DEGENERACY_TOLERANCE:
            continue  # (C, S) fixed by the rows: a continuum or nothing, never located
        b = 2 * (z0[2] * v[2] + z0[3] * v[3])
        c = z0[2] ** 2 + z0[3] ** 2 - 1
        disc = b * b - 4 * a * c
        if disc < -DEGENERACY_TOLERANCE:
            continue
        root = math.sqrt(max(disc, 0.0))
        for lam in {(-b - root) / (2 * a), (-b + root) / (2 * a)}:
            z = z0 + lam * v
            theta = math.atan2(z[3], z[2])
            out.append((int(row), _pose_from(pins[0], z[:2], theta)))
    return out


def _pose_from(c1, P1, theta: float) -> tuple[float, float, float]:
    """The pose whose part frame sees pin 1 (at c1) at P1: t = c1 - R(theta) P1."""
    c, s = math.cos(theta), math.sin(theta)
    return (float(c1[0] - (c * P1[0] - s * P1[1])), float(c1[1] - (s * P1[0] + c * P1[1])),
            float(math.atan2(s, c)))


def _tl_poly(a: np.ndarray) -> np.ndarray:
    """Numerator in u (highest power first) of a0 + ac cos(theta) + as sin(theta) at
    theta = THETA_OFFSET + phi, u = tan(phi / 2), over (1 + u^2). a: (N, 3)."""
    c0, s0 = math.cos(THETA_OFFSET), math.sin(THETA_OFFSET)
    a0 = a[:, 0]
    ac = a[:, 1] * c0 + a[:, 2] * s0
    as_ = a[:, 2] * c0 - a[:, 1] * s0
    return np.stack([a0 - ac, 2 * as_, a0 + ac], axis=1)


def _pmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0], a.shape[1] + b.shape[1] - 1))
    for i in range(a.shape[1]):
        out[:, i:i + b.shape[1]] += a[:, i:i + 1] * b
    return out


def _abc(F: Features, Fk: Features, w1: np.ndarray, d: np.ndarray, code: np.ndarray):
    """A, B, C of the contact of a pin (features ``Fk``, its radius) at offset d (N, 2)
    from pin 1 (features ``F``, its radius) with feature ``code`` (N,), pin 1 touching
    vertex w1 (N, 2): each (N, 3), coefficients of (1, cos theta, sin theta)."""
    N, r, nE = len(code), F.r, F.n_edges
    A, B, Cc = np.zeros((N, 3)), np.zeros((N, 3)), np.zeros((N, 3))
    dp = _prime(d)
    edge = code < nE
    if edge.any():
        nk = F.normal[code[edge]]
        A[edge, 0], B[edge, 0] = r * nk[:, 0], r * nk[:, 1]
        Cc[edge] = np.stack([_dot(nk, w1[edge]) - Fk.e[code[edge]], _dot(nk, d[edge]),
                             _dot(nk, dp[edge])], axis=1)
    vtx = ~edge
    if vtx.any():
        g = w1[vtx] - F.vertices[code[vtx] - nE]
        dv, dpv = d[vtx], dp[vtx]
        A[vtx] = 2 * r * np.stack([g[:, 0], dv[:, 0], dpv[:, 0]], axis=1)
        B[vtx] = 2 * r * np.stack([g[:, 1], dv[:, 1], dpv[:, 1]], axis=1)
        Cc[vtx] = np.stack([_dot(g, g) + _dot(dv, dv) + (r * r - Fk.r * Fk.r),
                            2 * _dot(g, dv), 2 * _dot(g, dpv)], axis=1)
    return A, B, Cc


def _tl(a: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return a[..., 0] + a[..., 1] * np.cos(theta) + a[..., 2] * np.sin(theta)


def _real_roots(P: np.ndarray) -> list[np.ndarray]:
    """Real roots u of each row's polynomial (highest power first), and u = inf (phi =
    pi) where the leading coefficient vanishes. The eigenvalues of the companion
    matrices, all rows in one batch (numpy.roots does the same row by row)."""
    scale = np.max(np.abs(P), axis=1, keepdims=True)
    p = P / np.where(scale == 0, 1.0, scale)
    out: list[np.ndarray] = [np.zeros(0)] * len(P)
    full = np.flatnonzero(np.abs(p[:, 0]) > DEGENERACY_TOLERANCE)
    if len(full):
        q = p[full]
        deg = q.shape[1] - 1
        C = np.zeros((len(full), deg, deg))
        C[:, 0, :] = -q[:, 1:] / q[:, :1]
        C[:, np.arange(1, deg), np.arange(deg - 1)] = 1.0
        for k, r in zip(full, np.linalg.eigvals(C)):
            out[k] = r[np.abs(r.imag) <= ROOT_IMAG_TOLERANCE * (1 + np.abs(r))].real
    for k in np.flatnonzero(np.abs(p[:, 0]) <= DEGENERACY_TOLERANCE):
        nz = np.flatnonzero(np.abs(p[k]) > DEGENERACY_TOLERANCE)
        if not len(nz):
            continue  # the zero polynomial (the caller skips it)
        roots = np.roots(p[k, nz[0]:]) if len(p[k]) - nz[0] > 1 else np.zeros(0)
        real = roots[np.abs(roots.imag) <= ROOT_IMAG_TOLERANCE * (1 + np.abs(roots))].real
        out[k] = np.append(real, np.inf)
    return out


def solve_vertex(F, pins: np.ndarray, codes: np.ndarray
                 ) -> list[tuple[int, tuple]]:
    """Poses for rows whose first contact is a vertex (module docstring). ``pins`` (3,
    2), ``codes`` (N, 3) with codes[:, 0] a vertex.

    Parameters
    ----------
    F : Features or sequence of 3 Features
        The part's features for pins of one radius, or for each pin's radius.
    pins : numpy.ndarray
        The pins' centres, (3, 2), m, plate frame.
    codes : numpy.ndarray
        Feature codes, (N, 3), the first a vertex.

    Returns
    -------
    list of (int, tuple)
        (row of ``codes``, (x m, y m, theta rad)) for every pose found.
    """
    out: list[tuple[int, tuple]] = []
    N = len(codes)
    if N == 0:
        return out
    Fs = per_pin(F)
    F = Fs[0]
    r, nE = F.r, F.n_edges
    w1 = F.vertices[codes[:, 0] - nE]
    d2 = np.broadcast_to(pins[1] - pins[0], (N, 2))
    d3 = np.broadcast_to(pins[2] - pins[0], (N, 2))
    A2, B2, C2 = _abc(F, Fs[1], w1, d2, codes[:, 1])
    A3, B3, C3 = _abc(F, Fs[2], w1, d3, codes[:, 2])
    both_edges = (codes[:, 1] < nE) & (codes[:, 2] < nE)
    n2, n3 = F.normal[np.minimum(codes[:, 1], nE - 1)], F.normal[np.minimum(codes[:, 2],
                                                                              nE - 1)]
    parallel = both_edges & (np.abs(n2[:, 0] * n3[:, 1] - n2[:, 1] * n3[:, 0])
                             <= DEGENERACY_TOLERANCE)
    gen = np.flatnonzero(~parallel)
    if len(gen):
        pA2, pB2, pC2 = _tl_poly(A2[gen]), _tl_poly(B2[gen]), _tl_poly(C2[gen])
        pA3, pB3, pC3 = _tl_poly(A3[gen]), _tl_poly(B3[gen]), _tl_poly(C3[gen])
        D = _pmul(pA2, pB3) - _pmul(pA3, pB2)
        Nc = _pmul(pB2, pC3) - _pmul(pB3, pC2)
        Ns = _pmul(pA3, pC2) - _pmul(pA2, pC3)
        P = _pmul(Nc, Nc) + _pmul(Ns, Ns) - _pmul(D, D)
        size = (np.abs(_pmul(Nc, Nc)) + np.abs(_pmul(Ns, Ns)) + np.abs(_pmul(D, D))).max(1)
        for k, (row, roots) in enumerate(zip(gen, _real_roots(P))):
            if np.max(np.abs(P[k])) <= DEGENERACY_TOLERANCE * size[k]:
                continue  # identically zero: a continuum of poses, never located
            for u in roots:
                theta = THETA_OFFSET + (math.pi if np.isinf(u) else 2 * math.atan(u))
                for cpsi, spsi in _psi(A2[row], B2[row], C2[row], A3[row], B3[row],
                                       C3[row], theta):
                    P1 = w1[row] + r * np.array([cpsi, spsi])
                    out.append((int(row), _pose_from(pins[0], P1, theta)))
    for row in np.flatnonzero(parallel):
        lam = float(_dot(n2[row], n3[row]))
        q = C3[row] - lam * C2[row]
        R = math.hypot(q[1], q[2])
        if R <= DEGENERACY_TOLERANCE * (abs(q[0]) + 1e-300) or abs(q[0]) > R:
            continue  # no solution, or every theta: a continuum, never located
        alpha, beta = math.atan2(q[2], q[1]), math.acos(-q[0] / R)
        for theta in {alpha + beta, alpha - beta}:
            for cpsi, spsi in _circle_line(A2[row], B2[row], C2[row], theta):
                P1 = w1[row] + r * np.array([cpsi, spsi])
                out.append((int(row), _pose_from(pins[0], P1, theta)))
    return out


def _circle_line(A, B, Cc, theta: float) -> list[tuple[float, float]]:
    """(cos psi, sin psi) with a cos psi + b sin psi + c = 0 at theta (two at most)."""
    a, b, c = float(_tl(A, theta)), float(_tl(B, theta)), float(_tl(Cc, theta))
    R = math.hypot(a, b)
    if R == 0 or abs(c) > R * (1 + 1e-12):
        return []
    base, off = math.atan2(b, a), math.acos(max(-1.0, min(1.0, -c / R)))
    return [(math.cos(base + s * off), math.sin(base + s * off)) for s in {1.0, -1.0}]


def _psi(A2, B2, C2, A3, B3, C3, theta: float) -> list[tuple[float, float]]:
    """(cos psi, sin psi) solving both contacts at theta: Cramer, or (a singular pair)
    the circle-line solutions of the first that also solve the second."""
    a2, b2, c2 = float(_tl(A2, theta)), float(_tl(B2, theta)), float(_tl(C2, theta))
    a3, b3, c3 = float(_tl(A3, theta)), float(_tl(B3, theta)), float(_tl(C3, theta))
    D = a2 * b3 - a3 * b2
    if abs(D) > 1e-8 * (abs(a2) + abs(b2)) * (abs(a3) + abs(b3)):
        c, s = (b2 * c3 - b3 * c2) / D, (a3 * c2 - a2 * c3) / D
        h = math.hypot(c, s)
        return [(c / h, s / h)] if h > 0 else []
    scale = abs(a3) + abs(b3) + abs(c3)
    return [(c, s) for c, s in _circle_line(A2, B2, C2, theta)
            if abs(a3 * c + b3 * s + c3) <= 1e-6 * scale]


# --- gaps, independent of the features solved for -------------------------------------------
def pin_gaps(vertices: np.ndarray, poses: np.ndarray, pins: np.ndarray, r):
    """Signed gaps (m) of pins of radius r to the polygon at each pose, and the closest
    feature of each (edge code k, or n + k for vertex k).

    ``poses`` (M, 3), ``pins`` (M, K, 2) plate frame. Gap = signed distance of the pin
    centre to the polygon (negative inside) - r.

    Parameters
    ----------
    vertices : numpy.ndarray
        The polygon's vertices, (n, 2), m, counter-clockwise.
    poses : numpy.ndarray
        Poses (x m, y m, theta rad), (M, 3).
    pins : numpy.ndarray
        Pin centres, (M, K, 2), m, plate frame.
    r : float or array_like
        The pin radius (m), or each pin's, (K,).

    Returns
    -------
    gaps : numpy.ndarray
        (M, K), m.
    features : numpy.ndarray
        (M, K), the closest feature's code.
    """
    V = np.asarray(vertices, dtype=float)
    n = len(V)
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    dx = pins[..., 0] - poses[:, None, 0]
    dy = pins[..., 1] - poses[:, None, 1]
    px, py = c[:, None] * dx + s[:, None] * dy, -s[:, None] * dx + c[:, None] * dy
    a, b = V, np.roll(V, -1, axis=0)
    ex, ey = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    t = ((px[..., None] - a[:, 0]) * ex + (py[..., None] - a[:, 1]) * ey) / (ex * ex + ey * ey)
    tc = np.clip(t, 0.0, 1.0)
    qx, qy = a[:, 0] + tc * ex, a[:, 1] + tc * ey
    d2 = (px[..., None] - qx) ** 2 + (py[..., None] - qy) ** 2
    k = np.argmin(d2, axis=-1)
    dist = np.sqrt(np.take_along_axis(d2, k[..., None], -1)[..., 0])
    tk = np.take_along_axis(t, k[..., None], -1)[..., 0]
    feature = np.where(tk <= 0, n + k, np.where(tk >= 1, n + (k + 1) % n, k))
    # inside: ray crossing to +x
    y1, y2 = a[:, 1], b[:, 1]
    cross = (y1 > py[..., None]) != (y2 > py[..., None])
    with np.errstate(divide="ignore", invalid="ignore"):
        xint = a[:, 0] + (py[..., None] - y1) * (b[:, 0] - a[:, 0]) / (y2 - y1)
    inside = (np.sum(cross & (px[..., None] < xint), axis=-1) % 2) == 1
    return np.where(inside, -dist, dist) - (r if np.isscalar(r) else np.asarray(r, float)), \
        feature


def _residual(F, poses: np.ndarray, pins: np.ndarray, codes: np.ndarray
              ) -> np.ndarray:
    """The three contact equations of each candidate (m): n . P - e on an edge,
    |P - w| - r at a vertex, each pin with its radius (F: one Features or one per pin).
    poses (M, 3), pins (3, 2), codes (M, 3)."""
    Fs = per_pin(F)
    F = Fs[0]
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    dx, dy = pins[None, :, 0] - poses[:, None, 0], pins[None, :, 1] - poses[:, None, 1]
    P = np.stack([c[:, None] * dx + s[:, None] * dy, -s[:, None] * dx + c[:, None] * dy], -1)
    nE = F.n_edges
    edge = codes < nE
    res = np.empty(codes.shape)
    ce = np.minimum(codes, nE - 1)
    res_e = _dot(F.normal[ce], P) - np.stack([Fs[k].e[ce[:, k]] for k in range(3)], axis=1)
    w = F.vertices[np.where(edge, 0, codes - nE)]
    res_v = np.hypot(*(P - w).transpose(2, 0, 1)) - np.array([G.r for G in Fs])
    res[:] = np.where(edge, res_e, res_v)
    return res


def polish(F, poses: np.ndarray, pins: np.ndarray, codes: np.ndarray,
           L: float, steps: int = 2) -> np.ndarray:
    """Gauss-Newton steps on the contact equations (finite-difference Jacobian in (x, y,
    L theta)): the closed form's roots to full precision.

    Parameters
    ----------
    F : Features or sequence of 3 Features
        The part's features for pins of one radius, or for each pin's radius.
    poses : numpy.ndarray
        Poses (x m, y m, theta rad), (M, 3).
    pins : numpy.ndarray
        The pins' centres, (3, 2), m, plate frame.
    codes : numpy.ndarray
        Each pose's feature codes, (M, 3).
    L : float
        The part's length scale (m).
    steps : int, optional
        The number of Gauss-Newton steps.

    Returns
    -------
    numpy.ndarray
        The polished poses, (M, 3), theta in (-pi, pi].
    """
    q = poses.copy()
    h = 1e-7 * L
    for _ in range(steps):
        r0 = _residual(F, q, pins, codes)
        J = np.empty((len(q), 3, 3))
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = h if j < 2 else h / L
            J[:, :, j] = (_residual(F, q + dq, pins, codes) - r0) / h
        try:
            step = np.linalg.solve(J, -r0[..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = np.stack([np.linalg.lstsq(Jk, -rk, rcond=None)[0]
                             for Jk, rk in zip(J, r0)]) if len(q) else np.zeros((0, 3))
        step[:, 2] /= L
        bad = ~np.all(np.isfinite(step), axis=1) | (np.abs(step[:, :2]).max(1) > 1e-3 * L)
        step[bad] = 0.0
        q += step
    q[:, 2] = np.arctan2(np.sin(q[:, 2]), np.cos(q[:, 2]))
    return q


def solve_poses(F, pins: np.ndarray, codes: np.ndarray, L: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Every pose of the part touching the three ``pins`` (3, 2) with the contact
    ``codes`` (N, 3), polished: (poses (M, 3), row of codes (M,)). Not yet checked for
    penetration or the actual closest features (:func:`pin_gaps`).

    Parameters
    ----------
    F : Features or sequence of 3 Features
        The part's features for pins of one radius, or for each pin's radius (a pin's
        vertex codes only when its radius is positive).
    pins : numpy.ndarray
        The pins' centres, (3, 2), m, plate frame.
    codes : numpy.ndarray
        Feature codes, (N, 3).
    L : float
        The part's length scale (m).

    Returns
    -------
    poses : numpy.ndarray
        (M, 3): x (m), y (m), theta (rad).
    rows : numpy.ndarray
        (M,): the row of ``codes`` of each pose.
    """
    codes = np.asarray(codes, dtype=int)
    Fs = per_pin(F)
    nE = Fs[0].n_edges
    isv = codes >= nE
    has_v = isv.any(axis=1)
    found: list[tuple[int, tuple]] = []
    found += [(int(np.flatnonzero(~has_v)[k]), p) for k, p in
              solve_edges(Fs, pins, codes[~has_v])]
    vrows = np.flatnonzero(has_v)
    if len(vrows):
        first = np.argmax(isv[vrows], axis=1)  # the first vertex contact becomes pin 1
        order = np.stack([first, (first + 1) % 3, (first + 2) % 3], axis=1)
        for f in range(3):
            sel = first == f
            if not sel.any():
                continue
            perm = order[sel][0]
            sub = np.take_along_axis(codes[vrows[sel]], order[sel], axis=1)
            found += [(int(vrows[sel][k]), p) for k, p in
                      solve_vertex(tuple(Fs[k] for k in perm), pins[perm], sub)]
    if not found:
        return np.zeros((0, 3)), np.zeros(0, dtype=int)
    rows = np.array([k for k, _ in found], dtype=int)
    poses = np.array([p for _, p in found], dtype=float)
    return polish(Fs, poses, pins, codes[rows], L), rows


# --- location ---------------------------------------------------------------------------------
def contact_jacobian(vertices, com, pose, pins: np.ndarray, features, r: float, L: float
                     ) -> np.ndarray:
    """N (3 x 3): row k = (n_k, (p_k - com) x n_k / L), n_k the unit normal from pin k
    into the part at the contact point p_k (plate frame), for the closest ``features``
    (edge code k or n + vertex k) of :func:`pin_gaps`.

    Parameters
    ----------
    vertices : array_like
        The polygon's vertices, (n, 2), m, part frame.
    com : array_like
        The centre of mass (m, part frame).
    pose : tuple of 3 float
        (x m, y m, theta rad).
    pins : numpy.ndarray
        The pins' centres, (3, 2), m, plate frame.
    features : sequence of int
        The closest feature of each pin.
    r : float or sequence of 3 float
        The pin radius (m), or each pin's.
    L : float
        The part's length scale (m).

    Returns
    -------
    numpy.ndarray
        N, 3 x 3.
    """
    V = np.asarray(vertices, dtype=float)
    n = len(V)
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    R = np.array([[c, -s], [s, c]])
    t = np.array([x, y])
    comw = t + R @ np.asarray(com, dtype=float)
    rows = []
    rs = [r] * len(pins) if np.isscalar(r) else list(r)
    for pin, f, r in zip(pins, features, rs):
        f = int(f)
        if f < n:
            e = V[(f + 1) % n] - V[f]
            nin = -(R @ np.array([e[1], -e[0]])) / math.hypot(*e)
        else:
            w = t + R @ V[f - n]
            nin = (w - pin) / np.linalg.norm(w - pin)
        p = pin + r * nin
        arm = p - comw
        rows.append([nin[0], nin[1], (arm[0] * nin[1] - arm[1] * nin[0]) / L])
    return np.array(rows)


def locating_accuracy(N: np.ndarray) -> tuple[bool, float]:
    """(located, accuracy): sigma_min of the contact Jacobian (its third singular value)
    above LOCATING_SIGMA_MIN, and ||N^+||_2 = 1 / sigma_min (m of com or L theta motion
    per m of pin error; inf when not located).

    Parameters
    ----------
    N : numpy.ndarray
        The contact Jacobian, k x 3 (one row per contact, rows of norm >= 1).

    Returns
    -------
    located : bool
        Whether sigma_min(N) > LOCATING_SIGMA_MIN.
    accuracy : float
        ||N^+||_2 (m per m); inf when not located.
    """
    if N.shape[0] < 3:
        return False, math.inf
    sv = np.linalg.svd(N, compute_uv=False)
    located = bool(sv[2] > LOCATING_SIGMA_MIN)
    return located, (float(1.0 / sv[2]) if located else math.inf)


@dataclass(frozen=True)
class PinContact:
    """One contact of a pin with the part (module docstring).

    Parameters
    ----------
    labels : tuple of str
        The features touched at this point (``e<k>`` edge k, ``v<k>`` vertex k), edges
        first.
    point : tuple of 2 float
        The contact point (m, plate frame).
    normal : tuple of 2 float
        The unit normal from the pin into the part (plate frame).
    edges : tuple of int
        The edges touched here (empty: a vertex alone, whose normal depends on the pose).
    """

    labels: tuple[str, ...]
    point: tuple[float, float]
    normal: tuple[float, float]
    edges: tuple[int, ...]

    @property
    def label(self) -> str:
        """The labels joined by ``+`` (``e2+v3``)."""
        return "+".join(self.labels)


def same_point_distance(r: float, tol: float) -> float:
    """Metres: two contact points of one pin closer than this are one point. A pin whose
    centre is within ``tol`` of both an edge's line and the vertex at its end has the
    edge's foot within sqrt((r + tol)^2 - (r - tol)^2) = 2 sqrt(r tol) of the vertex.

    Parameters
    ----------
    r : float
        The pin radius (m).
    tol : float
        The contact tolerance (m).

    Returns
    -------
    float
        2 sqrt(r tol) + tol.
    """
    return 2.0 * math.sqrt(r * tol) + tol


def pin_contacts(F: Features, pose, pin, tol: float) -> tuple[PinContact, ...]:
    """Every contact of the pin at ``pin`` (plate frame) with the part at ``pose``: the
    edges and convex vertices within ``tol`` of touching, contacts at one point merged
    (module docstring), sorted by label.

    Parameters
    ----------
    F : Features
        The part's features (and the pin radius).
    pose : tuple of 3 float
        (x m, y m, theta rad).
    pin : sequence of 2 float
        The pin's centre (m, plate frame).
    tol : float
        The contact tolerance (m).

    Returns
    -------
    tuple of PinContact
        Empty when the pin touches nothing.
    """
    x, y, th = (float(v) for v in pose)
    c, s = math.cos(th), math.sin(th)
    dx, dy = float(pin[0]) - x, float(pin[1]) - y
    px, py = c * dx + s * dy, -s * dx + c * dy  # the pin centre, part frame
    V, NR, r, n = F.vertices.tolist(), F.normal.tolist(), F.r, F.n_edges
    delta = same_point_distance(r, tol)
    raw = []  # (label, edge or None, point (part frame), inward normal (part frame))
    for k in range(n):
        ax, ay = V[k]
        nx, ny = NR[k]
        if abs(nx * (px - ax) + ny * (py - ay) - r) > tol:
            continue
        bx, by = V[(k + 1) % n]
        ex, ey = bx - ax, by - ay
        le = math.hypot(ex, ey)
        t = ((px - ax) * ex + (py - ay) * ey) / (le * le)
        if -delta / le <= t <= 1 + delta / le:
            t = min(1.0, max(0.0, t))
            raw.append((f"e{k}", k, (ax + t * ex, ay + t * ey), (-nx, -ny)))
    for j in F.convex.tolist():
        wx, wy = V[j]
        d = math.hypot(wx - px, wy - py)
        if d > 0 and abs(d - r) <= tol:
            raw.append((f"v{j}", None, (wx, wy), ((wx - px) / d, (wy - py) / d)))
    groups: list[list] = []
    for item in raw:
        for g in groups:
            if any(math.hypot(item[2][0] - o[2][0], item[2][1] - o[2][1]) <= delta
                   for o in g):
                g.append(item)
                break
        else:
            groups.append([item])
    out = []
    for g in groups:
        g.sort(key=lambda it: (it[1] is None, int(it[0][1:])))
        head = g[0]  # an edge when one is touched here: the pin is tangent to its line
        (qx, qy), (mx, my) = head[2], head[3]
        out.append(PinContact(tuple(it[0] for it in g),
                           (x + c * qx - s * qy, y + s * qx + c * qy),
                           (c * mx - s * my, s * mx + c * my),
                           tuple(it[1] for it in g if it[1] is not None)))
    return tuple(sorted(out, key=lambda ct: ct.label))


def contacts_jacobian(contacts, com_world, L: float) -> np.ndarray:
    """N (k x 3): row (n, (p - com) x n / L) for each contact (p its point, n its normal
    into the part, plate frame).

    Parameters
    ----------
    contacts : sequence of PinContact
        Every contact of every pin.
    com_world : sequence of 2 float
        The centre of mass (m, plate frame).
    L : float
        The part's length scale (m).

    Returns
    -------
    numpy.ndarray
        N, k x 3.
    """
    rows = []
    for ct in contacts:
        (px, py), (nx, ny) = ct.point, ct.normal
        ax, ay = px - com_world[0], py - com_world[1]
        rows.append([nx, ny, (ax * ny - ay * nx) / L])
    return np.array(rows, dtype=float).reshape(-1, 3)


def edges_parallel_exactly(vertices, edges) -> bool:
    """Whether the given edges of a polygon are all parallel, in exact rational
    arithmetic on the vertices' coordinates.

    Parameters
    ----------
    vertices : array_like
        The polygon's vertices, (n, 2), m.
    edges : iterable of int
        Edge indices.

    Returns
    -------
    bool
        True when every pair's cross product is exactly zero.
    """
    V = [(Fraction(float(a)), Fraction(float(b))) for a, b in np.asarray(vertices)]
    n = len(V)
    dirs = []
    for k in sorted(set(int(e) for e in edges)):
        (ax, ay), (bx, by) = V[k], V[(k + 1) % n]
        dirs.append((bx - ax, by - ay))
    return all(dirs[0][0] * d[1] - dirs[0][1] * d[0] == 0 for d in dirs[1:])


def locate(F: Features, contacts, com_world, L: float) -> tuple[bool, float]:
    """(located, accuracy) of a placement from every contact of its pins (module
    docstring): :func:`locating_accuracy` of :func:`contacts_jacobian`, and not located
    when every contact has an edge's normal and those edges are parallel exactly.

    Parameters
    ----------
    F : Features
        The part's features.
    contacts : sequence of PinContact
        Every contact of every pin.
    com_world : sequence of 2 float
        The centre of mass (m, plate frame).
    L : float
        The part's length scale (m).

    Returns
    -------
    located : bool
        Whether the pins locate the part.
    accuracy : float
        ||N^+||_2 (m per m); inf when not located.
    """
    contacts = list(contacts)
    if all(ct.edges for ct in contacts):
        n0 = F.normal[contacts[0].edges[0]]
        # the exact check only where the float normals are parallel to rounding
        if all(abs(n0[0] * F.normal[ct.edges[0]][1] - n0[1] * F.normal[ct.edges[0]][0])
               <= 1e-9 for ct in contacts[1:]) and edges_parallel_exactly(
                F.vertices, [ct.edges[0] for ct in contacts]):
            return False, math.inf
    return locating_accuracy(contacts_jacobian(contacts, com_world, L))


__all__ = ["DEGENERACY_TOLERANCE", "Features", "PinContact", "ROOT_IMAG_TOLERANCE",
           "THETA_OFFSET", "contact_jacobian", "contacts_jacobian", "convex_vertices",
           "edges_parallel_exactly",
           "locate", "locating_accuracy", "per_pin", "pin_contacts", "pin_gaps", "polish",
           "same_point_distance", "solve_edges", "solve_poses", "solve_vertex"]
