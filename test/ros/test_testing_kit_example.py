# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A toy tray-tilt controller and its tests, against the real wrenchcone node.

The controller tilts a tray so that gravity pushes the part in a wanted contact mode. It
asks the node which pull directions give that mode and no other (force_directions,
exclusive), takes the most robust one, and checks the resulting gravity force with
check_wrench before it would command the tilt.
"""

import math
from dataclasses import dataclass
from pathlib import Path

import pytest
from wrenchcone_msgs.msg import Status

from wrenchcone_ros.core import load_scene

SCENE = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
STANDARD_GRAVITY = 9.80665  # m/s^2
TILT = math.radians(10.0)  # rad: how far the controller tilts the tray


@dataclass(frozen=True)
class Tilt:
    downhill: float  # rad, fixture frame: the tray's direction of steepest descent
    angle: float  # rad: how far the tray is tilted
    force: tuple[float, float]  # N, fixture frame: gravity's pull in the tray plane


class ToyTrayController:
    def __init__(self, client, mass, angle=TILT):
        self.client = client  # a wrenchcone_ros.ros.client.WrenchConeClient
        self.mass = mass  # kg
        self.angle = angle  # rad

    def plan_tilt(self, mode):
        """The tilt that gives ``mode`` and no other mode, or None."""
        d = self.client.force_directions(mode, exclusive=True)
        if d.status != Status.OK or not d.intervals:
            return None
        best = max(d.intervals, key=lambda iv: iv.margin).best  # the most robust
        pull = self.mass * STANDARD_GRAVITY * math.sin(self.angle)
        force = (pull * math.cos(best), pull * math.sin(best))
        reply = self.client.check_wrench(mode, (*force, 0.0), classify=True)
        if reply.status != Status.OK or not (reply.consistent and reply.only_mode):
            return None
        return Tilt(best, self.angle, force)


@pytest.fixture
def wrenchcone_scene():
    return SCENE  # the node loads it as its scene_file


@pytest.fixture
def wrenchcone_parameters():
    # never stale: a loaded CI machine may take more than the default second between
    # publishing a pose and asking
    return {"input_timeout": 0.0}


@pytest.fixture
def controller(wrenchcone_client):
    return ToyTrayController(wrenchcone_client, mass=load_scene(SCENE).workpiece.mass)


def test_slides_the_pawl_right_to_its_stop(controller):
    tilt = controller.plan_tilt("arr")  # fixel 1 approached, sliding right on 2 and 3
    assert tilt is not None
    # Coulomb: the pins push up and left on the edge of their friction cones, so the
    # pull points right of straight down by more than the friction angle, and not up
    mu = load_scene(SCENE).friction
    assert -math.atan2(1.0, mu) < tilt.downhill <= 0.0
    assert math.hypot(*tilt.force) == pytest.approx(0.05 * STANDARD_GRAVITY * math.sin(TILT))  # 50 g


def test_no_tilt_for_a_mode_the_contacts_do_not_allow(controller):
    assert controller.plan_tilt("nss") is None  # fixel 1 is 8 mm away: it cannot roll


def test_follows_the_part_when_it_moves(controller, wrenchcone_inputs, wrenchcone_client):
    pose = wrenchcone_inputs.publish_pose(0.096, 0.205, 0.0)  # lifted 5 mm off the pins
    wrenchcone_inputs.wait_until_used(wrenchcone_client, pose)
    assert controller.plan_tilt("arr") is None  # nothing to slide on
