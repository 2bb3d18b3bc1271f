# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Location: the locating accuracy of the contact Jacobian against finite differences of
the closed-form pose solve, and the rank test on placements whose normals are concurrent
(an equilateral triangle touched at its edge midpoints) or parallel."""

import math

import numpy as np
import pytest

from wrenchcone_ros.design.geometry import (
    Features,
    contact_jacobian,
    locating_accuracy,
    pin_gaps,
    solve_poses,
)

PAWL = [[0.0, 0.0], [0.06, 0.0], [0.06, 0.01], [0.015, 0.01], [0.015, 0.035], [0.0, 0.035]]
COM = (0.02, 0.012)
R = 0.003


def _solve(F, pins, codes, L, near):
    poses, _ = solve_poses(F, pins, np.array([codes]), L)
    g, f = pin_gaps(F.vertices, poses, np.broadcast_to(pins, (len(poses), 3, 2)), F.r)
    poses = poses[np.all(np.abs(g) <= 1e-9, axis=1)]
    k = np.argmin(np.linalg.norm(poses[:, :2] - near[:2], axis=1)
                  + np.abs(np.remainder(poses[:, 2] - near[2] + np.pi, 2 * np.pi) - np.pi))
    return poses[k]


def _com_pose(q, L):
    c, s = math.cos(q[2]), math.sin(q[2])
    return np.array([q[0] + c * COM[0] - s * COM[1], q[1] + s * COM[0] + c * COM[1],
                     L * q[2]])


@pytest.mark.parametrize("pins,codes", [
    # two pins under the foot (edge 0), one against the foot's right end (edge 1)
    (np.array([[0.01, -0.003], [0.05, -0.003], [0.063, 0.004]]), (0, 0, 1)),
    # a pin at the heel's corner (vertex 0), one under the foot, one at the back
    (np.array([[-0.002, -0.0025], [0.04, -0.003], [-0.003, 0.02]]), (6, 0, 5)),
])
def test_locating_accuracy_matches_finite_differences_of_the_pose_solve(pins, codes):
    F = Features.of(PAWL, R)
    L = max(math.hypot(x - COM[0], y - COM[1]) for x, y in PAWL)
    q0 = _solve(F, pins, codes, L, np.array([0.0, 0.0, 0.0]))
    _g, feats = pin_gaps(F.vertices, q0[None], pins[None], R)
    N = contact_jacobian(PAWL, COM, q0, pins, feats[0], R, L)
    located, acc = locating_accuracy(N)
    assert located
    eps = 1e-7
    D = np.zeros((3, 6))
    for k in range(3):
        for a in range(2):
            dp = np.zeros_like(pins)
            dp[k, a] = eps
            qp = _solve(F, pins + dp, codes, L, q0)
            qm = _solve(F, pins - dp, codes, L, q0)
            D[:, 2 * k + a] = (_com_pose(qp, L) - _com_pose(qm, L)) / (2 * eps)
    fd = np.linalg.svd(D, compute_uv=False)[0]
    assert fd == pytest.approx(acc, rel=1e-5)


def test_concurrent_normals_are_not_located():
    # an equilateral triangle touched by three pins at its edge midpoints: the three
    # normals meet at the centre, the part turns about it to first order
    h = math.sqrt(3) / 2 * 0.04
    tri = [[0.0, 0.0], [0.04, 0.0], [0.02, h]]
    F = Features.of(tri, R)
    V = np.array(tri)
    pins = []
    for k in range(3):
        a, b = V[k], V[(k + 1) % 3]
        pins.append((a + b) / 2 + R * F.normal[k])
    pins = np.array(pins)
    g, feats = pin_gaps(V, np.zeros((1, 3)), pins[None], R)
    assert np.all(np.abs(g) <= 1e-12)
    N = contact_jacobian(tri, (0.02, h / 3), (0.0, 0.0, 0.0), pins, feats[0], R, 0.03)
    assert locating_accuracy(N) == (False, math.inf)
    # moved off the midpoints, the normals no longer meet: located
    pins2 = pins.copy()
    pins2[0, 0] += 0.005
    g2, feats2 = pin_gaps(V, np.zeros((1, 3)), pins2[None], R)
    N2 = contact_jacobian(tri, (0.02, h / 3), (0.0, 0.0, 0.0), pins2, feats2[0], R, 0.03)
    assert locating_accuracy(N2)[0]
