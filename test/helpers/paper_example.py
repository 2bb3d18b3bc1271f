# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The paper's worked example as data: the generators G of its disc in mode "na" (the
paper's Eq. 5), and equality of sets of rays up to positive scaling."""

import numpy as np

PAPER_G = [(1.0, 0.0, -1.0), (-0.2, -1.0, -0.2), (0.2, -1.0, 0.2)]


def same_rays(a, b, tol=1e-9):
    """Equal sets of rays up to positive scaling and order."""
    ua = sorted(tuple(np.round(r / np.linalg.norm(r), 9)) for r in np.asarray(a, float))
    ub = sorted(tuple(np.round(r / np.linalg.norm(r), 9)) for r in np.asarray(b, float))
    return len(ua) == len(ub) and np.allclose(ua, ub, atol=tol)
