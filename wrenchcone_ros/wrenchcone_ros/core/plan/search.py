# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The search for a plan whose guarantee holds on a moving body (:func:`plan_seating`).

The search is depth first over segments (:mod:`.segments`): at each pose the candidate
modes, best margin first, and for each the directions to try: the one of largest
worst-case margin over its own path, then the directions of the seat's holds found so
far that lie in the interval (one constant tilt through the contact event), then
interior points of the interval (DIRECTION_FRACTIONS). When the target contacts are
made, the hold segments (:func:`~.segments.hold_segments`) are tried, each with the
moving segments' force scaled by each of FORCE_SCALES (ease off: the same path from
rest, a slower arrival).

Every complete candidate is put to the capture test (:func:`capture`): the plan run in
the engine from the start, with inelastic impacts, for the nominal model and the
boundary models of the uncertainty (:func:`~.execution.capture_models`), and, for a
candidate whose margins are all positive, for the nominal model under each of the
engine settings ENGINE_VARIATIONS (time step, solver iterations, collision slop, each
scaled down and up); it passes when every run meets the contacts in the planned order
and comes to rest seated. A candidate
whose margins are all positive and that passes is returned: *guaranteed*. Every
rejected candidate goes to the plan's ``tried`` list with its reason. When a bound is
reached, or every candidate is rejected, the best candidate found is returned (not
guaranteed, with what is missing), or ``feasible`` False with the reasons.

**The search is bounded by work, not by seconds**, so that the same scene gives the
same plan on every machine, loaded or not, bit for bit (segments, directions, margins,
``tried``, reason): at most ``max_candidates`` complete candidates
(DEFAULT_MAX_CANDIDATES) are put to the capture test, and at most ``max_trials`` segments
(DEFAULT_MAX_TRIALS) are planned and simulated (:func:`~.segments.plan_segment`). The
defaults lie above what every task of the planner's test families and the documented
examples needs, so that they are ended by their candidates, not by a bound. Neither bound
cuts short the first descent (each step's best mode and direction, as far as the first
complete candidate or the first dead end): a plan the greedy search finds is always
found. A time budget is an opt-in cap only (``budget``, seconds of CPU time of the
searching thread, None by default): a plan it cut says so (``out_of_time``, ``reason``),
and another machine may find another plan.

When no candidate seats the part in its nominal run (a part that bounces off a stop
changes mode on the way, and no segment of one mode gets it there), the last resort is
one constant direction from the start (:meth:`_Search.constant`): the multiples of
CONSTANT_STEP in the seated pose's nominal hold intervals, each run in the engine; the
first that seats the part is a candidate like the others, its segments certified by the
cones only where they can be (a segment whose mode changes on the way has margin 0), so
it is guaranteed only if its margins are positive and it passes the capture test. This
stage is finite (one run per direction); the bounds above bound it too: when one has
been reached, the directions not yet run are noted in ``tried``.

The search's goal (``goal``): GOAL_GUARANTEED (the default) searches until a candidate
is guaranteed or a bound is reached; GOAL_SEATED stops at the first candidate whose
nominal run seats the part (guaranteed or not: what it lacks is stated as always). The
latter is for a caller who knows that no plan can be guaranteed, such as a fixture
design whose seat, fixed by its three pins, has no funnel: every candidate ends in that
seat, so a search for a guarantee could only run to its bound.

