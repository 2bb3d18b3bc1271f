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

Run ``.venv/bin/python test/core/test_plan_examples.py`` to print the scan's summary
quoted in docs/planning.md.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import pytest

pytest.importorskip("pymunk")

from test_tutorial_tray_tilting import ROOT  # noqa: E402

from wrenchcone_ros.core import DirectionInterval, load_scene  # noqa: E402
from wrenchcone_ros.core.plan import (  # noqa: E402
    HOLD_LIMIT,
    SEGMENT_TIMEOUT,
    Plan,
    Segment,
    plan_seating,
    trace,
)
from wrenchcone_ros.core.simulate import Actuator, Simulation  # noqa: E402
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND, SIM_SLOP  # noqa: E402

TBAR = ROOT / "examples" / "tbar_swing.yaml"
TARGET = (1, 2)
#: The scan: every SCAN_STEP degrees over the full circle.
SCAN_STEP = 2
NEVER = "never reaches pin 2"
SWINGS = "reaches pin 2 but is not seated at the end"


@dataclass(frozen=True)
class Outcome:
    """One constant tilt (degrees): seated at the end, the fixels (1-based) reached in
    order, and whether the part ended free for good (:func:`gone`)."""

    direction_deg: float
    seated: bool
    reached: tuple[int, ...]
    gone: bool


def one_tilt_plan(scene, phi: float, target) -> Plan:
    """A plan of one tilt phi (rad): move until every target fixel not yet touched is
    reached, then hold, all under phi; run by ``plan.trace`` like any plan."""
    todo = tuple(i for i in target if not scene.in_contact[i - 1])
    pose = tuple(scene.pose)

    def segment(hold: bool) -> Segment:
        return Segment(mode="", interval=DirectionInterval(phi, phi, phi, 0.0), direction=phi,
                       margin=0.0,
                       start_pose=pose, end_pose=pose, event="", predicted_event="",
                       reached=() if hold else todo, hold=hold)
    return Plan(((segment(False),) if todo else ()) + (segment(True),), True, "",
                tuple(target), Actuator(), None)


def gone(sim: Simulation, scene) -> bool:
    """The part is free and can never touch a fixel again: for every fixel f, the com c
    is farther than L + rho + band (+ the engine's slop) from it and both the com's
    velocity v and the pull F point away from it ((f - c).v <= 0, (f - c).F <= 0, so
    |f - c| only grows: the pull is at the com, the part spins freely and no point of
    it is farther than L from c)."""
    body = sim.sp.body
    c = body.local_to_world(scene.workpiece.com)
    v = body.velocity
    fx, fy = (math.cos(sim.direction), math.sin(sim.direction))
    reach = sim.sp.length_scale * (1.0 + SIM_CONTACT_BAND + SIM_SLOP)  # the engine's pins
    for f in scene.fixels:
        dx, dy = f.position[0] - c.x, f.position[1] - c.y
        if math.hypot(dx, dy) <= reach + f.radius or dx * v.x + dy * v.y > 0 \
                or dx * fx + dy * fy > 0:
            return False
    return True


def constant_tilt(scene, degrees: float, target=TARGET) -> Outcome:
    """The part under one tilt from the scene's pose (nominal model): first run until it
    is gone (then it is not seated) or for as long as a plan may run; if it is not gone,
    the verdict is ``plan.trace``'s for the one-tilt plan."""
    phi = math.radians(degrees)
    sim = Simulation(scene, Actuator(), phi)
    band = SIM_CONTACT_BAND * sim.sp.length_scale
    touching = {i for i, c in enumerate(scene.in_contact) if c}
    reached: list[int] = []
    while sim.t < (SEGMENT_TIMEOUT + HOLD_LIMIT) * sim.sp.time_scale:
        sim.step()
        for i, g in enumerate(sim.gaps()):
            if i not in touching and g <= band:
                touching.add(i)
                reached.append(i + 1)
        if gone(sim, scene):
            return Outcome(degrees, False, tuple(reached), True)
    run = trace(scene, one_tilt_plan(scene, phi, target), None, record_every=0)[0]
    return Outcome(degrees, run.success, run.events, False)


def scan(scene) -> list[Outcome]:
    """Every constant tilt, SCAN_STEP degrees apart over the full circle."""
    return [constant_tilt(scene, d) for d in range(-180, 180, SCAN_STEP)]


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


def summarise(outcomes: list[Outcome]) -> dict[str, list[tuple[float, float]]]:
    """Consecutive tilts with the same fate, as (first, last) degree ranges."""
    out: dict[str, list[tuple[float, float]]] = {}
    for o in outcomes:
        f = "seated" if o.seated else SWINGS if 2 in o.reached else NEVER
        runs = out.setdefault(f, [])
        if runs and runs[-1][1] == o.direction_deg - SCAN_STEP:
            runs[-1] = (runs[-1][0], o.direction_deg)
        else:
            runs.append((o.direction_deg, o.direction_deg))
    return out


def summary_lines(summary: dict[str, list[tuple[float, float]]]) -> list[str]:
    """The summary as docs/planning.md quotes it, one line per fate."""
    return [f"* {fate}: " + ", ".join(f"{lo:g} .. {hi:g}" for lo, hi in ranges)
            for fate, ranges in summary.items()]


if __name__ == "__main__":
    print("\n".join(summary_lines(summarise(scan(load_scene(TBAR))))))
    sys.exit(0)
