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
from wrenchcone_ros.core.plan.results import failure_rate_bound
from wrenchcone_ros.core.plan.segment_funnels import (
    as_planned_from,
    certify_segment_funnels,
    entry_states,
    hull,
    tube_of,
)

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
    mu = (0.3, 0.3, 0.3)  # the runs' model: their friction (no other parameter varies)
    assert entry_states(runs) == {2: [(a, mu), (b, mu)]}
    assert entry_states(runs, first=2) == {3: [(a, mu), (b, mu)]}
    lo, hi = hull([a, b])
    assert lo == tuple(min(p, q) for p, q in zip(a, b))
    assert hi == tuple(max(p, q) for p, q in zip(a, b))
    # the boxes around the entry states: a tenth of the pose box, no velocity spread
    assert tube_of(lo, hi, 0.1) == pytest.approx((5e-6, 1e-5, 5e-5, 0.0, 0.0, 0.0))
    x, y, t = scene.pose
    entries = [(x, y + 0.001, t, 0.01, 0.0, 0.0), (x + 0.001, y + 0.002, t, 0.0, 0.02, 0.5)]
    h = (0.0005, 0.0005, 0.01, 0.0, 0.0, 0.0)
    drawn = sample_states(scene, entries, h, 50, seed=3)
    assert len(drawn) == 50 and drawn == sample_states(scene, entries, h, 50, seed=3)
    assert {i for i, _ in drawn} == {0, 1}
    for i, st in drawn:
        assert all(abs(v - c) <= w for v, c, w in zip(st, entries[i], h))
        assert st[3:] == entries[i][3:]  # the entry state's velocity
        scene.with_pose(*st[:3])  # no fixel overlaps the part there (raises otherwise)
    # a pose wholly inside a pin gives no state, and says so by returning fewer
    assert sample_states(scene, [(x, y - 0.01, t, 0, 0, 0)], (0.0,) * 6, 3, 0) == []


def test_a_funnel_says_what_it_holds():
    entries = ((0.0,) * 6, (1.0,) * 6)
    f = SegmentFunnel(2, (0.0,) * 6, (1.0,) * 6, 2, 688, 688, 1e-3, "", 0.1, entries)
    assert f.holds and (1.0 - f.epsilon) ** 688 == pytest.approx(1e-3)
    assert f.half_widths == pytest.approx((0.05, 0.05, 0.05, 0.0, 0.0, 0.0))
    assert f.near((0.04, -0.05, 0.0)) == [0] and f.near((0.5, 0.5, 0.5)) == []
    assert "a funnel: 688 of 688 states drawn" in f.verdict()
    g = SegmentFunnel(3, (0.0,) * 6, (1.0,) * 6, 10, 688, 687, 1e-3, "state (...)")
    assert not g.holds and g.epsilon == pytest.approx(0.01334, abs=1e-5)
    assert "not a funnel: 687 of 688" in g.verdict() and "above 1.3 %" in g.verdict()
    d = g.to_dict()
    assert d["axes"][3] == "vx (m/s)" and d["holds"] is False and d["segment"] == 3


def test_a_region_that_is_not_a_funnel_is_narrowed(pawl):
    """The tube rule on a made-up world (no engine): a drawn state seats when its pose
    lies within 3 % of the entry box's half-width in x of its entry state. The region at
    10 % is not a funnel, nor at 5 %; at 2.5 % it is, and its line says how it got
    there. With no halving allowed it stays not a funnel; with a world where nothing
    seats, every halving is tried and the narrowest reported."""
    scene, plan = pawl
    x, y, t = scene.pose
    entries = [(x + 0.001 * i, y + 0.001, t, 0.01, 0.0, 0.0) for i in range(5)]
    runs = [_run([1], entries=[e]) for e in entries]
    half_x = 0.5 * (entries[-1][0] - entries[0][0])

    def world(limit):
        def run_from(segment, states, models):
            out = []
            for st in states:
                near = min(abs(st[0] - e[0]) for e in entries) <= limit * half_x
                out.append(RunResult(tuple(models[0]), near, (), near, tuple(st[:3]),
                                     "" if near else "off its pin"))
            return out
        return run_from

    (f,) = certify_segment_funnels(scene, plan, runs, world(0.03), draws=50, seed=1)
    assert f.holds and f.tube == pytest.approx(0.025) and f.checks == 3
    assert f.wider.startswith("at 5 %: ") and "off its pin" in f.wider
    assert "its boxes halved 2 time(s) to 2.5 % (3 regions checked): at 5 %" in f.verdict()
    assert "per region checked" in f.verdict()
    (g,) = certify_segment_funnels(scene, plan, runs, world(0.03), draws=50, seed=1,
                                   shrinks=0)
    assert not g.holds and g.tube == 0.1 and g.checks == 1 and g.wider == ""
    (h,) = certify_segment_funnels(scene, plan, runs, world(-1.0), draws=50, seed=1)
    assert not h.holds and h.passed == 0 and h.checks == 4
    assert h.tube == pytest.approx(0.0125) and h.wider.startswith("at 2.5 %: 0 of 50")
    assert "not a funnel" in h.verdict() and "halved 3 time(s)" in h.verdict()


