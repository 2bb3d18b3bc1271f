# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Cone.contains() and Cone.margin() (closed form) against an independent reference on
every kind of cone: membership from the face rows, the distance outside from a
non-negative least-squares projection onto the generators (Cone.distance)."""

from __future__ import annotations

import numpy as np
import pytest

from wrenchcone_ros.core import enumerate_modes, load_scene, wrench_cone
from wrenchcone_ros.core.cones import cone_from_vrep

RNG = np.random.default_rng(7)
WRENCHES = np.vstack([RNG.normal(size=(300, 3)), np.eye(3), -np.eye(3), np.zeros((1, 3))])

SCENES = {
    "paper": "examples/paper_disc.yaml",
    "pawl": "examples/pawl_polygon.yaml",
    "square_mu0": {
        "workpiece": {"mass": 2.0, "inertia": 0.3, "com": [0.1, 0.0],
                      "shape": {"type": "polygon",
                                "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}},
        "friction": 0.0,
        "fixels": [[-0.5, -1.0], [0.5, -1.0], [1.0, 0.3], [-1.5, 0.5]],
    },
    "pinned_disc": {
        "workpiece": {"mass": 1.0, "inertia": 1.0, "shape": {"type": "disc", "radius": 1.0}},
        "friction": 0.2, "fixels": [[0.0, -1.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.5]],
    },
}


def scene_cones():
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    for name, src in SCENES.items():
        scene = load_scene(root / src if isinstance(src, str) else src)
        for mode in enumerate_modes(scene.in_contact):
            yield f"{name}:{mode}", wrench_cone(scene, mode)


def synthetic_cones():
    shapes = {
        "R3": ([], np.eye(3)),
        "zero": ([], []),
        "half_space": ([[0, 0, 1]], [[1, 0, 0], [0, 1, 0]]),
        "wedge": ([[1, 0, 0], [0, 1, 0]], [[0, 0, 1]]),
        "plane": ([], [[1, 0, 0], [0, 1, 0]]),
        "half_plane": ([[0, 1, 0]], [[1, 0, 0]]),
        "sector": ([[1, 0, 0], [1, 1, 0]], []),
        "ray": ([[1, 2, 3]], []),
        "line": ([], [[1, -1, 0.5]]),
        "pointed": ([[1, 0, 1], [0, 1, 1], [-1, -1, 1]], []),
        "thin": ([[1, 0, 1], [1, 1e-6, 1], [1, 0, 1 + 1e-6]], []),
    }
    for name, (rays, lines) in shapes.items():
        for L in (1.0, 0.01):
            yield f"{name}:L={L}", cone_from_vrep(rays, lines, mode="x", length_scale=L,
                                                  method="test", exact=False)


CONES = list(scene_cones()) + list(synthetic_cones())


def reference(cone, g):
    """(contains, margin) from the definitions, with NNLS for the distance outside."""
    if not cone.feasible:
        return False, -1.0
    gh = np.asarray(g, float) * [1.0, 1.0, 1.0 / cone.length_scale]
    n = np.linalg.norm(gh)
    if n == 0:
        return True, 0.0
    u = gh / n
    F, E = cone.F_hat, cone.E_hat
    contains = bool(np.all(F @ u <= 1e-9) and np.all(np.abs(E @ u) <= 1e-9))
    if F.shape[0] == 0 and E.shape[0] == 0:
        return True, 1.0
    if (F.shape[0] == 0 or np.max(F @ u) <= 0) and (E.shape[0] == 0 or np.max(np.abs(E @ u)) == 0):
        return contains, 0.0 if E.shape[0] else float(np.min(-(F @ u)))
    return contains, -cone.distance(u)


@pytest.mark.slow
@pytest.mark.parametrize("name,cone", CONES, ids=[c[0] for c in CONES])
def test_margin_and_contains_equal_the_reference(name, cone):
    for g in WRENCHES:
        contains, margin = cone.check(g)
        want_c, want_m = reference(cone, g)
        assert margin == pytest.approx(want_m, abs=1e-9), (name, g)
        assert contains == want_c, (name, g)
        assert cone.margin(g) == margin and cone.contains(g) == contains


def test_cone_kinds_are_covered():
    kinds = {(c.feasible, c.F.shape[0] > 0, c.equalities.shape[0] > 0,
              c.lineality.shape[0] > 0) for _, c in CONES}
    assert len(kinds) >= 6
