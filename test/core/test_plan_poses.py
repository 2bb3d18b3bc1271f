# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Poses near contact (core/plan/poses.py) against plane geometry worked by hand: a disc
of radius R touches a pin of radius r at p exactly when its centre is R + r from p, so
the poses touching two pins are the intersections of two circles, and a disc lifted by h
off a pin is R + r + h from it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrenchcone_ros.core.plan import lifted_scene, project_pose, solve_pose
from wrenchcone_ros.core.scene_yaml import scene_from_dict

R = 0.05  # m, the disc's radius
PINS = [(-0.04, -0.05), (0.06, -0.03), (0.0, 0.2)]  # m; the third far away
RHO = [0.004, 0.002, 0.003]  # m, pin radii


def disc(pose=(0.0, 0.0, 0.0)):
    return scene_from_dict({
        "workpiece": {"mass": 0.1, "inertia": 1e-4, "shape": {"type": "disc", "radius": R},
                      "pose": list(pose)},
        "friction": 0.3,
        "fixels": [{"position": list(p), "radius": r} for p, r in zip(PINS, RHO)]})


def circle_intersections(c0, r0, c1, r1):
    """The two points at distance r0 from c0 and r1 from c1 (plane geometry)."""
    c0, c1 = np.asarray(c0, float), np.asarray(c1, float)
    d = float(np.hypot(*(c1 - c0)))
    a = (r0 ** 2 - r1 ** 2 + d ** 2) / (2 * d)
    h = math.sqrt(r0 ** 2 - a ** 2)
    m = c0 + a * (c1 - c0) / d
    perp = np.array([-(c1 - c0)[1], (c1 - c0)[0]]) / d
    return m + h * perp, m - h * perp


def test_a_pose_onto_two_pins_is_the_nearer_intersection_of_two_circles():
    start = (0.003, 0.004, 0.3)
    pose = project_pose(disc(), start, [0, 1])
    assert pose is not None
    candidates = circle_intersections(PINS[0], R + RHO[0], PINS[1], R + RHO[1])
    nearest = min(candidates, key=lambda q: np.hypot(*(q - start[:2])))
    tol = 1e-9 * 100  # the scene's contact tolerance, with margin for the iteration
    assert np.hypot(*(np.array(pose[:2]) - nearest)) <= tol
    for p, r in zip(PINS[:2], RHO[:2]):
        assert abs(math.hypot(pose[0] - p[0], pose[1] - p[1]) - (R + r)) <= tol


def test_a_gap_goal_is_met_and_the_disc_turns_freely():
    """A disc's gaps do not depend on its angle: the solve may keep theta anywhere, the
    centre is R + r + goal from the pin."""
    goal = 0.002
    pose = solve_pose(disc(), (0.0, 0.01, 0.0), [0], [goal], slack=0.01)
    assert pose is not None
    assert math.hypot(pose[0] - PINS[0][0], pose[1] - PINS[0][1]) == \
        pytest.approx(R + RHO[0] + goal, abs=1e-9)


def test_no_fixels_leaves_the_pose_and_three_pins_a_disc_cannot_touch_give_none():
    assert solve_pose(disc(), (0.01, 0.02, 0.5), [], [], slack=0.01) == (0.01, 0.02, 0.5)
    # the third pin is 0.25 m from the others: no disc of radius 0.05 touches all three
    assert project_pose(disc(), (0.0, 0.0, 0.0), [0, 1, 2]) is None


def test_lifted_scene_lifts_off_one_pin_and_keeps_the_other():
    touching = disc(tuple(project_pose(disc(), (0.0, 0.0, 0.0), [0, 1])))
    assert touching.in_contact[0] and touching.in_contact[1]
    lift = 0.001
    lifted = lifted_scene(touching, missing=1, keep=[0], lift=lift)
    assert lifted is not None
    x, y, _ = lifted.pose
    assert math.hypot(x - PINS[0][0], y - PINS[0][1]) == pytest.approx(R + RHO[0], abs=1e-8)
    assert math.hypot(x - PINS[1][0], y - PINS[1][1]) == \
        pytest.approx(R + RHO[1] + lift, abs=1e-8)
    assert lifted.in_contact[0] and not lifted.in_contact[1]