def test_the_failure_rate_bound_is_the_binomial_tail():
    """For no failure it is the zero-failure bound; for k failures the binomial tail at
    eps equals beta (checked by summing it)."""
    assert failure_rate_bound(688, 0, 1e-3) == pytest.approx(1.0 - 1e-3 ** (1 / 688))
    for n, k in ((688, 1), (1000, 3), (50, 10)):
        eps = failure_rate_bound(n, k, 1e-3)
        tail = sum(math.comb(n, i) * eps ** i * (1 - eps) ** (n - i) for i in range(k + 1))
        assert tail == pytest.approx(1e-3, rel=1e-6)
    assert failure_rate_bound(5, 5, 1e-3) == 1.0


def test_bad_draws_are_refused(pawl):
    scene, plan = pawl
    with pytest.raises(PlanError, match="draws must be a whole number >= 0"):
        check_segment_funnels(scene, plan, None, draws=-1)
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


def drawn_states(scene, f, half_widths, count: int, seed: int) -> list[tuple]:
    """``count`` (state, model) pairs (this test's own draw): an entry state of the
    funnel, then its pose moved uniformly within ``half_widths`` (a pose at which the
    scene says a fixel overlaps the part drawn again) or its velocity moved within the
    velocity half-widths, the model of its run."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        i = int(rng.integers(len(f.entries)))
        c, h = np.asarray(f.entries[i]), np.asarray(half_widths)
        st = tuple(rng.uniform(c - h, c + h))
        try:
            scene.with_pose(*st[:3])
        except SceneError:
            continue
        out.append((st, f.models[i]))
    return out


def seated_from(scene, plan, f, half_widths, count, seed) -> int:
    ok = 0
    for st, model in drawn_states(scene, f, half_widths, count, seed):
        r, _ = trace(scene.with_pose(*st[:3]), plan, model, record_every=0,
                     start_segment=f.segment, twist=st[3:])
        ok += r.success
    return ok


@pytest.mark.heavy
def test_the_pawls_hold_is_a_funnel():
    """The pawl from +-2 mm x +-2 mm x +-5 deg: segment 2's entry states are those of the
    runs that certified the box, its check passes (100 states here, 688 by default), and
    100 states drawn in its region by this test, each under the model of the entry state
    it was drawn around, seat from segment 2 on. Not vacuous: with the velocity moved as
    well, by up to 8 times its entry states' box, some do not."""
    scene = load_scene(EXAMPLES / "pawl_seating.yaml")
    plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False,
                        workers=2, start_region=PAWL_BOX, region_candidates=1,
                        segment_funnel_draws=100)
    cert = plan.region
    assert plan.start_region == StartRegion(*PAWL_BOX)
    assert cert.evidence == ()  # the runs behind it are not carried with the plan
    (f,) = cert.segment_funnels
    assert f.segment == 2 and f.observed == cert.runs == len(f.entries) == len(f.models)
    assert f.holds and f.draws == f.passed == 100
    assert f.lo[3] >= 0.0 and f.hi[3] > 0.0  # it arrives moving in +x, towards fixel 1
    assert all(f.near(e[:3]) for e in f.entries[:20])
    assert seated_from(scene, plan, f, f.half_widths, 100, seed=11) >= 99
    wide = np.asarray(f.half_widths) + 8.0 * 0.5 * np.subtract(f.hi, f.lo) * (
        np.arange(6) >= 3)
    assert seated_from(scene, plan, f, wide, 100, seed=12) < 100
    text = plan_text(plan)
    assert "\nfunnel: segment 2's entry region (" in text
    assert "a funnel: 100 of 100 states drawn in it seat the part from segment 2 on" in text
    assert "\n  entry region: poses within 10 % of the half-widths" in text
    # where the part rests on a segment's contacts, the cones decide
    # (test_plan_region_cones.py checks them against the engine)
    assert [(c.segment, c.lifted) for c in cert.cone_slices] == [(1, 0), (2, 1), (2, 2),
                                                                 (2, 3)]
    assert all(c.holds for c in cert.cone_slices)
    assert "\ncones: segment 1 at rest on fixel(s) 2 3, in the start box (a curve; " in text
    assert "\ncones: segment 2 at rest on fixel(s) 2 3, lifted off fixel 1, in segment 2's" in text
