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


def test_in_free_flight_the_pose_is_the_integrators_closed_form():
    """Pulled away from every pin (50 deg: the cones give one mode, ass, fixel 1 free and
    the part leaving pins 2 and 3, margin >= 0.05) the part flies free: no contact, and
    the pull acts at the com, so no torque. Then the pose after n steps of dt is a hand
    computation, independent of core.simulate: the engine (Chipmunk) moves each body with
    its velocity before adding the step's acceleration, so x_n = x_0 + a dt^2 n (n - 1) / 2
    along the pull and theta stays. The continuous 1/2 a t^2 is farther off than the
    tolerance, so the check sees a step too many or too few, or a wrong pull."""
    scene = load_scene(PAWL)
    phi = math.radians(50.0)
    m = scene.workpiece.mass
    (mode,) = consistent_modes(scene, (m * A10 * math.cos(phi), m * A10 * math.sin(phi), 0.0))
    assert mode.mode == "ass" and mode.margin >= 0.05
    tray = TrayPhysics(scene)
    tray.set_command(phi, A10)
    tray.advance(0.2)
    dt = tray.sim.dt
    n = round(tray.clock / dt)
    d = 0.5 * A10 * dt * dt * n * (n - 1)
    x0, y0, th0 = scene.pose
    got = tray.readout()
    assert set(got.letters) <= {"a", "s"}  # touching no pin
    assert got.pose == pytest.approx((x0 + d * math.cos(phi), y0 + d * math.sin(phi), th0),
                                     abs=1e-12)
    t = n * dt  # the continuous law differs by a dt t / 2, far above the tolerance
    assert abs(0.5 * A10 * t * t - d) > 1e3 * 1e-12 and d > 0.02


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
