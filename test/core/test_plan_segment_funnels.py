# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Each later segment's entry box of a region plan, checked as a funnel of the plan's
rest (core/plan/segment_funnels.py).

The rules are checked on hand-made runs; a run from a later segment against a run of
the whole plan; the pawl's funnel from outside the checker: states drawn uniformly in
its entry box by this test's own generator, each with its own friction per pin, run in
the engine and judged by the run's own test of seated; and not vacuous: the box
enlarged about its centre shows failures.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from wrenchcone_ros.cli.render import plan_text
from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.geometry import SceneError
from wrenchcone_ros.core.plan import (
    PlanError,
    RunResult,
    SegmentFunnel,
    StartRegion,
    plan_seating,
    sample_states,
    trace,
)
from wrenchcone_ros.core.plan.region import check_segment_funnels
from wrenchcone_ros.core.plan.segment_funnels import as_planned_from, entry_states, hull

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PAWL_BOX = (0.002, 0.002, math.radians(5.0))


@pytest.fixture(scope="module")
def pawl():
    scene = load_scene(EXAMPLES / "pawl_seating.yaml")
    return scene, plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4),
                               simulate_runs=False)


def _run(events, success=True, entries=()) -> RunResult:
    return RunResult((0.3, 0.3, 0.3), success, tuple(events), True, (0.0, 0.0, 0.0),
                     entries=tuple(entries))


# --- the rules, on hand-made runs (no engine) ---------------------------------------------
def test_events_as_planned_from_a_later_segment(pawl):
    """The pawl's plan: segment 1 reaches fixel 1, segment 2 holds it seated; it starts
    on pins 2 and 3. From segment 2 nothing is left to reach: fixel 1 (an earlier
    segment's) and the pins it starts on may be touched again, nothing else; from
    segment 1 the rule is the whole plan's."""
    _, plan = pawl
    assert [s.hold for s in plan.segments] == [False, True]
    on = {2, 3}
    assert as_planned_from(plan, 2, on, _run([]))
    assert as_planned_from(plan, 2, on, _run([1, 3, 2]))
    assert not as_planned_from(plan, 2, {3}, _run([2]))  # pin 2 neither earlier nor on
    assert not as_planned_from(plan, 2, on, _run([], success=False))
    assert as_planned_from(plan, 1, on, _run([2, 1]))
    assert not as_planned_from(plan, 1, on, _run([2, 3]))  # fixel 1 never reached
    assert as_planned_from(plan, 1, {1, 2, 3}, _run([]))  # touching it from the start


def test_entry_states_hull_and_drawn_states(pawl):
    scene, _ = pawl
    a, b = (0.1, 0.2, 0.0, 0.01, 0.0, -0.1), (0.1001, 0.2002, 0.001, 0.03, 0.002, 0.0)
    runs = [_run([1], entries=[a]), _run([1], entries=[b]), _run([], entries=[])]
    assert entry_states(runs) == {2: [a, b]}
    assert entry_states(runs, first=2) == {3: [a, b]}
    lo, hi = hull([a, b])
    assert lo == tuple(min(p, q) for p, q in zip(a, b))
    assert hi == tuple(max(p, q) for p, q in zip(a, b))
    x, y, t = scene.pose
    lo = (x - 0.001, y - 0.001, t - 0.05, -0.1, -0.1, -1.0)
    hi = (x + 0.001, y + 0.001, t + 0.05, 0.1, 0.1, 1.0)
    states = sample_states(scene, lo, hi, 50, seed=3)
    assert len(states) == 50 and states == sample_states(scene, lo, hi, 50, seed=3)
    for st in states:
        assert all(low <= v <= high for v, low, high in zip(st, lo, hi))
        scene.with_pose(*st[:3])  # no fixel overlaps the part there (raises otherwise)
    # a box wholly inside a pin gives no state, and says so by returning fewer
    assert sample_states(scene, (x, y - 0.01, t, 0, 0, 0), (x, y - 0.01, t, 0, 0, 0), 3, 0) \
        == []


