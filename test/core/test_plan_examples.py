# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The plan examples of docs/planning.md, checked independently of the planner's cones.

examples/tbar_swing.yaml (section 4) is the example whose plan needs two different tilts:
the planner's two intervals are disjoint, and a scan of constant tilts, each run in the
engine (core/simulate.py, the nominal model) from the start pose, finds none that seats
the part. A constant tilt is run as a one-tilt plan through ``plan.trace``, the very code
that runs the plans (same time limits, same test of "seated": every target fixel touches
and the part is at rest); a run is cut short only once the part is free and can never
touch a fixel again (:func:`gone`), which cannot seat it. The check is shown to say yes
where it should (the seated T-bar under the hold tilt, single tilts on the pawl of
section 1), so the scan is able to fail.

Run ``.venv/bin/python test/helpers/tilt_scan.py`` to print the scan's summary
quoted in docs/planning.md.
"""

from __future__ import annotations

import math

import pytest

pytest.importorskip("pymunk")

from helpers.docs_examples import ROOT  # noqa: E402
from helpers.tilt_scan import (  # noqa: E402
    NEVER,
    SCAN_STEP,
    SWINGS,
    TARGET,
    TBAR,
    constant_tilt,
    scan,
    summarise,
    summary_lines,
)

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating  # noqa: E402

pytestmark = pytest.mark.slow  # plans and constant tilts run in the physics engine


@pytest.fixture(scope="module")
def tbar():
    return load_scene(TBAR)


@pytest.fixture(scope="module")
def tbar_plan(tbar):
    return plan_seating(tbar, TARGET, "tilt", (0.2, 0.4), runs=0)


def test_tbar_plan_needs_two_disjoint_tilts(tbar_plan):
    """The planner's own plan: a swing onto pin 2, then a hold, under two tilts whose
    intervals share no direction (each tilt lies outside the other segment's interval)."""
    plan = tbar_plan
    assert plan.feasible and plan.nominal.success, plan.reason
    assert [s.mode for s in plan.segments] == ["na", "nn"]
    swing, hold = plan.segments
    assert swing.event == "fixel 2 reached" and hold.hold
    assert swing.interval.hi < hold.interval.lo or hold.interval.hi < swing.interval.lo
    assert not (hold.interval.lo <= swing.direction <= hold.interval.hi)
    assert not (swing.interval.lo <= hold.direction <= swing.interval.hi)


def test_the_check_can_say_seated(tbar, tbar_plan):
    """The scan's check is not blind: the seated T-bar under the hold's tilt is seated
    (and the plan's own two-tilt run, by the same ``trace``, seats it)."""
    hold = tbar_plan.segments[-1]
    seated = tbar.with_pose(*hold.end_pose)
    assert constant_tilt(seated, math.degrees(hold.direction)).seated
    assert tbar_plan.nominal.success


def test_the_scan_finds_a_single_tilt_where_one_does():
    """The same check on the pawl of section 1, where one tilt is enough: tilts that
    slide it to the stop and hold it there seat it; at -80 deg it sticks on its pins."""
    pawl = load_scene(ROOT / "examples" / "pawl_seating.yaml")
    seated = [d for d in (-80, -70, -60, -50) if constant_tilt(pawl, d, (1, 2, 3)).seated]
    assert seated == [-70, -60, -50]


def test_no_single_tilt_seats_the_tbar(tbar):
    """Independent evidence that one tilt does not do it: none of the constant tilts of
    the scan seats the bar (docs/planning.md quotes this summary)."""
    outcomes = scan(tbar)
    assert len(outcomes) == 360 // SCAN_STEP
    assert [o.direction_deg for o in outcomes if o.seated] == []
    summary = summarise(outcomes)
    assert set(summary) == {NEVER, SWINGS}
    text = (ROOT / "docs" / "planning.md").read_text()
    for line in summary_lines(summary):
        assert line in text, f"docs/planning.md section 4 should read: {line}"


def test_the_tipped_pawl_does_not_show_it():
    """docs/planning.md, section 4, last paragraph: the tipped pawl's plan changes its
    tilt, but some direction lies in every one of its segments' intervals."""
    plan = plan_seating(load_scene(ROOT / "examples" / "pawl_tipped.yaml"), (1, 2, 3),
                        "tilt", (0.2, 0.4), runs=0)
    assert plan.feasible and len({s.direction for s in plan.segments}) >= 2
    lo = max(s.interval.lo for s in plan.segments)
    hi = min(s.interval.hi for s in plan.segments)
    assert lo <= hi


def test_the_swing_tilts_slide_off_pin_2(tbar):
    """Why the swing's tilts fail on their own: under each of them the bar reaches pin 2
    and then leaves both pins for good (it slides on, off them)."""
    for d in range(-72, -20, 10):
        o = constant_tilt(tbar, d)
        assert o.reached[:1] == (2,) and not o.seated and o.gone, d
