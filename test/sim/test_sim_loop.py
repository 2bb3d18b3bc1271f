# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Runs one after another in one loop (wrenchcone_ros.sim.loop.Loop), as the benchmark
does, loosely, on a small sample of the guaranteed task (the pawl of
examples/pawl_seating.yaml, mu in [0.2, 0.4], the planner's seeded sample): every model
the open loop seats, the closed loop seats too, each run starting from a part that did
not move before its first command, the previous run's controller idle. The 100-model
comparison is benchmarks/closed_loop.py (docs/closed_loop.md)."""

from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # three closed-loop runs over DDS

pytest.importorskip("pymunk")

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.core.plan import execute, plan_seating, sample_models  # noqa: E402
from wrenchcone_ros.sim.loop import Loop  # noqa: E402

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"
FRICTION = (0.2, 0.4)


def test_consecutive_runs_seat_what_the_open_loop_seats():
    scene = load_scene(PAWL)
    plan = plan_seating(scene, [1, 2, 3], "tilt", uncertainty=FRICTION, runs=0)
    assert plan.guaranteed
    models = sample_models(scene, Uncertainty(friction=FRICTION), 3, 0)
    open_loop = [execute(scene, plan, m).success for m in models]
    with Loop(PAWL, [1, 2, 3], FRICTION,
              controller_parameters={"reuse_plan": True}) as loop:
        results = [loop.run(m, timeout=120.0) for m in models]
    assert all(open_loop)
    for r in results:
        assert r.seated and r.state == "SEATED", (r.state, r.reason, r.letters)
        assert r.previous_idle
        # the tray read the part at rest at its start (on pins 2 and 3, 8 mm off the
        # stop: snn) before it slid (arr): nothing moved it before the run's controller
        # commanded it (a previous run's command leaking in slides it at once)
        assert "snn" in r.letters and "arr" in r.letters, r.letters
        assert r.letters.index("snn") < r.letters.index("arr"), r.letters
        # the planned sequence, one plan: in lockstep no step comes late, however loaded
        # the machine
        assert r.modes == ["arr", "nnn"] and r.plans == 1, (r.modes, r.plans)
        assert r.lockstep_timeouts == 0