**The region search** (``start_region``; docs/planning.md, "From a region of starts"):
the first candidate that meets the goal (guaranteed; with GOAL_SEATED, seated in its
nominal run) is certified over the box (:func:`~.region.certify_region`). When the box
certified is not the whole asked one, the search does not stop there: it goes on as if
that candidate had been refuted (the same depth-first order: the next force scale, the
next hold, the next direction, the next mode), and each further candidate that meets the
goal is certified the same way (the same counts and seed), until one holds from the
whole box, REGION_CANDIDATES (``region_candidates``) have been certified, or the search
ends (no candidate left, or its work bounds, which count these candidates as before).
The plan returned is the one with the largest certified box: the largest fraction of
the asked volume, then the largest mean per-axis fraction (a box of zero volume can
still hold a turn), then a box at all (the scene's pose holds), then the earliest in the
search's order. ``plan.region`` lists every plan certified (``compared``) and which was
chosen; ``tried`` says the same in words. A search whose plan is not a candidate that
meets the goal (its best refuted candidate, or the constant direction) certifies that
plan alone, as does ``region_candidates`` = 1 (the first plan only, certified after the
search). The comparison is by counts, like the rest: the same inputs and seed give the
same plan on every machine, with any number of worker processes.
"""

from __future__ import annotations

import math
import multiprocessing
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

from ..scene import Scene
from ..directions import DirectionInterval
from ..simulate import DEFAULT_ENGINE, Actuator, EngineSettings
from ..uncertainty import NOMINAL, Uncertainty, UncertaintyError, as_uncertainty
from .execution import (
    ENGINE_VARIATIONS,
    capture_models,
    check_stop,
    execute,
    run_models,
    sample_models,
)
from .poses import project_pose
from .region_cones import check_region_cones
from .region import (
    REGION_BISECTIONS,
    REGION_GRID,
    certify_region,
    check_segment_funnels,
    run_region_samples,
)
from .segment_funnels import FUNNEL_DRAWS
from .results import (
    DEFAULT_RUNS,
    ENGINE_CHECK_PREFIX,
    DEFAULT_SEED,
    DEFAULT_WORKERS,
    Plan,
    PlanError,
    RegionCandidate,
    RegionCertificate,
    RunResult,
    Segment,
    StartRegion,
    fixels_text,
)
from .segments import (
    CONSTANT_STEP,
    DIRECTION_SETTLE,
    candidate_modes,
    constant_directions,
    constant_segment,
    hold_segments,
    plan_segment,
    robust_directions,
    simulate_segment,
)

#: Most segments a plan may have (the hold segment included).
MAX_SEGMENTS: int = 8

#: Default bound on the complete candidates a search puts to the capture test (module
#: docstring): above what every task of the planner's families and the documented
#: examples needs (the most, 21, by a disc of the arrival family), so that they end by
#: their candidates; the same plan on every machine.
DEFAULT_MAX_CANDIDATES: int = 40

#: Default bound on the segments a search plans and simulates (:func:`~.segments.
#: plan_segment` calls), the search's other unit of work (a dead end costs segments,
#: not candidates): above what every task of the families and the examples needs.
DEFAULT_MAX_TRIALS: int = 400

#: The time budget by default: none (an opt-in cap, in CPU s of the searching thread).
DEFAULT_BUDGET: float | None = None

#: Interior points of a mode's interval (fractions from its low end) tried after the
#: direction of largest margin and the seat's directions.
DIRECTION_FRACTIONS: tuple[float, ...] = (0.5, 0.2, 0.8)

#: The search's goals (module docstring): a guaranteed plan (searched for until a
#: bound is reached), or the first candidate whose nominal run seats the part.
GOAL_GUARANTEED: str = "guaranteed"
GOAL_SEATED: str = "seated"
GOALS: tuple[str, ...] = (GOAL_GUARANTEED, GOAL_SEATED)

#: Force scales (fractions of the actuator's force) of the moving segments tried for
#: each hold: the arrival's kinetic energy scales with them, the hold's force does not.
FORCE_SCALES: tuple[float, ...] = (1.0, 0.5, 0.25, 0.1)

#: Most plans the region search certifies (``region_candidates`` of
#: :func:`plan_seating`, with a start region): the search's first plan that meets the
#: goal, and, while none holds from the whole asked box, the next ones in the search's
#: order; the one with the largest certified region is returned. Each costs up to
#: 2 + 4 REGION_BISECTIONS boxes of runs (minutes for a box that must be shrunk).
REGION_CANDIDATES: int = 3


def _targets(scene: Scene, target) -> tuple[int, ...]:
    try:
        t = tuple(sorted({int(v) for v in target}))
    except (TypeError, ValueError):
        raise PlanError(f"target must be fixel numbers (1..{scene.n_fixels}), got "
                        f"{target!r}") from None
    if not t or t[0] < 1 or t[-1] > scene.n_fixels:
        raise PlanError(f"target must be fixel numbers 1..{scene.n_fixels} (1-based, as "
                        f"in the scene file), got {list(target)!r}")
    return t


def describe(segments: Sequence[Segment]) -> str:
    """'la -40.10 deg x0.5, nn -35.20 deg': modes, directions, force scales."""
    return ", ".join(f"{s.mode} {math.degrees(s.direction):.2f} deg"
                     + ("" if s.scale == 1.0 else f" x{s.scale:g}") for s in segments)


def capture(scene: Scene, plan: Plan, uncertainty: Uncertainty | None,
            should_stop: Callable[[], bool] | None = None,
            engines: Sequence[EngineSettings] = ()) -> tuple[RunResult, ...]:
    """The capture test's runs (module docstring): the nominal model first, then the
    boundary models, then the nominal model under each of ``engines`` (other engine
    settings); it stops at the first run that does not seat as planned.

    Parameters
    ----------
    scene : Scene
        The part at its start pose.
    plan : Plan
        The plan.
    uncertainty : Uncertainty or None
        The model set (None or NOMINAL: the nominal model only).
    should_stop : callable or None, optional
        Polled between runs; True cancels.
    engines : sequence of EngineSettings, optional
        Engine settings the nominal model is also run under (the search passes
        ENGINE_VARIATIONS for a candidate whose margins are all positive).

    Returns
    -------
    tuple of RunResult
        The runs, up to the first that does not seat as planned.

    Raises
    ------
    PlanCancelled
        ``should_stop()`` returned True.
    """
    out = []
    runs = [(label, model, DEFAULT_ENGINE)
            for label, model in capture_models(scene, as_uncertainty(uncertainty))]
    runs += [(ENGINE_CHECK_PREFIX + e.label, runs[0][1], e) for e in engines]
    for label, model, engine in runs:
        check_stop(should_stop)
        r = execute(scene, plan, model, label=label, engine=engine)
        out.append(r)
        if not r.seats_as_planned:
            break
    return tuple(out)


class _BoundReached(Exception):
    """A bound was reached: max_candidates or max_trials (``capped``), or the opt-in
    time budget (``out_of_time``)."""


class _Seated(Exception):
    """GOAL_SEATED: a candidate seats the part in its nominal run (it is the fallback)."""


class _Search:
    """The state of one search (module docstring)."""

    def __init__(self, scene: Scene, target: tuple[int, ...], actuator: Actuator,
                 uncertainty: Uncertainty, budget: float | None,
                 should_stop: Callable[[], bool] | None,
                 on_segment: Callable[[int], None] | None,
                 goal: str = GOAL_GUARANTEED,
                 max_candidates: int | None = DEFAULT_MAX_CANDIDATES,
                 max_trials: int | None = DEFAULT_MAX_TRIALS,
                 accept: Callable[[Plan], bool] | None = None) -> None:
        self.scene, self.target, self.act, self.unc = scene, target, actuator, uncertainty
        # the region search's hook (plan_seating): called with each candidate that meets
        # the goal; True ends the search with it, False goes on (None: always True)
        self.accept = accept
        self.goal, self.max_candidates, self.max_trials = goal, max_candidates, max_trials
        self.target0 = {i - 1 for i in target}
        # the opt-in cap: CPU s of this thread (module docstring); None: no deadline
        self.deadline = None if budget is None else time.thread_time() + budget
        self.should_stop, self.on_segment = should_stop, on_segment
        self.tried: list[str] = []
        self.hints: list[float] = []
        self.reason = ""
        self.fallback: Plan | None = None
        self.constant_plan: Plan | None = None  # the constant stage's candidate
        self.candidates = 0  # complete candidates put to the capture test
        self.trials = 0  # segments planned and simulated (plan_segment calls)
        self.first = True  # on the first descent (until a candidate or a dead end)
        self.out_of_time = False  # the opt-in time budget ran out
        self.capped = ""  # the work bound reached: "candidates" or "trials" ("": none)
        self.friction = tuple(tuple(p) for p in uncertainty.friction_intervals(scene))

    def tick(self) -> None:
        """Cancelled: PlanCancelled; a bound reached (max_candidates, max_trials, the
        opt-in time budget): _BoundReached, but never on the first descent (the greedy
        plan, which no bound cuts short)."""
        check_stop(self.should_stop)
        if self.first:
            return
        if self.max_candidates is not None and self.candidates >= self.max_candidates:
            self.capped = "candidates"
            raise _BoundReached
        if self.max_trials is not None and self.trials >= self.max_trials:
            self.capped = "trials"
            raise _BoundReached
        if self.deadline is not None and time.thread_time() > self.deadline:
            self.out_of_time = True
            raise _BoundReached

    def bound_text(self) -> str:
        """The bound that ended the search, in words ("" when none did)."""
        if self.capped == "candidates":
            return f"the search's candidate limit ({self.max_candidates}) was reached"
        if self.capped == "trials":
            return (f"the search's segment limit ({self.max_trials} segments planned) was "
                    "reached")
        if self.out_of_time:
            return "the search's time budget ran out"
        return ""

    def done(self, plan: Plan) -> bool:
        """Whether a candidate that meets the goal ends the search (always, unless the
        region search's hook says to go on)."""
        return self.accept is None or self.accept(plan)

    def note(self, step: int, why: str) -> None:
        """The first failure met is the plan's reason when nothing is found."""
        if not self.reason:
            self.reason = f"step {step}: {why}"

    def directions(self, iv, done: list[float]) -> Iterator[float | None]:
        yield None
        for phi in list(self.hints) + [iv.lo + f * (iv.hi - iv.lo)
                                       for f in DIRECTION_FRACTIONS]:
            if iv.contains(phi) and not any(abs(phi - q) <= DIRECTION_SETTLE for q in done):
                yield phi

    def extend(self, state: Scene, segments: list[Segment]) -> Plan | None:
        self.tick()
        step = len(segments) + 1
        contact = {i for i, c in enumerate(state.in_contact) if c}
        if self.target0 <= contact:
            return self.seat(state, segments)
        if step >= MAX_SEGMENTS:
            self.note(step, f"no plan within {MAX_SEGMENTS} segments")
            return None
        kept = sorted(contact)
        point = self.act.directions_point
        scored = []
        for mode in candidate_modes(state.in_contact, self.target0):
            scored += [(iv.margin, mode, iv)
                       for iv in robust_directions(state, mode, point, self.unc)]
        scored.sort(key=lambda x: -x[0])
        need = fixels_text(sorted(self.target0 - contact))
        if not scored:
            self.first = False
            self.note(step, f"no direction gives a mode that keeps "
                      f"{fixels_text(kept) if kept else 'the contacts'} and approaches "
                      f"{need}" + (" for every model of the uncertainty"
                                   if self.unc != NOMINAL else ""))
            return None
        why_not = []
        for _m, mode, iv in scored:
            done: list[float] = []
            for phi in self.directions(iv, done):
                self.tick()
                self.trials += 1
                seg, why = plan_segment(state, mode, iv, self.act, self.unc, kept,
                                        self.target0, phi)
                if seg is None:
                    self.tried.append(f"step {step}: {why}")
                    why_not.append(why)
                    if phi is None:
                        break  # the mode fails from its best direction: next mode
                    continue
                if any(abs(seg.direction - q) <= DIRECTION_SETTLE for q in done):
                    continue
                done.append(seg.direction)
                if self.on_segment is not None:
                    self.on_segment(step)
                found = self.extend(state.with_pose(*seg.end_pose), segments + [seg])
                if found is not None:
                    return found
        self.first = False
        self.note(step, f"no candidate mode reaches {need} in the simulation "
                  f"({'; '.join(why_not[:6]) or 'every candidate refuted later'})")
        return None

    def seat(self, state: Scene, segments: list[Segment]) -> Plan | None:
        step = len(segments) + 1
        previous = segments[-1].direction if segments else None
        holds, why = hold_segments(state, previous, self.act, self.unc, self.target0)
        if not holds:
            self.first = False
            self.note(step, why)
            return None
        # a hold without the funnel is never guaranteed; while no candidate seats the
        # part in its nominal run, the first such one is run at once (one run), so that
        # a plan the engine seats is at hand before the bounds are spent on the others
        weak = [h for h in holds if h.margin <= 0]
        if weak and len(weak) < len(holds) and (
                self.fallback is None or not self.fallback.nominal.success):
            first = self.first
            self.try_plan(segments, weak[0], 1.0, why)
            self.first = first  # the first descent goes on to the first full candidate
            holds = [h for h in holds if h is not weak[0]]
        for hold in holds:
            if not any(abs(hold.direction - q) <= DIRECTION_SETTLE for q in self.hints):
                self.hints.append(hold.direction)
            for scale in (FORCE_SCALES if segments else (1.0,)):
                self.tick()
                plan = self.try_plan(segments, hold, scale, why)
                if plan.guaranteed and self.done(plan):
                    return plan
                if not plan.margins_positive:
                    break  # a smaller force changes no margin
        return None

    def try_plan(self, segments: list[Segment], hold: Segment, scale: float, why: str
                 ) -> Plan:
        """One complete candidate: the moving segments at force ``scale``, then the
        hold, put to the capture test (the nominal model alone when a margin is not
        positive); a refuted one is noted in ``tried`` and kept if it is the best."""
        segs = tuple([replace(s, scale=scale) for s in segments] + [hold])
        plan = Plan(segs, True, why, self.target, self.act, self.friction,
                    uncertainty=self.unc)
        self.candidates += 1
        if self.on_segment is not None:
            self.on_segment(len(segs))
        checks = capture(self.scene, plan, self.unc if plan.margins_positive else NOMINAL,
                         self.should_stop,
                         ENGINE_VARIATIONS if plan.margins_positive else ())
        plan = replace(plan, checks=checks, nominal=checks[0])
        self.first = False
        if not plan.guaranteed:
            self.tried.append(f"plan {describe(segs)}: not guaranteed: "
                              + "; ".join(plan.missing))
            self.keep(plan)
            if self.goal == GOAL_SEATED and plan.nominal.success and self.done(plan):
                raise _Seated
        return plan

    def constant(self) -> Plan | None:
        """The last resort when no candidate seats the part in its nominal run: one
        constant direction from the start to the seat. The directions of
        :func:`~.segments.constant_directions` (at the seated pose found from the start
        pose, :func:`~.poses.project_pose`), each run in the engine (nominal model) as a
        one-direction plan; the first that seats the part becomes a candidate, its
        segments certified by the cones where they can be
        (:func:`~.segments.constant_segment`, the hold and its funnel under that
        direction), put to the capture test (the boundary models too when its margins
        are positive). A guaranteed one is returned, any other kept as the best refuted
        candidate when it is better. The search's bounds bound this stage (checked before
        each direction): when one is reached, ``tried`` says how many directions were
        run."""
        target0 = sorted(self.target0)
        pose = project_pose(self.scene, self.scene.pose, target0)
        seat = None if pose is None else self.scene.with_pose(*pose)
        if seat is None or not all(seat.in_contact[i] for i in target0):
            self.tried.append("constant directions: no seated pose found near the start "
                              "pose")
            return None
        contact = {i for i, c in enumerate(self.scene.in_contact) if c}
        todo = tuple(i + 1 for i in target0 if i not in contact)
        dirs = constant_directions(seat, self.act.directions_point, self.scene.pose[2])
        nominal = [self.scene.mu(i) for i in range(self.scene.n_fixels)]
        for k, phi in enumerate(dirs):
            try:
                self.tick()
            except _BoundReached:
                self.tried.append(f"constant directions: {self.bound_text()} after {k} "
                                  f"of {len(dirs)}")
                return None
            # the part at rest that never starts to move, or never meets a fixel, is not
            # seated: a short run to the first contact event says so
            if todo and simulate_segment(self.scene, self.act, phi, [], nominal
                                         ).reason != "reached":
                continue
            run = execute(self.scene, self._one_direction(phi, todo), label="nominal")
            if not run.success:
                continue
            plan = self._constant_plan(phi, run.final_pose)
            if plan is None:
                continue
            if plan.guaranteed:
                return plan
            self.tried.append(f"plan {describe(plan.segments)} (one constant direction): "
                              "not guaranteed: " + "; ".join(plan.missing))
            self.constant_plan = plan
            self.keep(plan)
            return None
        self.tried.append(f"constant directions: none of {len(dirs)} (every "
                          f"{math.degrees(CONSTANT_STEP):g} deg in the seated pose's hold "
                          "intervals) seats the part in the nominal model")
        return None

    def _one_direction(self, phi: float, todo: tuple[int, ...]) -> Plan:
        """A plan of one direction phi, to run: move until the ``todo`` fixels (1-based)
        are reached, then hold, all under phi (no margins: a probe, never returned)."""
        pose = tuple(self.scene.pose)

        def segment(hold: bool) -> Segment:
            return Segment(mode="", interval=DirectionInterval(phi, phi, phi, 0.0),
                           direction=phi, margin=0.0, start_pose=pose, end_pose=pose,
                           event="", predicted_event="", reached=() if hold else todo,
                           hold=hold)
        return Plan(((segment(False),) if todo else ()) + (segment(True),), True, "",
                    self.target, self.act, self.friction)

    def _constant_plan(self, phi: float, final_pose) -> Plan | None:
        """The candidate of constant direction phi that seated the part at
        ``final_pose`` in the engine: its moving segment and its hold, both under phi,
        each with its interval and worst-case margin, put to the capture test."""
        pose = project_pose(self.scene, final_pose, sorted(self.target0)) or final_pose
        seat = self.scene.with_pose(*pose)
        holds, why = hold_segments(seat, phi, self.act, self.unc, self.target0, only=phi)
        if not holds:
            return None
        segs = ([constant_segment(self.scene, phi, self.act, self.unc, self.target0, pose)]
                if not self.target0 <= {i for i, c in enumerate(self.scene.in_contact) if c}
                else [])
        plan = Plan(tuple(segs) + (holds[0],), True, why, self.target, self.act,
                    self.friction, uncertainty=self.unc)
        self.candidates += 1
        checks = capture(self.scene, plan, self.unc if plan.margins_positive else None,
                         self.should_stop,
                         ENGINE_VARIATIONS if plan.margins_positive else ())
        return replace(plan, checks=checks, nominal=checks[0])

    def keep(self, plan: Plan) -> None:
        """The best refuted candidate: seated in the nominal run first, then positive
        margins, then the largest worst margin."""
        def key(p: Plan):
            return (p.nominal.success, p.margins_positive, p.worst_margin)
        if self.fallback is None or key(plan) > key(self.fallback):
            self.fallback = plan


def plan_seating(scene: Scene, target: Sequence[int], actuator: Actuator | str | None = None,
                 uncertainty=None, *, runs: int = DEFAULT_RUNS, seed: int = DEFAULT_SEED,
                 workers: int = DEFAULT_WORKERS,
                 progress: Callable[[int, int], None] | None = None,
                 simulate_runs: bool = True,
                 on_segment: Callable[[int], None] | None = None,
                 should_stop: Callable[[], bool] | None = None,
                 start_method: str | None = None,
                 budget: float | None = DEFAULT_BUDGET, pool=None,
                 goal: str = GOAL_GUARANTEED,
                 max_candidates: int | None = DEFAULT_MAX_CANDIDATES,
                 max_trials: int | None = DEFAULT_MAX_TRIALS,
                 start_region=None, region_grid: int = REGION_GRID,
                 region_bisections: int = REGION_BISECTIONS,
                 region_candidates: int = REGION_CANDIDATES,
                 segment_funnel_draws: int = FUNNEL_DRAWS) -> Plan:
    """A plan of force directions that seats the part on the ``target`` fixels, and its
    evidence from the simulation.

    Each segment holds one contact mode; its interval is the set of force directions
    whose wrench lies in that mode's wrench cone (Balkcom and Trinkle, 2002, Theorem 1)
    along the segment's simulated path, for every model of ``uncertainty``; the last
    segment holds the part seated.

    Parameters
    ----------
    scene : Scene
        The part at its start pose and the fixels.
    target : sequence of int
        The fixels (1-based, as in the scene file) that must all touch the seated part.
    actuator : Actuator or str, optional
        ``"tilt"`` (default: gravity, by tilting the fixture), ``"spring:X,Y"`` (a pull at
        (X, Y) m in the workpiece frame) or an :class:`~.simulate.Actuator`.
    uncertainty : Uncertainty or tuple, optional
        None (the nominal model), an :class:`~.uncertainty.Uncertainty` (friction per
        fixel, mass, inertia, centre of mass, contact-normal error), or a friction
        interval (lo, hi) for every fixel, or one per fixel.
    runs : int
        Sampled models (every uncertain parameter drawn, seeded by ``seed``) the plan is
        simulated in afterwards; 0 or ``simulate_runs=False`` skips them (the capture
        test's runs are part of planning and always made).
    seed : int
        Seed of the sampled models.
    workers : int
        Processes the sampled runs use.
    progress : callable, optional
        ``progress(done, total)`` after each sampled run.
    simulate_runs : bool
        False: no sampled runs.
    on_segment : callable, optional
        ``on_segment(k)`` when a k-th segment is planned.
    should_stop : callable, optional
        Polled between candidates and between runs; True raises :class:`PlanCancelled`.
    start_method : str, optional
        How the worker processes start (multiprocessing; None: the platform's default; a
        program with threads of its own, a ROS node, passes ``"spawn"``).
    budget : float or None
        An opt-in cap on the search's time (s of CPU time of the calling thread; None,
        the default: none). A search it ends says so (``out_of_time``, ``reason``), and
        another machine may find another plan; the first descent is never cut short.
    pool : concurrent.futures.Executor, optional
        Worker processes the caller owns and keeps (a ROS node's, started once), used
        for the runs instead of a pool made for this call.
    goal : str
        GOAL_GUARANTEED (``"guaranteed"``, default): search until a candidate is
        guaranteed or a bound is reached; GOAL_SEATED (``"seated"``): stop at the first
        candidate whose nominal run seats the part, for a caller who knows that no plan
        can be guaranteed (module docstring).
    max_candidates : int or None
        The most complete candidates the search puts to the capture test
        (DEFAULT_MAX_CANDIDATES; None: no limit): a bound on its work that gives the same
        plan on every machine (module docstring); the first descent is never cut short.
    max_trials : int or None
        The most segments the search plans and simulates (DEFAULT_MAX_TRIALS; None: no
        limit), the same kind of bound.
    start_region : StartRegion or sequence of 3 float, optional
        A box of start poses around the scene's pose, half-widths (dx m, dy m, dtheta
        rad). The plan found from the scene's pose is then run from every point of a
        cover of the box under every model of the capture test, and the box is shrunk
        per axis until it holds (:func:`~.region.certify_region`); while the box
        certified is not the whole asked one, the search goes on to its next plans
        (``region_candidates``, module docstring) and returns the one with the largest
        certified box: ``plan.region`` says what holds and what was compared,
        ``plan.start_region`` is the certified box; the sampled runs then start at poses
        drawn uniformly in the certified box. None (default): the scene's pose only.
    region_grid : int
        Cover points per axis of the start region (REGION_GRID).
    region_bisections : int
        Bisection steps per stage of the region's shrinking (REGION_BISECTIONS).
    region_candidates : int
        With a start region, the most plans the search certifies (REGION_CANDIDATES;
        >= 1): its first plan that meets the goal, then, while none holds from the
        whole asked box, the next ones in the search's order. 1: the first plan only.
    segment_funnel_draws : int
        With a start region, states drawn in each later segment's entry box to check it
        as a funnel of the plan's rest (FUNNEL_DRAWS; 0: the boxes only;
        :mod:`.segment_funnels`).

    Returns
    -------
    Plan
        ``guaranteed`` when its margins are positive and it passed the capture test;
        otherwise ``missing`` says what the guarantee lacks. ``feasible`` is False, with
        the ``reason``, when no plan was found.

    Raises
    ------
    PlanError
        A bad argument (not a Scene, an unknown target fixel, a negative ``runs``, a
        budget that is neither None nor a positive number of seconds, an unknown goal, a
        ``max_candidates`` or ``max_trials`` that is neither None nor a whole number
        >= 1, a bad start region, a ``region_candidates`` that is not a whole number
        >= 1), with what is allowed.
    PlanCancelled
        ``should_stop()`` returned True.
    SimulationUnavailable
        pymunk is not installed (``pip install .[sim]``).
    """
    if not isinstance(scene, Scene):
        raise PlanError(f"scene must be a Scene, got {type(scene).__name__}")
    act = Actuator.parse(actuator)
    t1 = _targets(scene, target)
    try:
        unc = as_uncertainty(uncertainty, scene)
    except (UncertaintyError, TypeError) as exc:
        raise PlanError(f"uncertainty: {exc}") from None
    if not isinstance(runs, int) or isinstance(runs, bool) or runs < 0:
        raise PlanError(f"runs must be a whole number >= 0, got {runs!r}")
    if budget is not None and (isinstance(budget, bool) or not isinstance(
            budget, (int, float)) or not math.isfinite(budget) or budget <= 0):
        raise PlanError(f"budget must be None (no time cap) or a positive number of "
                        f"seconds, got {budget!r}")
    if goal not in GOALS:
        raise PlanError(f"goal must be one of {list(GOALS)}, got {goal!r}")
    for name, value in (("max_candidates", max_candidates), ("max_trials", max_trials)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                                  or value < 1):
            raise PlanError(f"{name} must be None (no limit) or a whole number >= 1, got "
                            f"{value!r}")
    region = None if start_region is None else StartRegion.of(start_region)
    for name, value, least in (("region_grid", region_grid, 1),
                               ("region_bisections", region_bisections, 0),
                               ("region_candidates", region_candidates, 1),
                               ("segment_funnel_draws", segment_funnel_draws, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise PlanError(f"{name} must be a whole number >= {least}, got {value!r}")
    compare = region is not None and region_candidates > 1
    own_pool = None
    if compare and pool is None and workers > 1:
        # one set of worker processes for every plan the region search certifies
        own_pool = ProcessPoolExecutor(max_workers=workers,
                                       mp_context=multiprocessing.get_context(start_method))
    try:
        return _plan_seating(scene, t1, act, unc, runs, seed, workers, progress,
                             simulate_runs, on_segment, should_stop, start_method, budget,
                             pool if own_pool is None else own_pool, goal, max_candidates,
                             max_trials, region, region_grid, region_bisections,
                             region_candidates if compare else 1, segment_funnel_draws)
    finally:
        if own_pool is not None:
            own_pool.shutdown(wait=True, cancel_futures=True)


def _without_evidence(cert: RegionCertificate) -> RegionCertificate:
    """The certificate without the runs behind it (nor its compared plans'): a plan is
    sent to worker processes with each run."""
    return replace(cert, evidence=(), compared=tuple(
        replace(c, certificate=replace(c.certificate, evidence=())) for c in cert.compared))


def _region_key(cert: RegionCertificate, index: int) -> tuple:
    """The region search's order of plans (the largest first): the certified fraction of
    the asked volume, then the mean per-axis fraction (:attr:`~.results.
    RegionCertificate.axis_fraction`), then whether the scene's pose itself holds, then
    the search's order (the earliest)."""
    return (cert.fraction, cert.axis_fraction, cert.certified is not None, -index)


def _region_text(cert: RegionCertificate) -> str:
    """'38.0 % of the asked volume, 72.9 % per axis (+-1.5 mm x ...)'."""
    box = "no box" if cert.certified is None else cert.certified.text()
    return (f"{100.0 * cert.fraction:.1f} % of the asked volume, "
            f"{100.0 * cert.axis_fraction:.1f} % per axis ({box})")


def _plan_seating(scene, t1, act, unc, runs, seed, workers, progress, simulate_runs,
                  on_segment, should_stop, start_method, budget, pool, goal,
                  max_candidates, max_trials, region, region_grid, region_bisections,
                  region_candidates, segment_funnel_draws) -> Plan:
    """:func:`plan_seating` after its arguments are checked (``region_candidates`` 1: the
    search's plan certified alone)."""
    def certify(p: Plan) -> RegionCertificate:
        return certify_region(scene, p, region, unc, grid=region_grid,
                              bisections=region_bisections, seed=seed, workers=workers,
                              pool=pool, start_method=start_method, should_stop=should_stop)

    # the region search (region_candidates > 1): each candidate that meets the goal is
    # certified; the search goes on until one holds from the whole box or
    # region_candidates have been certified (or it ends)
    compared: list[tuple[Plan, RegionCertificate, int]] = []

    def accept(p: Plan) -> bool:
        cert = certify(p)
        compared.append((p, cert, search.candidates))
        search.tried.append(f"region: candidate {len(compared)} of at most "
                            f"{region_candidates} (plan {describe(p.segments)}; search "
                            f"candidate {search.candidates}) certified {_region_text(cert)}")
        return cert.whole or len(compared) >= region_candidates

    search = _Search(scene, t1, act, unc, None if budget is None else float(budget),
                     should_stop, on_segment, goal, max_candidates, max_trials,
                     accept if region_candidates > 1 else None)
    try:
        plan = search.extend(scene, [])
    except _BoundReached:
        plan = None
    except _Seated:  # the fallback seats the part in its nominal run
        plan = None
        search.tried.append(f"goal {GOAL_SEATED!r}: the search stopped at the first "
                            "candidate its nominal run seats" if not compared else
                            f"goal {GOAL_SEATED!r}: the search stopped at the region "
                            f"search's last candidate ({len(compared)} certified)")
    cones = search.reason  # the first dead end of the search, before the constant stage

    def spent_text() -> str:
        if search.out_of_time:
            return (f"the search's time budget ({budget:g} s) ran out after "
                    f"{search.candidates} candidate plan(s)")
        return search.bound_text()

    spent = spent_text()
    chosen = None
    if compared:
        # the region search's answer: the plan with the largest certified region
        best = max(range(len(compared)), key=lambda i: _region_key(compared[i][1], i))
        plan, cert, _ = compared[best]
        ended = (f"it ended at the region search's bound ({region_candidates} plans)"
                 if len(compared) >= region_candidates and not compared[-1][1].whole
                 else "the last holds from the whole box" if compared[-1][1].whole
                 else f"the search ended ({spent})" if spent
                 else "the search had no other candidate")
        search.tried.append(
            f"region: {len(compared)} candidate plan(s) certified (at most "
            f"{region_candidates}; {ended}); chosen: candidate {best + 1} (plan "
            f"{describe(plan.segments)}), {_region_text(cert)}: the largest certified "
            "fraction of the asked volume, then the largest mean per-axis fraction, "
            "then the earliest")
        chosen = replace(cert, chosen=best + 1, limit=region_candidates, compared=tuple(
            RegionCandidate(i + 1, k, describe(p.segments), p.guaranteed, c)
            for i, (p, c, k) in enumerate(compared)))
        if not plan.guaranteed:  # GOAL_SEATED: a candidate the nominal run seats
            plan = replace(plan, reason="; ".join(filter(None, [
                "not guaranteed: " + "; ".join(plan.missing), plan.reason, spent])))
    elif plan is None and (search.fallback is None or not search.fallback.nominal.success):
        plan = search.constant()
        spent = spent_text()  # the constant stage is bounded by the same counts
    if plan is None and search.fallback is not None:
        p = search.fallback
        plan = replace(p, reason="; ".join(filter(None, [
            "not guaranteed: " + "; ".join(p.missing), p.reason, spent,
            f"the search's first dead end: {cones}"
            if cones and p is search.constant_plan else ""])))
    if plan is None:
        return Plan((), False, "; ".join(filter(None, [search.reason, spent]))
                    or "no plan found", t1, act, search.friction, seed=seed,
                    tried=tuple(search.tried), uncertainty=unc,
                    out_of_time=search.out_of_time, candidates=search.candidates,
                    trials=search.trials)
    if region is not None and chosen is None:
        chosen = certify(plan)
        if region_candidates > 1:
            # no candidate met the goal: the search's plan (its best refuted candidate,
            # or the constant direction) is the only one to certify
            search.tried.append(
                f"region: no candidate met the goal {goal!r}; the search's plan (plan "
                f"{describe(plan.segments)}) certified alone, {_region_text(chosen)}")
            alone = RegionCandidate(1, 0, describe(plan.segments), plan.guaranteed, chosen)
            chosen = replace(chosen, chosen=1, limit=region_candidates, compared=(alone,))
    plan = replace(plan, seed=seed, tried=tuple(search.tried),
                   out_of_time=search.out_of_time, candidates=search.candidates,
                   trials=search.trials)
    if chosen is not None:
        if chosen.certified is not None:
            # each later segment's entry box, checked as a funnel of the plan's rest
            chosen = check_segment_funnels(
                scene, plan, chosen, draws=segment_funnel_draws, seed=seed,
                workers=workers, pool=pool, start_method=start_method,
                should_stop=should_stop)
            # where the part rests on a segment's contacts, the cones decide
            chosen = check_region_cones(scene, plan, chosen)
        plan = replace(plan, region=_without_evidence(chosen))
    box = plan.start_region
    if box is not None and box != StartRegion(0.0, 0.0, 0.0) and simulate_runs and runs:
        # starts drawn uniformly in the certified box, each with a sampled model
        check_stop(should_stop)
        plan = replace(plan, runs=tuple(run_region_samples(
            scene, plan, box, unc, runs, seed, workers, progress, should_stop,
            start_method, pool=pool)))
    elif unc != NOMINAL and simulate_runs and runs:  # no model set given: nothing to sample
        check_stop(should_stop)
        results = tuple(run_models(scene, plan, sample_models(scene, unc, runs, seed),
                                   workers, progress, should_stop, start_method,
                                   pool=pool))
        plan = replace(plan, runs=results)
    return plan
