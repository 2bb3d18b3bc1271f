# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tray_sim node between two runs (wrenchcone_ros.sim.tray_sim): a command computed
for the part of before a reset never moves the part of after it, even when it is in
flight while the reset happens; after a reset the part stays where it was put until the
first command of the new run. The physics thread is not started: the test steps the
node itself (step_once), so that what happens when is the test's to say."""

import math
import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

from wrenchcone_msgs.msg import TiltCommand  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.directions import STANDARD_GRAVITY  # noqa: E402
from wrenchcone_ros.core.simulate import DEFAULT_TILT  # noqa: E402
from wrenchcone_ros.sim.tray import TrayPhysics  # noqa: E402
from wrenchcone_ros.sim.tray_sim import TraySimNode, _time_msg  # noqa: E402

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
A10 = STANDARD_GRAVITY * math.sin(DEFAULT_TILT)  # m/s^2: a tray tilted by 10 degrees
SLIDE = math.radians(-58.5)  # the pawl's first segment: slide right on pins 2 and 3


@pytest.fixture
def tray(ros_context):
    node = TraySimNode(physics=TrayPhysics(load_scene(PAWL)), context=ros_context,
                       start=False)
    yield node
    node.destroy_node()


def command(direction: float, magnitude: float, stamp) -> TiltCommand:
    msg = TiltCommand(direction=direction, magnitude=magnitude)
    msg.header.stamp = stamp
    return msg


def moved(tray: TraySimNode) -> float:
    """How far (m) the part is from the scene's start pose."""
    return math.dist(tray.physics.readout().pose[:2], tray.physics.start.pose[:2])


def test_a_command_in_flight_during_a_reset_does_not_move_the_new_part(tray):
    """The previous run's last command, computed from a pose of before the reset,
    reaches the tray's callback just before the reset and gets the lock just after it
    (the callback of a loaded executor): it is stale, and the part stays put."""
    tray.step_once()
    old_stamp = _time_msg(tray.physics.clock)  # a pose the previous run saw
    tray.step_once()
    stale = command(SLIDE, A10, old_stamp)
    with tray.lock:
        late = threading.Thread(target=tray._on_command, args=(stale,))
        late.start()
        time.sleep(0.2)  # the callback is waiting for the lock
        tray.physics.reset(None)
        tray.after_reset()
    late.join(5.0)
    for _ in range(40):  # 0.2 s of sim time: the pawl would slide millimetres
        tray.step_once()
    assert moved(tray) <= 1e-9
    assert tray.stale_commands == 1 and tray.physics.command.magnitude == 0.0


def test_a_command_from_the_last_pose_before_the_reset_is_stale(tray):
    """A pose published at the very instant of the reset belongs to the part of before
    it: a command stamped with it is stale too."""
    tray.step_once()
    with tray.lock:
        at_reset = _time_msg(tray.physics.clock)  # the last pose published
        tray.physics.reset(None)
        tray.after_reset()
    tray._on_command(command(SLIDE, A10, at_reset))
    for _ in range(40):
        tray.step_once()
    assert moved(tray) <= 1e-9 and tray.stale_commands == 1


def test_after_a_reset_the_part_is_held_until_the_new_runs_first_command(tray):
    """After a reset the engine is not stepped (the clock runs on) until a command of the
    new run arrives; from then on the part moves under it."""
    tray._on_command(command(SLIDE, A10, _time_msg(0.0)))
    for _ in range(20):
        tray.step_once()
    assert moved(tray) > 1e-4  # the first run moved the part
    with tray.lock:
        tray.physics.reset(None)
        tray.after_reset()
    t_reset = tray.physics.clock
    for _ in range(20):
        tray.step_once()
    assert moved(tray) <= 1e-9 and tray.physics.held
    dt = tray.physics.dt  # the engine's step: a publish period is whole steps of it
    assert tray.physics.clock == pytest.approx(t_reset + 20 * round(tray.period / dt) * dt)
    tray._on_command(command(SLIDE, A10, _time_msg(tray.physics.clock)))
    assert not tray.physics.held
    for _ in range(20):
        tray.step_once()
    assert moved(tray) > 1e-4
