# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An independent enumeration of edge-edge-edge placements of a polygon on a pin
lattice, written from the geometry alone (nothing here imports wrenchcone_ros).

Pose (t, theta): a part point v is at t + R(theta) v. A pin of radius r at c touches
edge e (outward unit normal n, first vertex a) from outside when (R(theta) n) . (c - t)
= n . a + r. Each pin has its own radius r_m (pins of unequal radii), so e_m = n_m .
a_m + r_m is per pin. For three pins on three edges, the three equations are linear in
t; they have a common solution when the 3 x 3 determinant of [N_m^T | N_m . c_m - e_m]
vanishes (N_m = R(theta) n_m). Expanded along its last column, with the 2 x 2 minors N_a x N_b =
n_a x n_b independent of theta:

    A cos(theta) + B sin(theta) + C = 0,  w_m = n_{m+1} x n_{m+2} (cyclic),
    A = sum w_m (n_m . c_m),  B = sum w_m (n_m x c_m),  C = -sum w_m e_m,

so theta = atan2(B, A) +- acos(-C / hypot(A, B)), then t from the linear equations. A
solution counts when every pin's distance to the polygon's boundary is r (within tol),
no pin centre is inside, and each pin's foot on its edge lies on the segment.

On a plate that offers several pin radii each of the three pins takes any of them: the
reference solves every assignment (the product of the radii, pin by pin), all at once.
"""

from __future__ import annotations

import itertools
import math

import numpy as np


def edges(V):
    V = np.asarray(V, dtype=float)
    A, B = V, np.roll(V, -1, axis=0)
    E = B - A
    le = np.hypot(E[:, 0], E[:, 1])
    n = np.stack([E[:, 1], -E[:, 0]], axis=1) / le[:, None]
    return A, B, n


def boundary_distance(V, P):
    A, B, _ = edges(V)
    best = math.inf
    for a, b in zip(A, B):
        ab = b - a
        t = min(1.0, max(0.0, float((P - a) @ ab) / float(ab @ ab)))
        best = min(best, float(np.hypot(*(P - a - t * ab))))
    return best


def inside(V, P) -> bool:
    V = np.asarray(V, dtype=float)
    c = False
    for k in range(len(V)):
        (x1, y1), (x2, y2) = V[k], V[(k + 1) % len(V)]
        if (y1 > P[1]) != (y2 > P[1]) and P[0] < x1 + (P[1] - y1) * (x2 - x1) / (y2 - y1):
            c = not c
    return c


def to_part(pose, c):
    x, y, th = pose
    co, si = math.cos(th), math.sin(th)
    dx, dy = c[0] - x, c[1] - y
    return np.array([co * dx + si * dy, -si * dx + co * dy])


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def eee_poses(V, pins, r, tol=1e-9):
    """Every pose touching the three pins (plate frame, (3, 2)) with edge contacts: a
    list of (pose, edge triple), pins of radius r (one number). With ``r`` a list of
    radius triples (one radius per pin each): a list of (pose, edge triple, radii). All
    edge triples and radius triples at once (numpy)."""
    one = np.ndim(r) == 0
    RR = np.array([[r, r, r]] if one else r, dtype=float)  # (Q, 3)
    A, B, n = edges(V)
    e0 = np.einsum("ij,ij->i", n, A)
    m = len(V)
    K1 = np.array(list(itertools.product(range(m), repeat=3)))
    K = np.tile(K1, (len(RR), 1))
    Q = np.repeat(np.arange(len(RR)), len(K1))  # the radius triple of each row
    eK = e0[K] + RR[Q]  # (M, 3): each pin's edge offset with its own radius
    nn = n[K]  # (M, 3, 2)
    w = np.stack([_cross(nn[:, (i + 1) % 3], nn[:, (i + 2) % 3]) for i in range(3)], 1)
    Ac = np.sum(w * np.einsum("mij,ij->mi", nn, pins), axis=1)
    Bc = np.sum(w * _cross(nn, pins[None]), axis=1)
    Cc = -np.sum(w * eK, axis=1)
    R = np.hypot(Ac, Bc)
    ok = (np.max(np.abs(w), axis=1) >= 1e-12) & (R >= 1e-15) & (np.abs(Cc) <= R * (1 + 1e-12))
    K, nn, Ac, Bc, Cc, R, eK, Q = K[ok], nn[ok], Ac[ok], Bc[ok], Cc[ok], R[ok], eK[ok], Q[ok]
    base = np.arctan2(Bc, Ac)
    off = np.arccos(np.clip(-Cc / R, -1.0, 1.0))
    th = np.concatenate([base + off, base - off])
    K2, nn2 = np.concatenate([K, K]), np.concatenate([nn, nn])
    eK2, Q2 = np.concatenate([eK, eK]), np.concatenate([Q, Q])
    co, si = np.cos(th)[:, None], np.sin(th)[:, None]
    N = np.stack([co * nn2[..., 0] - si * nn2[..., 1], si * nn2[..., 0] + co * nn2[..., 1]],
                 -1)  # (M2, 3, 2)
    rhs = np.einsum("mij,ij->mi", N, pins) - eK2
    NtN = np.einsum("mki,mkj->mij", N, N)
    good = np.abs(np.linalg.det(NtN)) > 1e-20
    t = np.zeros((len(th), 2))
    t[good] = np.linalg.solve(NtN[good], np.einsum("mki,mk->mi", N[good], rhs[good])[..., None])[..., 0]
    good &= np.max(np.abs(np.einsum("mij,mj->mi", N, t) - rhs), axis=1) <= tol
    idx = np.flatnonzero(good)
    keep = touches_edges_all(V, t[idx], th[idx], pins, K2[idx], RR[Q2[idx]], tol)
    out = []
    seen = set()
    for i in idx[keep]:
        pose = (float(t[i, 0]), float(t[i, 1]), math.remainder(float(th[i]), 2 * math.pi))
        ks = tuple(int(k) for k in K2[i])
        rs = tuple(float(v) for v in RR[Q2[i]])
        if (ks, rs, round(pose[2], 12)) in seen:
            continue  # a double root (off = 0) found twice
        seen.add((ks, rs, round(pose[2], 12)))
        out.append((pose, ks) if one else (pose, ks, rs))
    return out


def touches_edges_all(V, t, th, pins, K, RS, tol) -> np.ndarray:
    """:func:`touches_edges` for many poses at once (numpy, the same tests): poses
    (t[i], th[i]), each with its edge triple K[i] and radius triple RS[i]; a boolean per
    pose."""
    A, B, n = edges(V)
    co, si = np.cos(th)[:, None], np.sin(th)[:, None]
    d = pins[None] - t[:, None, :]  # (M, 3, 2): pin minus translation, plate frame
    P = np.stack([co * d[..., 0] + si * d[..., 1], -si * d[..., 0] + co * d[..., 1]], -1)
    ab = (B - A)[K]  # (M, 3, 2)
    PA = P - A[K]
    ab2 = np.einsum("mij,mij->mi", ab, ab)
    s = np.einsum("mij,mij->mi", PA, ab) / ab2
    slack = tol / np.sqrt(ab2)
    ok = np.all((-slack <= s) & (s <= 1 + slack), axis=1)
    ok &= np.all(np.abs(np.einsum("mij,mij->mi", n[K], PA) - RS) <= tol, axis=1)
    # every pin outside the polygon and r from its boundary (every edge's segment)
    E = B - A  # (e, 2)
    Q = P[:, :, None, :] - A[None, None]  # (M, 3, e, 2)
    u = np.clip(np.einsum("mpek,ek->mpe", Q, E) / np.einsum("ek,ek->e", E, E), 0.0, 1.0)
    dist = np.min(np.hypot(Q[..., 0] - u * E[:, 0], Q[..., 1] - u * E[:, 1]), axis=2)
    ok &= np.all(np.abs(dist - RS) <= tol, axis=1)
    y1, y2 = A[:, 1], B[:, 1]
    x1, x2 = A[:, 0], B[:, 0]
    Px, Py = P[..., 0][..., None], P[..., 1][..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        cross = ((y1 > Py) != (y2 > Py)) & (Px < x1 + (Py - y1) * (x2 - x1) / (y2 - y1))
    ok &= ~np.any(np.sum(cross, axis=2) % 2 == 1, axis=1)
    return ok


def touches_edges(V, pose, pins, ks, r, tol) -> bool:
    """Each pin (its radius r[m], or r for all) on its edge's segment and r from the
    polygon's boundary, outside."""
    A, B, n = edges(V)
    rs = [r] * len(pins) if np.ndim(r) == 0 else list(r)
    for c, k, r in zip(pins, ks, rs):
        P = to_part(pose, c)
        ab = B[k] - A[k]
        s = float((P - A[k]) @ ab) / float(ab @ ab)
        slack = tol / float(np.hypot(*ab))
        if not (-slack <= s <= 1 + slack) or abs(float(n[k] @ (P - A[k])) - r) > tol:
            return False
    for c, r in zip(pins, rs):
        P = to_part(pose, c)
        if inside(V, P) or abs(boundary_distance(V, P) - r) > tol:
            return False
    return True


