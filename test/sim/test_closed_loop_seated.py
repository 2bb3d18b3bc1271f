# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The controller knows when it is done: no run ends TIMEOUT on a part at rest in its
seat. The pawl of examples/pawl_seating.yaml, in the lockstep loop; the wrenchcone node
is given the same fixture with every pin 8 um bigger than the tray's (3.008 mm for 3 mm,
within a pin's manufacturing tolerance; every pin the same radius, so the test does not
depend on how the node learns radii). At rest in its seat the part is pressed into the
stop, which the node then sees overlapping it by 10 um, beyond its contact tolerance
(the engine's contact band, 8.35 um): the node refuses the pose (SCENE_ERROR). The
controller used to take that for an impact's bounce at every step and hold for ever:
the run ended TIMEOUT while the tray's truth said seated. Now a part at rest where the
node refuses the pose is a deviation at once, and the run ends FAILED with that reason
within the controller's bounds (plans, back-offs, open loop), each step said on
``~/state``."""

from pathlib import Path

import pytest
import yaml

pytest.importorskip("pymunk")

from wrenchcone_ros.sim.loop import Loop  # noqa: E402

pytestmark = pytest.mark.slow  # closed-loop runs over DDS

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
BIGGER = 8e-6  # m: the node's pins are this much bigger than the tray's


def test_a_part_at_rest_in_its_seat_never_ends_the_run_timeout(tmp_path):
    data = yaml.safe_load(PAWL.read_text())
    for f in data["fixels"]:
        f["radius"] += BIGGER
    # the file's own pose check at the node's tolerance (the pose comes from the tray)
    data["contact_tolerance"] = 8.35e-6
    node_file = tmp_path / "pawl_pins_bigger.yaml"
    node_file.write_text(yaml.safe_dump(data))
    with Loop(PAWL, [1, 2, 3], node_scene=node_file, sim_timeout=10.0) as loop:
        r = loop.run(timeout=300.0)
        states = list(loop.controller.log.states)
    assert r.lockstep_timeouts == 0
    assert r.seated, (r.state, r.reason, r.letters)  # the tray's truth: at rest, seated
    assert r.state != "TIMEOUT", r.reason
    # the node cannot confirm the seat: the controller says so instead of SEATED
    assert r.state == "FAILED" and "refuses the pose" in r.reason, (r.state, r.reason)
    assert "penetrates" in r.reason
    # its replans are bounded and counted in the reasons it published
    assert r.plans <= loop.controller.max_plans
    assert any(s == "PLANNING" and f"of at most {loop.controller.max_plans}" in why
               for s, why in states), states
