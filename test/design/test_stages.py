# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A design's loading plan, executed again in pymunk for models the Monte Carlo did not
draw (the corners of the friction box), seats the part as the design's row says; the
loading start is free of the pins and the direction of arrival frees the seat."""

import itertools
import math

import pytest

from wrenchcone_ros.core import Uncertainty, load_scene
from wrenchcone_ros.core.plan import plan_seating, run_models
from wrenchcone_ros.design.problem import DesignProblem, load_plate
from wrenchcone_ros.design.stages import design_scene, hold, loading_direction, plan

pytest.importorskip("pymunk")

# design 2 of docs/fixture_design.md: two pins under the foot, the third at its end
POSITIONS = [(0.01, 0.0), (0.05, 0.0), (0.07, 0.01)]
POSE = (0.007, 0.003, 0.0)


@pytest.fixture(scope="module")
def problem():
    return DesignProblem(load_scene("examples/pawl_seating.yaml"),
                         load_plate("examples/plates/plate_pawl.yaml"),
                         Uncertainty(friction=(0.2, 0.4)))


@pytest.mark.slow
def test_the_plan_seats_the_part_at_the_friction_box_corners(problem):
    row = plan(problem, POSITIONS, POSE, runs=4, seed=3)
    assert row["plan_guaranteed"] and row["success_rate"] == 1.0
    scene = design_scene(problem, POSITIONS, POSE)
    phi = row["load_direction"]
    assert phi == loading_direction(scene, row["funnel_tilt"])
    off = problem.start_offset
    start = scene.with_pose(POSE[0] - off * math.cos(phi), POSE[1] - off * math.sin(phi), 0.0)
    assert not any(start.in_contact) and min(start.gaps) > 0
    p = plan_seating(start, [1, 2, 3], "tilt", (0.2, 0.4), runs=0)
    assert ";".join(s.mode for s in p.segments) == row["plan_modes"]
    corners = list(itertools.product((0.2, 0.4), repeat=3))
    runs = run_models(start, p, corners, workers=1)
    assert all(r.success for r in runs), [(r.friction, r.reason) for r in runs]


def test_a_spring_actuator_gives_its_own_hold_interval(problem):
    """The hold under a spring hooked at the top of the pawl's upright differs from the
    tray tilt's (the pull acts at another point), and a hook at the com gives the
    tilt's interval."""
    from dataclasses import replace

    tilt = hold(problem, POSITIONS, POSE)
    spring = hold(replace(problem, actuator="spring:0.0075,0.035"), POSITIONS, POSE)
    at_com = hold(replace(problem, actuator="spring:0.02,0.012"), POSITIONS, POSE)
    assert (spring["hold_lo"], spring["hold_hi"]) != (tilt["hold_lo"], tilt["hold_hi"])
    assert at_com["hold_lo"] == pytest.approx(tilt["hold_lo"], abs=1e-9)
    assert at_com["hold_hi"] == pytest.approx(tilt["hold_hi"], abs=1e-9)