def touches(V, pose, pin, label, r, tol) -> bool:
    """Whether the pin touches the feature ``label`` (eK: edge K's segment, vK: vertex
    K) at ``pose``, within tol."""
    A, B, _ = edges(V)
    P = to_part(pose, pin)
    k = int(label[1:])
    if label[0] == "v":
        return abs(float(np.hypot(*(P - A[k]))) - r) <= tol
    ab = B[k] - A[k]
    s = min(1.0, max(0.0, float((P - A[k]) @ ab) / float(ab @ ab)))
    return abs(float(np.hypot(*(P - A[k] - s * ab))) - r) <= tol


def sigma_min(V, pose, pins, contacts, com, L, r):
    """Smallest singular value of the rows (N, (p - com) x N / L) of the given (pin, edge)
    contacts at ``pose`` (N the unit normal into the part, p = c + r N the contact point,
    r the pin's radius (r[pin] when a list); plate frame; com in the part frame)."""
    rs = [r] * len(pins) if np.ndim(r) == 0 else list(r)
    _A, _B, n = edges(V)
    x, y, th = pose
    co, si = math.cos(th), math.sin(th)
    cw = np.array([x + co * com[0] - si * com[1], y + si * com[0] + co * com[1]])
    rows = []
    for pi, k in contacts:
        N = -np.array([co * n[k][0] - si * n[k][1], si * n[k][0] + co * n[k][1]])
        arm = pins[pi] + rs[pi] * N - cw
        rows.append([N[0], N[1], (arm[0] * N[1] - arm[1] * N[0]) / L])
    return float(np.linalg.svd(np.array(rows), compute_uv=False)[-1])