def test_a_funnel_says_what_it_holds():
    f = SegmentFunnel(2, (0.0,) * 6, (1.0,) * 6, 10, 688, 688, 1e-3)
    assert f.holds and (1.0 - f.epsilon) ** 688 == pytest.approx(1e-3)
    assert f.contains((0.5,) * 6) and not f.contains((0.5,) * 5 + (1.5,))
    assert "a funnel: 688 of 688 states drawn" in f.verdict()
    g = SegmentFunnel(3, (0.0,) * 6, (1.0,) * 6, 10, 688, 600, 1e-3, "state (...)")
    assert not g.holds and g.epsilon is None and "not a funnel: 600 of 688" in g.verdict()
    d = g.to_dict()
    assert d["axes"][3] == "vx (m/s)" and d["holds"] is False and d["segment"] == 3


def test_bad_draws_are_refused(pawl):
    scene, plan = pawl
    with pytest.raises(PlanError, match="draws must be a whole number >= 0"):
        check_segment_funnels(scene, plan, None, None, draws=-1)
    with pytest.raises(PlanError, match="segment_funnel_draws must be a whole number"):
        plan_seating(scene, [1, 2, 3], start_region=PAWL_BOX, segment_funnel_draws=1.5)


# --- the engine ----------------------------------------------------------------------------
def test_a_run_from_a_later_segment_goes_on_from_its_entry_state(pawl):
    """The whole plan's nominal run records the state at which segment 2 began (fixel 1
    just reached, the part moving); the plan from segment 2 on, started at that state,
    seats the part too. A segment that does not exist is refused."""
    scene, plan = pawl
    whole, _ = trace(scene, plan, None, record_every=0)
    assert whole.success and len(whole.entries) == 1
    state = whole.entries[0]
    assert len(state) == 6 and math.hypot(state[3], state[4]) > 0.0  # it moves
    rest, _ = trace(scene.with_pose(*state[:3]), plan, None, record_every=0,
                    start_segment=2, twist=state[3:])
    assert rest.success and rest.entries == ()
    assert abs(rest.final_pose[0] - whole.final_pose[0]) < 1e-4
    for bad in (0, 3):
        with pytest.raises(ValueError, match="start_segment must be in 1..2"):
            trace(scene, plan, None, record_every=0, start_segment=bad)


def drawn_states(scene, lo, hi, count: int, seed: int) -> list[tuple]:
    """``count`` states uniform in [lo, hi] (this test's own draw), a pose at which the
    scene says a fixel overlaps the part drawn again."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        st = tuple(rng.uniform(lo, hi))
        try:
            scene.with_pose(*st[:3])
        except SceneError:
            continue
        out.append(st)
    return out


def seated_from(scene, plan, segment, lo, hi, count, seed, mu=(0.2, 0.4)) -> int:
    rng = np.random.default_rng(seed + 1)
    ok = 0
    for st in drawn_states(scene, lo, hi, count, seed):
        r, _ = trace(scene.with_pose(*st[:3]), plan, tuple(rng.uniform(*mu, scene.n_fixels)),
                     record_every=0, start_segment=segment, twist=st[3:])
        ok += r.success
    return ok


@pytest.mark.heavy
def test_the_pawls_hold_is_a_funnel_and_not_a_vacuous_one():
    """The pawl from +-2 mm x +-2 mm x +-5 deg: segment 2's entry box holds every entry
    state of the runs that certified the box, its check passes (200 states here, 688
    by default), and 100 states drawn in it by this test, each with its own friction,
    seat from segment 2 on; the box enlarged 8 times about its centre does not."""
    scene = load_scene(EXAMPLES / "pawl_seating.yaml")
    plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False,
                        workers=2, start_region=PAWL_BOX, region_candidates=1,
                        segment_funnel_draws=200)
    cert = plan.region
    assert plan.start_region == StartRegion(*PAWL_BOX)
    assert cert.evidence == ()  # the runs behind it are not carried with the plan
    (f,) = cert.segment_funnels
    assert f.segment == 2 and f.observed == cert.runs and f.holds
    assert f.draws == f.passed == 200
    assert f.lo[3] >= 0.0 and f.hi[3] > 0.0  # it arrives moving in +x, towards fixel 1
    assert seated_from(scene, plan, 2, f.lo, f.hi, 100, seed=11) >= 99
    c, h = np.add(f.lo, f.hi) / 2.0, np.subtract(f.hi, f.lo) / 2.0
    assert seated_from(scene, plan, 2, c - 8 * h, c + 8 * h, 100, seed=12) < 100
    text = plan_text(plan)
    assert "\nfunnel: segment 2's entry box (" in text
    assert "a funnel: 200 of 200 states drawn in it seat the part from segment 2 on" in text
    assert "\n  entry box: x " in text
