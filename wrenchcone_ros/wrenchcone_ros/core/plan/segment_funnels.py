# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Funnels: each later segment's entry region of a plan for a region of starts, and the
check that the rest of the plan seats the part from every state of it.

A plan is a chain of segments, one tilt each; a segment ends at its contact event (a
fixel reached) and the next one begins. Chained as Burridge, Rizzi and Koditschek's
funnels (sequential composition, 1999), each segment's tilt must bring every state that
enters it to a state from which the next segment goes on, down to the seat. region.py
certifies the start box of the whole chain; this module gives each later segment its
**entry region** and checks it as a funnel of the plan's rest.

**Entry regions.** A state is (x m, y m, theta rad, vx m/s, vy m/s, omega rad/s): the
pose, and the centre of mass's velocity, fixture frame (a segment begins at a contact
event, so the part moves). Every run of the certified start box (region.py: its cover
under every model, its drawn starts) records the state at which each later segment
began (:func:`~.execution.trace`). Segment k's **entry states** are those of the
certified box's runs and, for k > 2, of the runs of segment k - 1's check below; their
**box** is the smallest box per axis that holds them all. The entry region E_k is the
set of states whose pose lies within FUNNEL_TUBE times the pose box's half-width, per
pose axis, of an entry state's pose, and whose velocity is that entry state's: every
pose near one where the chain hands over to segment k, the part arriving as the chain
brings it there. (The velocity is not drawn: a part arrives with the velocity the
segment before gave it, a disc that rolls onto its pin turning at the speed it moves;
states with velocities no segment gives are no test of the chain.) Segment 1's entry
region is the start box, at rest.

**The check** (:func:`certify_segment_funnels`), segment by segment, k = 2, ..., n:
FUNNEL_DRAWS states drawn in E_k (an entry state drawn uniformly, then a point
uniformly in its box; a pose at which a fixel overlaps the part is drawn again), each
run in the engine from segment k on under the model of the run that produced its entry
state (the model is the world's: the same in every segment; every model of the start
box's runs, the capture test's and the drawn ones, so appears). A run passes when the part comes to rest seated with the contact events of segment k
and the later ones, in the plan's order (a fixel of an earlier segment, one the plan
starts on, or one touching at the drawn state, may be touched again). E_k is a funnel
when every run passes; then a failure rate above eps of such draws is ruled out with
confidence 1 - beta (eps from the draws and REGION_BETA, as for the start box; one
bound per region checked). When some run fails, E_k is checked again with its boxes
half as wide (new draws), up to FUNNEL_SHRINKS times, as the start box is shrunk when
it does not hold: the segment's funnel is the widest region that holds, and its line
says so, with the last wider one that did not; when none holds, the narrowest is
reported as not a funnel, with the failure rate its draws rule out. The images of E_(k-1)'s drawn states enter E_k by its construction;
what each check adds is that the plan's rest seats the part from states no run of the
chain produced, around those it did.

**What is claimed**, exactly: for each segment k with a funnel, from a state drawn in
E_k as above, under the model it was drawn with, the plan from segment k on seats
the part but for a failure rate of at most eps, with confidence 1 - beta; nothing is
proved between the drawn states. A controller that observes the part in E_k can go on
with segment k (the composition the funnels are for). The work is bounded by counts:
FUNNEL_DRAWS runs per segment, the same on every machine.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from ..scene import Scene
from .poses import start_scene
from .results import STATE_AXES, SegmentFunnel, Plan, RunResult

#: States drawn in each entry box and run from its segment on (the scenario bound of
#: region.py's REGION_EPSILON and REGION_BETA: 688).
FUNNEL_DRAWS: int = 688

#: Dimensionless: the half-width per pose axis (x, y, theta) of the box around each
#: entry state's pose that the entry region is made of, as a fraction of the half-width
#: of the box holding every entry state of the segment.
FUNNEL_TUBE: float = 0.1

#: Halvings of the tube when an entry region is not a funnel: the region is checked
#: again with boxes FUNNEL_TUBE / 2, / 4, ... around the entry states, at most this many
#: times, and the widest that holds is the segment's funnel (as the start box is shrunk).
FUNNEL_SHRINKS: int = 3

#: The seeds of a funnel's drawn states: the plan's seed plus this times the segment
#: (plus the tube's halvings, each a new draw).
FUNNEL_SEED_STRIDE: int = 7_000_003

#: Most draws per drawn state: a pose at which a fixel overlaps the part is drawn again,
#: at most this many times the states asked for in all.
FUNNEL_ATTEMPTS: int = 100


def segment_count(plan: Plan) -> int:
    """The plan's segments: its moving ones and the hold."""
    return sum(1 for s in plan.segments if not s.hold) + 1


def run_model(run: RunResult):
    """The model a run was made under: its whole model when parameters other than
    friction varied, else its friction per fixel."""
    return run.model if run.model is not None else tuple(run.friction)


def entry_states(runs: Sequence[RunResult], first: int = 1
                 ) -> dict[int, list[tuple[tuple[float, ...], object]]]:
    """The entry states of each later segment in ``runs`` that started with segment
    ``first``, each with the model of its run: segment (1-based) -> (state, model).

    Parameters
    ----------
    runs : sequence of RunResult
        Runs with their ``entries`` (:func:`~.execution.trace`).
    first : int
        The segment the runs started with.

    Returns
    -------
    dict
        Segment -> its (entry state, model) pairs, in the runs' order.
    """
    out: dict[int, list[tuple[tuple[float, ...], object]]] = {}
    for r in runs:
        for j, state in enumerate(r.entries):
            out.setdefault(first + 1 + j, []).append((tuple(state), run_model(r)))
    return out


