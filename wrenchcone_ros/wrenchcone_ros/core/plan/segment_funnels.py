# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Funnels: each segment's entry region of a plan for a region of starts, and the check
that the rest of the plan seats the part from every state of it.

A plan is a chain of segments, one tilt each; a segment ends at its contact event (a
fixel reached) and the next one begins. Chained as Burridge, Rizzi and Koditschek's
funnels (sequential composition, 1999), each segment's tilt must bring every state
that enters it to a state from which the next segment goes on, down to the seat.
region.py certifies the start box of the whole chain; this module gives each later
segment its **entry box** and checks it as a funnel of the plan's rest.

**Entry boxes** (:func:`entry_boxes`). A state is (x m, y m, theta rad, vx m/s, vy m/s,
omega rad/s): the pose, and the centre of mass's velocity, fixture frame (a segment
begins at a contact event, so the part moves). Every run of the certified start box
(region.py: its cover under every model, its drawn starts) records the state at which
each later segment began (:func:`~.execution.trace`). The entry box E_k of segment
k >= 2 is the smallest box, per axis, that holds every such state of segment k: of the
certified box's runs, and of the runs of E_(k-1)'s check below. Segment 1's entry region
is the start box itself, at rest.

**The check** (:func:`certify_funnels`), segment by segment, k = 2, ..., n:
FUNNEL_DRAWS states drawn uniformly in E_k (a pose at which a fixel overlaps the part is
drawn again; the velocity uniform in its box, independently of the pose, so that the
drawn states are not the runs' own), each with a model drawn from the uncertainty, and
the plan run in the engine from segment k on. A run passes when the part comes to rest
seated with the contact events of segment k and the later ones, in the plan's order (a
fixel of an earlier segment, one the plan starts on, or one touching at the drawn state,
may be touched again).
E_k is a funnel when every run passes; then a failure rate above eps of such draws is
ruled out with confidence 1 - beta (eps from the draws and REGION_BETA, as for the start
box; one bound per funnel). The images of E_(k-1)'s drawn states enter E_k by the box's
construction; what each check adds is that the plan's rest seats the part from states
no run of the chain produced: the combinations of pose and velocity the box holds.

**What is claimed**, exactly: for each segment k with a funnel, from a state drawn
uniformly in E_k with a model drawn from the uncertainty, the plan from segment k on
seats the part but for a failure rate of at most eps, with confidence 1 - beta; nothing
is proved between the drawn states. A controller that observes the part inside E_k can
switch to segment k (the composition the funnels are for). The work is bounded by
counts: FUNNEL_DRAWS runs per segment, the same on every machine.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..scene import Scene
from ..uncertainty import Uncertainty
from .execution import sample_models
from .poses import start_scene
from .results import STATE_AXES, SegmentFunnel, Plan, RunResult

#: States drawn in each entry box and run from its segment on (the scenario bound of
#: region.py's REGION_EPSILON and REGION_BETA: 688).
FUNNEL_DRAWS: int = 688

#: The seeds of a funnel's drawn states: the plan's seed plus this times the segment.
FUNNEL_SEED_STRIDE: int = 7_000_003

#: Most draws per drawn state: a pose at which a fixel overlaps the part is drawn again,
#: at most this many times the states asked for in all.
FUNNEL_ATTEMPTS: int = 100


def segment_count(plan: Plan) -> int:
    """The plan's segments: its moving ones and the hold."""
    return sum(1 for s in plan.segments if not s.hold) + 1


def entry_states(runs: Sequence[RunResult], first: int = 1
                 ) -> dict[int, list[tuple[float, ...]]]:
    """The entry states of each later segment in ``runs`` that started with segment
    ``first``: segment (1-based) -> states.

    Parameters
    ----------
    runs : sequence of RunResult
        Runs with their ``entries`` (:func:`~.execution.trace`).
    first : int
        The segment the runs started with.

    Returns
    -------
    dict
        Segment -> its entry states, in the runs' order.
    """
    out: dict[int, list[tuple[float, ...]]] = {}
    for r in runs:
        for j, state in enumerate(r.entries):
            out.setdefault(first + 1 + j, []).append(tuple(state))
    return out


