# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Each row as the geometry has it: a pin in a concave corner carries both of its
contacts (location, accuracy and hold use them, the label lists them); one row per
physical placement (no two rows with the same pins and pose, theta = +-180 deg one
angle); a placement whose normals are parallel in exact arithmetic is never located."""

import math

import numpy as np
import pytest

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.design import design_fixtures
from wrenchcone_ros.design.enumerate import enumerate_placements
from wrenchcone_ros.design.problem import DESIGN_POSE_TOLERANCE_M, DesignProblem, load_plate

PAWL = "examples/pawl_seating.yaml"
CORNER_PLATE = {"pitch": 0.01, "extent": [9, 6], "pin_radius": 0.003,
                "fixed_pins": [[2, 2], [5, 2], [6, 2]]}
WRAP_PLATE = {"pitch": 0.01, "extent": [12, 12], "pin_radius": 0.003,
              "fixed_pins": [[0, 2], [4, 0], [4, 2]]}


def _problem(plate, vertices=None):
    scene = load_scene(PAWL)
    if vertices is not None:
        d = scene.to_dict()
        d["workpiece"]["shape"] = {"type": "polygon", "vertices": vertices}
        d["workpiece"]["com"] = list(np.mean(np.asarray(vertices), axis=0))
        scene = load_scene(d)
    return DesignProblem(scene, load_plate(plate))


def _at(rows, x, y, theta):
    return [r for r in rows if math.hypot(r.pose[0] - x, r.pose[1] - y) < 1e-9
            and abs(math.remainder(r.pose[2] - theta, 2 * math.pi)) < 1e-9]


def test_a_pin_in_a_concave_corner_carries_both_contacts():
    rows = list(enumerate_placements(_problem(CORNER_PLATE)))
    (row,) = _at(rows, 0.002, 0.007, 0.0)
    # pin 1 at (0.02, 0.02) sits in the foot's inner corner: edges 2 and 3
    assert row.features[0] == "e2+e3", row.features
    assert row.located and math.isfinite(row.accuracy)


def test_a_pin_at_an_edge_end_lists_the_edge_and_the_vertex():
    rows = list(enumerate_placements(_problem(CORNER_PLATE)))
    (row,) = _at(rows, 0.0, 0.007, 0.0)
    # pin 3 at (0.06, 0.02) sits right above the foot's corner (vertex 2), on edge 2's end
    assert row.features == ("e2", "e2", "e2+v2"), row.features
    assert not row.located and row.accuracy == math.inf  # three parallel normals


def test_the_corner_design_reaches_the_hold_with_both_contacts():
    res = design_fixtures(PAWL, CORNER_PLATE, (0.2, 0.4), workers=0, plans=0, runs=0)
    (row,) = [r for r in res.rows if math.hypot(r["x"] - 0.002, r["y"] - 0.007) < 1e-9
              and abs(r["theta"]) < 1e-9]
    assert row["located"] and row["stage"] == "hold", row
    assert row["hold_margin"] is not None and row["hold_margin"] > 0


def _same_placement(a, b, L):
    return (a.holes == b.holes
            and math.hypot(a.pose[0] - b.pose[0], a.pose[1] - b.pose[1])
            <= DESIGN_POSE_TOLERANCE_M
            and abs(math.remainder(a.pose[2] - b.pose[2], 2 * math.pi)) * L
            <= DESIGN_POSE_TOLERANCE_M)


@pytest.mark.parametrize("plate", [CORNER_PLATE, WRAP_PLATE], ids=["corner", "wrap"])
def test_no_two_rows_describe_the_same_pins_and_pose(plate):
    pr = _problem(plate)
    rows = list(enumerate_placements(pr))
    L = pr.part.length_scale
    assert rows
    for i, a in enumerate(rows):
        assert -math.pi < a.pose[2] <= math.pi
        for b in rows[i + 1:]:
            assert not _same_placement(a, b, L), (a.design_id, b.design_id)


def test_a_pin_at_an_edge_end_never_passes_the_rank_test_through_round_off():
    # two pins under edge 0 of a rectangle, the third under its end (vertex 1), its
    # centre 2 um past the end: within the contact tolerance of both the edge's line and
    # the vertex (gap 7e-10 m), so the three normals are parallel. The vertex's normal
    # computed from the centre is turned by 2e-6 / r = 7e-4 rad: enough for a rank test
    # relative to round-off to call it located, with an accuracy of thousands of m/m.
    from wrenchcone_ros.design.geometry import (
        Features,
        contact_jacobian,
        locating_accuracy,
        pin_gaps,
    )
    r, u = 0.003, 2e-6
    rect = [[0.0, 0.0], [0.03, 0.0], [0.03, 0.02], [0.0, 0.02]]
    F = Features.of(rect, r)
    pins = np.array([[0.005, -r], [0.015, -r], [0.03 + u, -r]])
    pose = (0.0, 0.0, 0.0)
    g, feats = pin_gaps(F.vertices, np.zeros((1, 3)), pins[None], r)
    assert np.all(np.abs(g) <= 1e-9)
    N = contact_jacobian(rect, (0.015, 0.01), pose, pins, feats[0], r, 0.018)
    assert locating_accuracy(N) == (False, math.inf)
    from wrenchcone_ros.design.geometry import locate, pin_contacts
    contacts = [pin_contacts(F, pose, c, 1e-9) for c in pins]
    assert [[ct.label for ct in cs] for cs in contacts] == [["e0"], ["e0"], ["e0+v1"]]
    assert locate(F, [ct for cs in contacts for ct in cs], (0.015, 0.01), 0.018) == (
        False, math.inf)


@pytest.mark.parametrize("turn", [0.0, 0.3, 2.0])
def test_normals_parallel_in_exact_arithmetic_are_never_located(turn):
    # a rectangle turned by `turn` (no edge on an axis unless 0): three pins on its two
    # long sides, whatever the rounding of the turned coordinates
    from wrenchcone_ros.design.geometry import Features, locate, pin_contacts
    r = 0.003
    c, s = math.cos(turn), math.sin(turn)
    rect = np.array([[0.0, 0.0], [0.03, 0.0], [0.03, 0.02], [0.0, 0.02]]) @ [[c, s], [-s, c]]
    F = Features.of(rect, r)
    local = np.array([[0.005, -r], [0.02, -r], [0.01, 0.02 + r]])
    pins = local @ [[c, s], [-s, c]]
    com = np.array([0.015, 0.01]) @ [[c, s], [-s, c]]
    contacts = [ct for p in pins for ct in pin_contacts(F, (0.0, 0.0, 0.0), p, 1e-9)]
    assert sorted(ct.label for ct in contacts) == ["e0", "e0", "e2"]
    assert locate(F, contacts, com, 0.018) == (False, math.inf)


def test_hold_pieces_that_meet_across_180_degrees_are_one_interval():
    from wrenchcone_ros.core.directions import DirectionInterval
    from wrenchcone_ros.design.stages import merge_wrapped
    a = DirectionInterval(2.5, math.pi, 3.0, 0.2)
    b = DirectionInterval(-math.pi, -2.0, -2.5, 0.4)
    c = DirectionInterval(0.0, 1.0, 0.5, 0.1)
    out = merge_wrapped([c, a, b])
    assert len(out) == 2
    (m,) = [v for v in out if v.lo == 2.5]
    assert m.hi == pytest.approx(2 * math.pi - 2.0) and m.margin == 0.4
    assert m.best == pytest.approx(-2.5 + 2 * math.pi)


def test_the_plate_area_test_allows_the_pose_tolerance_and_no_more():
    # a 30 x 20 mm rectangle whose left side lies eps to the left of the usable area at
    # the first translation: within the pose tolerance it fits there, beyond it not
    from wrenchcone_ros.design.enumerate import Enumerator
    TOL = DESIGN_POSE_TOLERANCE_M
    rect = [[0.0, 0.0], [0.03, 0.0], [0.03, 0.02], [0.0, 0.02]]
    en = Enumerator(_problem({"pitch": 0.01, "extent": [6, 5], "pin_radius": 0.003}, rect))
    triple = ((1, 0), (2, 0))

    def count(eps):
        return en.fit(triple, (-0.005 - eps, -0.005, 0.0))[0]
    inside = count(0.0)
    assert inside > 0
    assert count(1e-12) == count(1e-10) == count(0.5 * TOL) == inside
    assert count(2 * TOL) < inside
