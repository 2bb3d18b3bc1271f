# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The closed loop on a fixture of unequal pins: the pawl of examples/pawl_seating.yaml on
two 4 mm pins under its foot and a 3 mm stop. The tray publishes the true radii, so the
node sees the part on its pins (a node that gave every pin the smallest radius saw it 1 mm
above them, planned from a fixture that did not exist, and the run ended FAILED while the
tray's truth said seated)."""

import pytest

pytestmark = pytest.mark.slow  # a closed-loop run over DDS

pytest.importorskip("pymunk")

from helpers.fixture_scenes import pawl_file  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import execute, plan_seating  # noqa: E402
from wrenchcone_ros.sim.loop import Loop  # noqa: E402

#: The example's start, 8 mm left of the seat, raised onto the 4 mm pins.
START = (0.096, 0.201, 0.0)


def test_the_closed_loop_seats_the_pawl_on_unequal_pins(tmp_path):
    path = pawl_file(tmp_path, pose=START)
    scene = load_scene(str(path))
    assert scene.in_contact == (False, True, True)  # on pins 2 and 3, off the stop
    plan = plan_seating(scene, [1, 2, 3], "tilt", runs=0)
    assert plan.feasible and execute(scene, plan).success  # the open loop seats it
    with Loop(path, [1, 2, 3], None, real_time_factor=0.5) as loop:
        r = loop.run(None, timeout=120.0)
    assert r.seated and r.state == "SEATED", (r.state, r.reason, r.letters, r.plans)
    assert "snn" in r.letters, r.letters  # the node and the tray agree: on pins 2 and 3