def hull(states: Sequence[Sequence[float]]) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The smallest box holding ``states``: (lo, hi) per axis."""
    a = np.asarray(states, dtype=float).reshape(-1, len(STATE_AXES))
    return tuple(map(float, a.min(axis=0))), tuple(map(float, a.max(axis=0)))


def sample_states(scene: Scene, lo: Sequence[float], hi: Sequence[float], count: int,
                  seed: int) -> list[tuple[float, ...]]:
    """``count`` states drawn uniformly in the box [lo, hi] (``default_rng(seed)``); a
    state whose pose overlaps a fixel is drawn again.

    Parameters
    ----------
    scene : Scene
        The scene (its part and fixels).
    lo, hi : sequence of 6 float
        The box.
    count : int
        How many states.
    seed : int
        The seed.

    Returns
    -------
    list of tuple of 6 float
        The states; fewer than ``count`` when FUNNEL_ATTEMPTS * count draws did not find
        them (a box that is nearly all overlap).
    """
    rng = np.random.default_rng(seed)
    lo_a, hi_a = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    x0, y0, t0 = scene.pose
    out: list[tuple[float, ...]] = []
    for _ in range(FUNNEL_ATTEMPTS * count):
        if len(out) >= count:
            break
        state = lo_a + (hi_a - lo_a) * rng.random(len(STATE_AXES))
        if start_scene(scene, (state[0] - x0, state[1] - y0, state[2] - t0)) is None:
            continue
        out.append(tuple(map(float, state)))
    return out


def as_planned_from(plan: Plan, segment: int, start_contacts: set[int],
                    run: RunResult) -> bool:
    """Whether a run from ``segment`` on seats the part as planned: it succeeded, and its
    contact events are those of ``segment`` and the later segments, in the plan's order,
    apart from fixels of earlier segments and ``start_contacts`` (1-based: those the
    plan starts on, those touching at the run's start), which it may touch again.

    Parameters
    ----------
    plan : Plan
        The plan.
    segment : int
        The segment the run started with (1-based).
    start_contacts : set of int
        The fixels it may touch again besides the earlier segments'.
    run : RunResult
        The run.

    Returns
    -------
    bool
    """
    if not run.success:
        return False
    moving = [s for s in plan.segments if not s.hold]
    group = {e: j for j, s in enumerate(moving) if j >= segment - 1 for e in s.reached}
    earlier = {e for s in moving[:segment - 1] for e in s.reached}
    allowed = earlier | start_contacts
    if any(e not in group and e not in allowed for e in run.events):
        return False
    order = [group[e] for e in run.events if e in group]
    pending = {e for e in group if e not in start_contacts}
    return pending <= set(run.events) and order == sorted(order)


def _state_text(state: Sequence[float]) -> str:
    x, y, th, vx, vy, w = state
    return (f"state ({x * 1e3:.3f} mm, {y * 1e3:.3f} mm, {math.degrees(th):.2f} deg; "
            f"{vx * 1e3:.1f} mm/s, {vy * 1e3:.1f} mm/s, {math.degrees(w):.1f} deg/s)")


def certify_segment_funnels(scene: Scene, plan: Plan, region_runs: Sequence[RunResult],
                    uncertainty: Uncertainty, run_from: Callable, *,
                    draws: int = FUNNEL_DRAWS, seed: int = 0, beta: float = 1e-3
                    ) -> tuple[SegmentFunnel, ...]:
    """The entry box of every segment after the first, each checked as a funnel of the
    plan's rest (module docstring), in segment order.

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose, and the fixels.
    plan : Plan
        The plan.
    region_runs : sequence of RunResult
        The runs that certified the start box (all passed), with their entry states.
    uncertainty : Uncertainty
        The model set the drawn states' models come from.
    run_from : callable
        ``run_from(segment, states, models) -> list of RunResult``: the plan from
        ``segment`` on from each state (x, y, theta, vx, vy, omega) under its model, in
        order (region.py runs them in its worker processes).
    draws : int
        States drawn per entry box (>= 0; 0: the boxes only, not checked).
    seed : int
        Seed of the drawn states and models.
    beta : float
        The scenario bound's confidence parameter.

    Returns
    -------
    tuple of SegmentFunnel
        One per segment 2..n; empty for a plan of one segment.
    """
    n = segment_count(plan)
    states = entry_states(region_runs)
    funnels: list[SegmentFunnel] = []
    for k in range(2, n + 1):
        seen = states.get(k, [])
        if not seen:
            funnels.append(SegmentFunnel(k, (0.0,) * 6, (0.0,) * 6, 0, 0, 0, beta,
                                  "no run entered the segment"))
            continue
        lo, hi = hull(seen)
        k_seed = seed + FUNNEL_SEED_STRIDE * k
        drawn = sample_states(scene, lo, hi, draws, k_seed) if draws else []
        models = sample_models(scene, uncertainty, len(drawn), k_seed)
        res = run_from(k, drawn, models) if drawn else []
        passed, failure = 0, ""
        for state, r in zip(drawn, res):
            if r.matches:
                passed += 1
            elif not failure:
                failure = (f"{_state_text(state)}, mu "
                           f"{', '.join(f'{m:.3g}' for m in r.friction)}: "
                           + (r.reason or "meets the contacts in another order"))
        if draws and not drawn:
            failure = "every drawn pose overlaps a fixel"
        funnels.append(SegmentFunnel(k, lo, hi, len(seen), len(drawn), passed, beta, failure))
        # the images of this box's drawn states enter the later boxes too
        for later, extra in entry_states([r for r in res if r.matches], k).items():
            states.setdefault(later, []).extend(extra)
    return tuple(funnels)