def hull(states: Sequence[Sequence[float]]) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The smallest box holding ``states``: (lo, hi) per axis."""
    a = np.asarray(states, dtype=float).reshape(-1, len(STATE_AXES))
    return tuple(map(float, a.min(axis=0))), tuple(map(float, a.max(axis=0)))


def sample_states(scene: Scene, entries: Sequence[Sequence[float]], tube: Sequence[float],
                  count: int, seed: int) -> list[tuple[int, tuple[float, ...]]]:
    """``count`` states drawn in the union of the boxes of half-widths ``tube`` around the
    ``entries`` (``default_rng(seed)``: an entry state uniformly, then a point uniformly
    in its box); a state whose pose overlaps a fixel is drawn again.

    Parameters
    ----------
    scene : Scene
        The scene (its part and fixels).
    entries : sequence of 6-sequences of float
        The entry states.
    tube : sequence of 6 float
        The boxes' half-widths per axis (m, m, rad, m/s, m/s, rad/s).
    count : int
        How many states.
    seed : int
        The seed.

    Returns
    -------
    list of (int, tuple of 6 float)
        Each drawn state with the index of the entry state it was drawn around; fewer
        than ``count`` when FUNNEL_ATTEMPTS * count draws did not find them (boxes that
        are nearly all overlap).
    """
    rng = np.random.default_rng(seed)
    e = np.asarray(entries, dtype=float).reshape(-1, len(STATE_AXES))
    h = np.asarray(tube, dtype=float)
    x0, y0, t0 = scene.pose
    out: list[tuple[int, tuple[float, ...]]] = []
    if not len(e):
        return out
    for _ in range(FUNNEL_ATTEMPTS * count):
        if len(out) >= count:
            break
        i = int(rng.integers(len(e)))
        state = e[i] + h * (2.0 * rng.random(len(STATE_AXES)) - 1.0)
        if start_scene(scene, (state[0] - x0, state[1] - y0, state[2] - t0)) is None:
            continue
        out.append((i, tuple(map(float, state))))
    return out


def tube_of(lo: Sequence[float], hi: Sequence[float], tube: float = FUNNEL_TUBE
            ) -> tuple[float, ...]:
    """The half-widths of the boxes around the entry states: per pose axis ``tube`` times
    the half-width of their box [lo, hi]; 0 on the velocity axes (a drawn state keeps
    the velocity of the entry state it is drawn around)."""
    return tuple(float(tube * 0.5 * (b - a)) if i < 3 else 0.0
                 for i, (a, b) in enumerate(zip(lo, hi)))


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
                            run_from: Callable, *, draws: int = FUNNEL_DRAWS,
                            seed: int = 0, beta: float = 1e-3, tube: float = FUNNEL_TUBE,
                            shrinks: int = FUNNEL_SHRINKS) -> tuple[SegmentFunnel, ...]:
    """The entry region of every segment after the first, each checked as a funnel of the
    plan's rest (module docstring), in segment order.

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose, and the fixels.
    plan : Plan
        The plan.
    region_runs : sequence of RunResult
        The runs that certified the start box (all passed), with their entry states.
    run_from : callable
        ``run_from(segment, states, models) -> list of RunResult``: the plan from
        ``segment`` on from each state (x, y, theta, vx, vy, omega) under its model, in
        order (region.py runs them in its worker processes).
    draws : int
        States drawn per entry region (>= 0; 0: the regions only, not checked).
    seed : int
        Seed of the drawn states.
    beta : float
        The scenario bound's confidence parameter.
    tube : float
        FUNNEL_TUBE: the entry region's boxes around the entry states.
    shrinks : int
        FUNNEL_SHRINKS: halvings of the tube tried while the region is not a funnel.

    Returns
    -------
    tuple of SegmentFunnel
        One per segment 2..n; empty for a plan of one segment.
    """
    n = segment_count(plan)
    pairs = entry_states(region_runs)
    funnels: list[SegmentFunnel] = []
    for k in range(2, n + 1):
        seen = [st for st, _ in pairs.get(k, [])]
        if not seen:
            funnels.append(SegmentFunnel(k, (0.0,) * 6, (0.0,) * 6, 0, 0, 0, beta,
                                         "no run entered the segment", tube))
            continue
        lo, hi = hull(seen)
        # each drawn state under the model of the run whose entry state it was drawn
        # around: the model is the world's, the same in every segment
        wider = ""  # the last tube that was not a funnel, with its count and failure
        for halving in range(shrinks + 1):
            t = tube / 2 ** halving
            k_seed = seed + FUNNEL_SEED_STRIDE * k + halving
            picked = (sample_states(scene, seen, tube_of(lo, hi, t), draws, k_seed)
                      if draws else [])
            drawn = [st for _, st in picked]
            models = [pairs[k][i][1] for i, _ in picked]
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
            if not draws or (drawn and passed == len(drawn)) or halving == shrinks:
                break
            wider = (f"at {100.0 * t:.3g} %: {passed} of {len(drawn)} drawn states "
                     f"seat; first failure: {failure}")
        funnels.append(SegmentFunnel(k, lo, hi, len(seen), len(drawn), passed, beta,
                                     failure, t, tuple(seen),
                                     tuple(m for _, m in pairs[k]), wider=wider,
                                     checks=halving + 1))
        # the images of this region's drawn states enter the later regions too
        for later, extra in entry_states([r for r in res if r.matches], k).items():
            pairs.setdefault(later, []).extend(extra)
    return tuple(funnels)
