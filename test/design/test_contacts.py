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
from wrenchcone_ros.design import problem as design_problem
from wrenchcone_ros.design.problem import DesignProblem, load_plate

DESIGN_POSE_TOLERANCE_M = getattr(design_problem, "DESIGN_POSE_TOLERANCE_M", 1e-6)

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
