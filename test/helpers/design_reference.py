# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An independent reference for the enumeration, written from the geometry: the
distance of a point to a polygon (its own code, not the package's), and a dense search
of poses: Gauss-Newton from a grid of start poses on the three pins' gaps, with a
finite-difference Jacobian. Nothing here imports wrenchcone_ros."""

from __future__ import annotations

import numpy as np


def boundary_distance(V: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Unsigned distance (m) of points P (..., 2) to the boundary of polygon V (n, 2)."""
    best = np.full(P.shape[:-1], np.inf)
    n = len(V)
    for k in range(n):
        a, b = V[k], V[(k + 1) % n]
        ab = b - a
        t = np.clip(((P - a) @ ab) / (ab @ ab), 0.0, 1.0)
        q = a + t[..., None] * ab
        best = np.minimum(best, np.linalg.norm(P - q, axis=-1))
    return best


def inside(V: np.ndarray, P: np.ndarray) -> np.ndarray:
    """Winding number != 0 (points strictly inside V)."""
    wn = np.zeros(P.shape[:-1], dtype=int)
    n = len(V)
    for k in range(n):
        a, b = V[k], V[(k + 1) % n]
        cr = (b[0] - a[0]) * (P[..., 1] - a[1]) - (P[..., 0] - a[0]) * (b[1] - a[1])
        up = (a[1] <= P[..., 1]) & (b[1] > P[..., 1]) & (cr > 0)
        down = (a[1] > P[..., 1]) & (b[1] <= P[..., 1]) & (cr < 0)
        wn += up.astype(int) - down.astype(int)
    return wn != 0


def to_part(poses: np.ndarray, pins: np.ndarray) -> np.ndarray:
    """Pins (3, 2) seen in the part frame at each pose (M, 3): (M, 3, 2)."""
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    dx = pins[None, :, 0] - poses[:, None, 0]
    dy = pins[None, :, 1] - poses[:, None, 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


def gaps(V, poses, pins, r) -> np.ndarray:
    """Signed gap (m) of each pin: distance to the boundary, negative inside, minus r."""
    P = to_part(poses, pins)
    d = boundary_distance(V, P)
    return np.where(inside(V, P), -d, d) - r


def dense_poses(V, pins, r, n_theta=48, n_xy=7, iterations=40):
    """Poses touching all three pins found from a grid of start poses (the pins' centroid
    plus offsets within the part's reach, every n_theta-th of a turn): converged
    (|gap| <= 1e-11 m), no pin inside the part; with the smallest singular value ratio
    of the finite-difference Jacobian (x, y, L theta)."""
    V = np.asarray(V, float)
    L = np.max(np.linalg.norm(V - V.mean(0), axis=1))
    centre = pins.mean(0) - V.mean(0)
    th = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
    off = np.linspace(-1.5 * L, 1.5 * L, n_xy)
    T, X, Y = np.meshgrid(th, off, off, indexing="ij")
    q = np.stack([centre[0] + X.ravel(), centre[1] + Y.ravel(), T.ravel()], axis=1)
    # a start at theta places the part's centre about the pins' centroid turned
    c, s = np.cos(q[:, 2]), np.sin(q[:, 2])
    m = V.mean(0)
    q[:, 0] += m[0] - (c * m[0] - s * m[1])
    q[:, 1] += m[1] - (s * m[0] + c * m[1])

    def res(q):
        P = to_part(q, pins)
        return boundary_distance(V, P) - r

    h = 1e-8
    for _ in range(iterations):
        r0 = res(q)
        J = np.empty((len(q), 3, 3))
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = h if j < 2 else h / L
            J[:, :, j] = (res(q + dq) - r0) / h
        JT = J.transpose(0, 2, 1)
        A = JT @ J + 1e-12 * np.eye(3)  # Levenberg-damped normal equations
        step = np.linalg.solve(A, -(JT @ r0[..., None]))[..., 0]
        step[:, 2] /= L
        norm = np.abs(step[:, :2]).max(1) + L * np.abs(step[:, 2])
        scale = np.minimum(1.0, 0.2 * L / np.maximum(norm, 1e-300))
        q = q + step * scale[:, None]
    r0 = res(q)
    ok = np.all(np.abs(r0) <= 1e-11, axis=1)
    ok &= np.all(gaps(V, q, pins, r) >= -1e-9, axis=1)
    q = q[ok]
    cond = []
    for qk in q:
        J = np.empty((3, 3))
        for j in range(3):
            dq = np.zeros(3)
            dq[j] = 1e-7 if j < 2 else 1e-7 / L
            J[:, j] = (res((qk + dq)[None])[0] - res((qk - dq)[None])[0]) / 2e-7
        sv = np.linalg.svd(J, compute_uv=False)
        cond.append(sv[-1] / sv[0])
    q[:, 2] = np.arctan2(np.sin(q[:, 2]), np.cos(q[:, 2]))
    return q, np.array(cond)
