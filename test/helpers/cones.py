# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Equality of two cones as sets (not as arrays): the same feasibility, the same face and
generator rows up to order, the same spans of equalities and lines."""

import numpy as np

from wrenchcone_ros.core.cones import _sorted_rows


def _projector(B: np.ndarray) -> np.ndarray:
    return B.T @ B if B.shape[0] else np.zeros((3, 3))


def assert_same_cone(a, b, tol: float = 1e-9) -> None:
    """Same feasibility, same F and rays (as sets of unit rows), same spans of E and lines;
    for infeasible modes the same closure."""
    assert a.mode == b.mode and a.feasible == b.feasible
    pairs = [(a, b)] + ([(a.closure, b.closure)] if not a.feasible else [])
    for x, y in pairs:
        for f in ("F_hat", "G_hat"):
            p, q = _sorted_rows(getattr(x, f)), _sorted_rows(getattr(y, f))
            assert p.shape == q.shape, (x.mode, f, p, q)
            if p.size:
                assert np.abs(p - q).max() <= tol, (x.mode, f, p, q)
        for f in ("E_hat", "L_hat"):
            p, q = getattr(x, f), getattr(y, f)
            assert p.shape == q.shape, (x.mode, f)
            assert np.abs(_projector(p) - _projector(q)).max() <= tol, (x.mode, f)
