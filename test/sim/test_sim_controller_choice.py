# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller's choice of a direction among the node's intervals (no ROS
traffic: the pure functions of wrenchcone_ros.sim.tilt_controller)."""

import math

import pytest

pytest.importorskip("rclpy")

from wrenchcone_ros.sim.tilt_controller import (  # noqa: E402
    angular_distance,
    choose_direction,
    inside,
)

D = math.radians


@pytest.mark.parametrize("phi, lo, hi, expected", [
    (D(-58.5), D(-68.2), D(0.0), True), (D(-70.0), D(-68.2), D(0.0), False),
    (D(179.0), D(170.0), D(-170.0), True),  # an interval across +-180 degrees
    (D(-179.0), D(170.0), D(-170.0), True), (D(0.0), D(170.0), D(-170.0), False),
    (D(10.0), D(10.0), D(10.0), True)])  # a single direction
def test_inside_an_interval_counter_clockwise_from_lo_to_hi(phi, lo, hi, expected):
    assert inside(phi, lo, hi) is expected


def test_the_plans_direction_is_kept_when_the_node_allows_it():
    assert choose_direction(D(-58.5), [D(-68.2)], [D(0.0)], [D(-30.0)]) == (D(-58.5), True)


def test_else_the_best_of_the_nearest_interval():
    lo, hi, best = [D(-68.2), D(100.0)], [D(-62.0), D(120.0)], [D(-65.0), D(110.0)]
    assert choose_direction(D(-58.5), lo, hi, best) == (D(-65.0), False)
    assert choose_direction(D(130.0), lo, hi, best) == (D(110.0), False)
    assert angular_distance(D(179.0), D(-179.0)) == pytest.approx(D(2.0))
