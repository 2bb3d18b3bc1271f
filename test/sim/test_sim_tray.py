# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The simulated tray without ROS (wrenchcone_ros.sim.tray): bad commands and reset poses
are refused with one clear message; the letters it reads agree with the cones at rest;
its poses are the engine's for the same inputs."""

import math
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

from wrenchcone_ros.core import consistent_modes, load_scene  # noqa: E402
from wrenchcone_ros.core.tilt import STANDARD_GRAVITY  # noqa: E402
from wrenchcone_ros.core.simulate import (  # noqa: E402
    DEFAULT_TILT,
    Actuator,
    Simulation,
    simulate,
)
from wrenchcone_ros.sim.tray import (  # noqa: E402
    MAX_TILT_ACCELERATION,
    CommandError,
    TrayPhysics,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PAWL = EXAMPLES / "pawl_seating.yaml"
A10 = STANDARD_GRAVITY * math.sin(DEFAULT_TILT)  # m/s^2: a tray tilted by 10 degrees


@pytest.mark.parametrize("direction, magnitude, words", [
    (math.nan, 1.0, "finite"), (0.0, math.inf, "finite"), (0.0, -1.0, "outside"),
    (0.0, 1e6, "outside"), (0.0, MAX_TILT_ACCELERATION * 1.001, "outside")])
def test_a_bad_tilt_command_is_refused_and_the_previous_one_kept(direction, magnitude, words):
    tray = TrayPhysics(load_scene(PAWL))
    tray.set_command(-1.0, A10)
    with pytest.raises(CommandError, match=words) as info:
        tray.set_command(direction, magnitude)
    assert "\n" not in str(info.value) and "m/s^2" in str(info.value)
    assert (tray.command.direction, tray.command.magnitude) == (-1.0, A10)
    tray.advance(0.01)  # and the engine goes on
    assert all(math.isfinite(v) for v in tray.readout().pose)


@pytest.mark.parametrize("pose, words", [
    ((0.096, 0.195, 0.0), "penetrates"),  # the foot 5 mm into pins 2 and 3
    ((math.nan, 0.2, 0.0), "finite"), ((0.1, 0.2), "three")])
def test_a_bad_reset_pose_is_refused(pose, words):
    tray = TrayPhysics(load_scene(PAWL))
    before = tray.readout().pose
    with pytest.raises(CommandError, match=words):
        tray.reset(pose)
    assert tray.readout().pose == before


def test_sampling_without_an_uncertainty_is_refused_and_the_nominal_model_is_not():
    tray = TrayPhysics(load_scene(PAWL))
    with pytest.raises(CommandError, match="no uncertainty"):
        tray.sample(1)
    assert tray.sample(0, nominal=True).friction == (0.3, 0.3, 0.3)


@pytest.mark.parametrize("degrees", [-60.0, -30.0, -90.0, -110.0, 50.0, 130.0])
def test_the_letters_at_rest_agree_with_the_cones(degrees):
    """The tray's letters just after a command from rest are the one mode the cones give
    the tray's pull (a pull with exactly one consistent mode, margin >= 0.05)."""
    scene = load_scene(PAWL)
    phi = math.radians(degrees)
    m = scene.workpiece.mass
    modes = consistent_modes(scene, (m * A10 * math.cos(phi), m * A10 * math.sin(phi), 0.0))
    assert len(modes) == 1 and modes[0].margin >= 0.05
    tray = TrayPhysics(scene)
    tray.set_command(phi, A10)
    tray.advance(0.05 * tray.sim.sp.time_scale)
    assert tray.readout().letters == modes[0].mode


def test_the_poses_are_the_engines_for_the_same_inputs():
    """The tray under a constant command follows core.simulate's trajectory for the same
    scene, direction and pull."""
    scene = load_scene(PAWL)
    phi = math.radians(-58.5)
    tray = TrayPhysics(scene)
    tray.set_command(phi, A10)
    ref = simulate(scene, phi, duration=1.0 * 0.2)
    tray.advance(ref.frames[-1].t)
    assert tray.readout().pose == pytest.approx(ref.frames[-1].pose, abs=1e-12)
    assert ref.frames[-1].pose[0] > scene.pose[0] + 1e-3  # it really moved (right)


def test_a_reset_puts_the_part_back_at_rest_and_keeps_the_clock_running():
    tray = TrayPhysics(load_scene(PAWL))
    tray.set_command(math.radians(-58.5), A10)
    tray.advance(0.2)
    t = tray.clock
    tray.reset(None)
    assert tray.readout().pose == pytest.approx(load_scene(PAWL).pose)
    assert tray.command.magnitude == 0.0 and tray.clock == pytest.approx(t)
    tray.advance(0.1)
    assert tray.readout().pose == pytest.approx(load_scene(PAWL).pose, abs=1e-9)


def test_with_a_spring_the_poses_are_the_engines_for_the_same_spring():
    """A tray whose actuator is a spring hooked off the centre of mass: under a constant
    command it follows core.simulate's trajectory for that spring and direction (the
    spring's own force scaled to the command's m a), and the hook's torque turns the
    part, which a pull at the com does not."""
    scene = load_scene(PAWL)
    phi = math.radians(-58.5)
    spring = Actuator.parse("spring:0.01,0.005")
    tray = TrayPhysics(scene, actuator=spring)
    full = spring.force_magnitude(scene) / scene.workpiece.mass  # m/s^2 of the full force
    tray.set_command(phi, full)
    ref = simulate(scene, phi, actuator=spring, duration=0.1)
    tray.advance(ref.frames[-1].t)
    assert tray.readout().pose == pytest.approx(ref.frames[-1].pose, abs=1e-12)
    tilt = TrayPhysics(scene)
    tilt.set_command(phi, full)
    tilt.advance(ref.frames[-1].t)
    turned = abs(tray.readout().pose[2] - scene.pose[2])
    assert turned > 10 * abs(tilt.readout().pose[2] - scene.pose[2]) + 1e-6


def test_a_spring_command_is_its_force_in_units_of_the_mass():
    """Half the spring's force (a command of half its m/s^2) moves the part as the
    engine's spring at scale 0.5."""
    scene = load_scene(PAWL)
    spring = Actuator.parse("spring:0.01,0.005")
    tray = TrayPhysics(scene, actuator=spring)
    tray.set_command(-1.0, 0.5 * spring.force_magnitude(scene) / scene.workpiece.mass)
    sim = Simulation(scene, spring, -1.0)
    sim.set_direction(-1.0, 0.5)
    for _ in range(200):
        sim.step()
    tray.advance(200 * sim.dt)
    assert tray.readout().pose == pytest.approx(sim.pose, abs=1e-12)