def fits(V, pose, plate_bounds, margin) -> bool:
    x0, y0, x1, y1 = plate_bounds
    x, y, th = pose
    co, si = math.cos(th), math.sin(th)
    for vx, vy in np.asarray(V, dtype=float):
        wx, wy = x + co * vx - si * vy, y + si * vx + co * vy
        if not (x0 + margin <= wx <= x1 - margin and y0 + margin <= wy <= y1 - margin):
            return False
    return True


def enumerate_eee(V, pitch, extent, r, com, L, tol=1e-9):
    """Every edge-edge-edge placement of the polygon on the plate's lattice: a list of
    dicts (holes sorted, pose, sigma_min of every edge contact found at that pose, fits
    with margins +-2e-6 m, and ``radii``, each pin's). ``r``: the pin radius, or a list
    of the radii the plate offers (every hole takes any of them: each triple of holes is
    solved for every radius of each of its pins)."""
    one = np.ndim(r) == 0
    offered = [float(r)] if one else sorted(float(v) for v in r)
    triples = [list(q) for q in itertools.product(offered, repeat=3)]
    nx, ny = extent
    holes = [(i, j) for i in range(nx) for j in range(ny)]
    Vd = np.asarray(V, dtype=float)
    diam = max(float(np.hypot(*(a - b))) for a in Vd for b in Vd) + 2 * max(offered)
    bounds = (-pitch / 2, -pitch / 2, (nx - 0.5) * pitch, (ny - 0.5) * pitch)
    out = []
    for h in itertools.combinations(holes, 3):
        pins = np.array(h, dtype=float) * pitch
        if max(float(np.hypot(*(pins[a] - pins[b]))) for a, b in ((0, 1), (0, 2), (1, 2))
               ) > diam:
            continue
        found = []  # (pose, radii, set of (pin, edge))
        for pose, ks, rs in eee_poses(V, pins, triples, tol):
            for f in found:
                if (f[1] == rs and math.hypot(f[0][0] - pose[0], f[0][1] - pose[1]) <= 1e-7
                        and abs(math.remainder(f[0][2] - pose[2], 2 * math.pi)) * L <= 1e-7):
                    f[2].update(enumerate(ks))
                    break
            else:
                found.append((pose, rs, set(enumerate(ks))))
        for pose, rs, cts in found:
            out.append({"holes": h, "pins": pins, "pose": pose, "radii": rs,
                        "sigma": sigma_min(V, pose, pins, sorted(cts), com, L, rs),
                        "fits_surely": fits(V, pose, bounds, 2e-6),
                        "fits_maybe": fits(V, pose, bounds, -2e-6)})
    return out
