# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""One plan for a region of start poses (:func:`certify_region`), and runs from sampled
starts (:func:`sample_starts`, :func:`run_starts`).

A gripper or a chute does not put a part at one pose: it lands within a few millimetres
and degrees. A :class:`~.results.StartRegion` is a box of poses around the scene's pose
(x +- dx, y +- dy, theta +- dtheta); its poses at which a fixel overlaps the part are
not starts, the others are (the part at rest there).

**The method** (docs/planning.md, "From a region of starts"): the plan is one the
search found from the scene's pose (the search certifies up to REGION_CANDIDATES of its
plans and keeps the one with the largest box: :mod:`.search`, "The region search";
what follows is about one plan); :func:`certify_region` runs it open loop in the
engine, from every point of a **cover** of the box (a grid of REGION_GRID evenly spaced
values per axis, from -1 to 1 times the half-width, the boundary points first), under
every model of the capture test (the nominal and the boundary models of the
uncertainty, :func:`~.execution.capture_models`, and the nominal one under
ENGINE_VARIATIONS) and under REGION_SAMPLED_MODELS models drawn from the uncertainty;
and from REGION_DRAWS starts drawn uniformly in the box, each with a model drawn from
the uncertainty (the scenario part). A run passes when the part comes to rest seated with the plan's
contact events in the plan's order (landing on a fixel the plan starts on is allowed: a
start above the pins falls onto them first). The box holds when every run passes.

When the asked box does not hold, it is shrunk: first all half-widths together by the
same fraction, by REGION_BISECTIONS steps of bisection between 0 (the scene's pose) and
1, then each axis in turn (x, y, theta) grown back towards the asked half-width by as
many steps, the others kept. The certified box is the last box that held, and the claim
is exactly: every point of its cover seats the part under every model run (between
cover points nothing is proved), and the drawn starts all seat: if more than eps of the
(start, model) pairs drawn uniformly failed, that would have happened with probability
at most beta per box checked (eps from the number of draws and REGION_BETA, the
zero-failure bound). The work is bounded by counts: at most 2 + 4 REGION_BISECTIONS boxes, each
at most REGION_GRID ** 3 cover points times the models, so the same scene gives the same
region on every machine.
"""

from __future__ import annotations

import itertools
import math
import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import replace

import numpy as np

from ..scene import Scene
from ..scene_yaml import scene_from_dict
from ..simulate import DEFAULT_ENGINE, EngineSettings
from ..uncertainty import Model, Uncertainty
from ..uncertainty import NOMINAL
from .segment_funnels import FUNNEL_DRAWS, as_planned_from, certify_segment_funnels
from .poses import start_scene
from .execution import ENGINE_VARIATIONS, capture_models, check_stop, sample_models, trace
from .results import (
    DEFAULT_WORKERS,
    ENGINE_CHECK_PREFIX,
    Plan,
    PlanError,
    RegionCertificate,
    RunResult,
    StartRegion,
)

#: Cover points per axis of a start region (an odd number puts one on the scene's pose).
REGION_GRID: int = 5

#: Models drawn from the uncertainty (:func:`~.execution.sample_models`, seeded) that
#: each cover point is also run under, beside the capture test's: the boundary models
#: do not bound the models inside the set from every start (a disc lifted a fraction of
#: a millimetre off its pin is lost with one pin's mu low and the other's high).
REGION_SAMPLED_MODELS: int = 8

#: The scenario bound of the uniformly drawn starts (dimensionless): each box is also run
#: from REGION_DRAWS = ceil(ln(REGION_BETA) / ln(1 - REGION_EPSILON)) starts drawn
#: uniformly in it, each with a model drawn from the uncertainty; when all seat, a box
#: in which more than REGION_EPSILON of such draws fail would have passed with
#: probability at most REGION_BETA.
REGION_EPSILON: float = 0.01
REGION_BETA: float = 1e-3
REGION_DRAWS: int = math.ceil(math.log(REGION_BETA) / math.log(1.0 - REGION_EPSILON))

#: The seeds of a box's drawn starts: the search's seed plus this times the box's place
#: in the order the boxes are checked (1, 2, ...).
DRAW_SEED_STRIDE: int = 1_000_003

#: Bisection steps per stage of the shrinking (the common fraction, then each axis): the
#: certified half-widths are found to 1 / 2 ** REGION_BISECTIONS of the asked ones.
REGION_BISECTIONS: int = 3

#: Runs handed to the worker processes at once; a box stops at the first batch with a
#: failed run (the verdict does not depend on the batch: every run before the first
#: failure, in the cover's order, passed).
REGION_BATCH: int = 16

#: Most draws per sampled start (:func:`sample_starts`): a draw that overlaps a fixel is
#: drawn again, at most this many times the starts asked for in all.
SAMPLE_ATTEMPTS: int = 100


def cover(region: StartRegion, grid: int = REGION_GRID) -> list[tuple[float, float, float]]:
    """The cover of a start region: offsets (dx m, dy m, dtheta rad) from the scene's
    pose, ``grid`` evenly spaced values from -1 to 1 times each half-width (one value, 0,
    on an axis of half-width 0), the points farthest from the centre (in the box's
    normalised max-norm) first, then in lexicographic order.

    Parameters
    ----------
    region : StartRegion
        The box.
    grid : int
        Points per axis (>= 1).

    Returns
    -------
    list of (float, float, float)
        The offsets.
    """
    axes = []
    for h in region.half_widths:
        axes.append([0.0] if h == 0.0 or grid == 1 else
                    [float(v) * h for v in np.linspace(-1.0, 1.0, grid)])
    pts = list(itertools.product(*axes))

    def key(p):
        r = max((abs(v) / h for v, h in zip(p, region.half_widths) if h > 0), default=0.0)
        return (-r, p)
    return sorted(pts, key=key)


def as_planned(plan: Plan, start_contacts: set[int], run: RunResult) -> bool:
    """Whether a run from a start of a region seats the part as planned: it succeeded,
    and its contact events are the plan's, in the plan's order, apart from landing on
    fixels the plan starts on (``start_contacts``, 1-based: a start above them falls onto
    them first).

    Parameters
    ----------
    plan : Plan
        The plan.
    start_contacts : set of int
        The fixels (1-based) the part touches at the scene's pose.
    run : RunResult
        The run.

    Returns
    -------
    bool
    """
    if not run.success:
        return False
    group = {e: j for j, s in enumerate(plan.segments) if not s.hold for e in s.reached}
    if any(e not in group and e not in start_contacts for e in run.events):
        return False
    order = [group[e] for e in run.events if e in group]
    return set(e for e in run.events if e in group) == set(group) and order == sorted(order)


def _job(args) -> RunResult:
    scene_dict, plan, *job = args
    return _run(scene_from_dict(scene_dict), plan, *job)


def _run(scene: Scene, plan: Plan, pose, model, label: str,
         engine: EngineSettings, segment: int = 1, twist=None) -> RunResult:
    """One run from ``pose`` (at rest, or with ``twist``), from ``segment`` on."""
    r, _ = trace(scene.with_pose(*pose[:3]), plan, model, record_every=0, label=label,
                 engine=engine, start_segment=segment, twist=twist)
    return replace(r, start=tuple(pose[:3]))


class _Runner:
    """Runs (start pose, model, label, engine) jobs in order, in this process or in worker
    processes, in batches; stops after the first batch with a run that fails."""

    def __init__(self, scene: Scene, plan: Plan, workers: int, pool: Executor | None,
                 start_method: str | None,
                 should_stop: Callable[[], bool] | None) -> None:
        # the runs do not need the plan's region (its funnels' entry states): less to send
        self.scene, self.should_stop = scene, should_stop
        self.plan = replace(plan, region=None)
        self.contacts = {i + 1 for i, c in enumerate(scene.in_contact) if c}
        self.pool, self.own = pool, False
        if pool is None and workers > 1:
            self.pool = ProcessPoolExecutor(
                max_workers=workers, mp_context=multiprocessing.get_context(start_method))
            self.own = True
        self.runs = 0

    def close(self) -> None:
        if self.own:
            self.pool.shutdown(wait=True, cancel_futures=True)

    def run(self, jobs: Sequence, stop_at_failure: bool = True,
            progress: Callable[[int, int], None] | None = None,
            judge: Callable[[RunResult], bool] | None = None) -> list[RunResult]:
        """Each job (pose, model, label, engine[, segment, twist]) run; ``judge(run)``
        says whether it passed (default: :func:`as_planned` from the scene's contacts)."""
        out: list[RunResult] = []
        d = self.scene.to_dict()
        if judge is None:
            def judge(r: RunResult) -> bool:
                return as_planned(self.plan, self.contacts, r)
        for k in range(0, len(jobs), REGION_BATCH):
            check_stop(self.should_stop)
            batch = jobs[k:k + REGION_BATCH]
            if self.pool is None:
                res = [_run(self.scene, self.plan, *job) for job in batch]
            else:
                res = list(self.pool.map(_job, [(d, self.plan, *job) for job in batch]))
            self.runs += len(res)
            out += [_with_matches(r, judge(r)) for r in res]
            if progress:
                progress(len(out), len(jobs))
            if stop_at_failure and not all(r.matches for r in out[-len(res):]):
                break
        return out


def _with_matches(run: RunResult, matches: bool) -> RunResult:
    """The run with ``matches`` set (the events as planned from a region's start)."""
    return replace(run, matches=matches)


def _models(scene: Scene, uncertainty: Uncertainty
            ) -> list[tuple[str, Model, EngineSettings]]:
    models = [(label, m, DEFAULT_ENGINE) for label, m in capture_models(scene, uncertainty)]
    return models + [(ENGINE_CHECK_PREFIX + e.label, models[0][1], e)
                     for e in ENGINE_VARIATIONS]


def _offset_text(offset) -> str:
    dx, dy, dt = offset
    return (f"start offset ({dx * 1e3:+.3g} mm, {dy * 1e3:+.3g} mm, "
            f"{np.degrees(dt):+.3g} deg)")


def certify_region(scene: Scene, plan: Plan, asked, uncertainty: Uncertainty, *,
                   grid: int = REGION_GRID, bisections: int = REGION_BISECTIONS,
                   sampled: int = REGION_SAMPLED_MODELS, draws: int = REGION_DRAWS,
                   seed: int = 0,
                   workers: int = DEFAULT_WORKERS, pool: Executor | None = None,
                   start_method: str | None = None,
                   should_stop: Callable[[], bool] | None = None) -> RegionCertificate:
    """The largest box of start poses, up to ``asked``, from every cover point of which
    ``plan`` seats the part under every model of the capture test (module docstring).

    Parameters
    ----------
    scene : Scene
        The part at its nominal start pose (the centre of the box).
    plan : Plan
        A feasible plan (of :func:`~.search.plan_seating`).
    asked : StartRegion or sequence of 3 float
        The box asked for: half-widths (dx m, dy m, dtheta rad).
    uncertainty : Uncertainty
        The model set (its capture models are run).
    grid : int
        Cover points per axis (>= 1; REGION_GRID).
    bisections : int
        Bisection steps per stage of the shrinking (>= 0; REGION_BISECTIONS).
    sampled : int
        Models drawn from ``uncertainty`` that each cover point is also run under (>= 0;
        REGION_SAMPLED_MODELS; none for the nominal model alone).
    draws : int
        Starts drawn uniformly in each box, each with a model drawn from
        ``uncertainty``, that must all seat too (>= 0; REGION_DRAWS: the scenario
        bound of REGION_EPSILON and REGION_BETA).
    seed : int
        Seed of those models (the k-th start of a box's cover takes the k-th
        ``sampled`` of ``sample_models(scene, uncertainty, sampled * starts, seed)``).
    workers : int
        Processes for the runs (1: in this process).
    pool : concurrent.futures.Executor, optional
        Worker processes the caller owns (used instead of a pool made here).
    start_method : str, optional
        multiprocessing's start method for a pool made here.
    should_stop : callable, optional
        Polled between batches of runs; True raises PlanCancelled.

    Returns
    -------
    RegionCertificate
        The asked box, the certified one (or None), its fraction of the asked one and
        what was run.

    Raises
    ------
    PlanError
        A plan that is not feasible, a bad region, ``grid`` < 1, ``bisections`` or
        ``sampled`` < 0.
    PlanCancelled
        ``should_stop()`` returned True.
    """
    asked = StartRegion.of(asked)
    if not plan.feasible:
        raise PlanError("a start region needs a feasible plan")
    for name, value, least in (("grid", grid, 1), ("bisections", bisections, 0),
                               ("sampled", sampled, 0), ("draws", draws, 0)):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise PlanError(f"{name} must be a whole number >= {least}, got {value!r}")
    models = _models(scene, uncertainty)
    if uncertainty == NOMINAL:
        sampled = 0
    runner = _Runner(scene, plan, workers, pool, start_method, should_stop)
    checked: dict[tuple, tuple[bool, str, int, int]] = {}
    failed: list[str] = []  # the boxes that failed, in the order checked, with why
    drawn_counts: dict[tuple, int] = {}  # uniformly drawn starts run per box
    passed_runs: dict[tuple, list[RunResult]] = {}  # a box that held: its runs

    def check(box: StartRegion) -> bool:
        if box.half_widths in checked:
            return checked[box.half_widths][0]
        starts, overlapping = [], 0
        for off in cover(box, grid):
            s = start_scene(scene, off)
            if s is None:
                overlapping += 1
            else:
                starts.append(tuple(s.pose))
        drawn = sample_models(scene, uncertainty, sampled * len(starts), seed)
        jobs = [job for k, off in enumerate(starts) for job in
                [(off, m, label, e) for label, m, e in models]
                + [(off, m, "sampled", DEFAULT_ENGINE)
                   for m in drawn[k * sampled:(k + 1) * sampled]]]
        # the scenario part: starts uniform in the box, each with a drawn model, seeded
        # by the seed and the box's place in the search (the same boxes, the same draws)
        box_seed = seed + DRAW_SEED_STRIDE * (len(checked) + 1)
        uniform = sample_starts(scene, box, draws, box_seed) if starts else []
        jobs += [(p, m, "drawn start", DEFAULT_ENGINE) for p, m in zip(
            uniform, sample_models(scene, uncertainty, len(uniform), box_seed))]
        drawn_counts[box.half_widths] = len(uniform)
        res = runner.run(jobs)
        bad = next((r for r in res if not r.matches), None)
        why = "" if bad is None else (
            f"{_offset_text(np.subtract(bad.start, scene.pose))}, {bad.label} model: "
            + (bad.reason or "meets the contacts in another order"))
        if not starts:
            why = "every cover point overlaps a fixel"
        checked[box.half_widths] = (bad is None and bool(starts), why, len(starts),
                                    overlapping)
        if checked[box.half_widths][0]:
            passed_runs[box.half_widths] = res
        if why:
            failed.append(f"{box.text()}: {why}")
        return checked[box.half_widths][0]

    def scaled(f) -> StartRegion:
        return StartRegion(*(f[i] * h for i, h in enumerate(asked.half_widths)))

    try:
        best: StartRegion | None = None
        if check(asked):
            best = asked
        else:
            zero = StartRegion(0.0, 0.0, 0.0)
            if check(zero):
                lo, hi = 0.0, 1.0
                for _ in range(bisections):
                    mid = 0.5 * (lo + hi)
                    if check(scaled((mid,) * 3)):
                        lo = mid
                    else:
                        hi = mid
                frac = [lo, lo, lo]
                for axis in range(3):
                    if asked.half_widths[axis] == 0.0:
                        continue
                    a, b = frac[axis], 1.0
                    for _ in range(bisections):
                        mid = 0.5 * (a + b)
                        trial = list(frac)
                        trial[axis] = mid
                        if check(scaled(trial)):
                            a = mid
                        else:
                            b = mid
                    frac[axis] = a
                best = scaled(frac)
    finally:
        runner.close()
    failure = failed[-1] if failed else ""
    if best is None:
        return RegionCertificate(asked, None, 0.0, grid, 0, 0,
                                 tuple(label for label, _, _ in models), len(checked),
                                 runner.runs, failure, sampled)
    n = drawn_counts[best.half_widths]
    _, _, points, overlapping = checked[best.half_widths]
    fraction = 1.0 if best == asked else best.fraction_of(asked)
    return RegionCertificate(asked, best, fraction, grid, points, overlapping,
                             tuple(label for label, _, _ in models), len(checked),
                             runner.runs, failure, sampled, n,
                             _epsilon(n, REGION_BETA) if n else None, REGION_BETA,
                             evidence=tuple(passed_runs[best.half_widths]))


def check_segment_funnels(scene: Scene, plan: Plan, certificate: RegionCertificate, *,
                          draws: int = FUNNEL_DRAWS, seed: int = 0,
                          workers: int = DEFAULT_WORKERS, pool: Executor | None = None,
                          start_method: str | None = None,
                          should_stop: Callable[[], bool] | None = None
                          ) -> RegionCertificate:
    """The certificate with the entry region of every later segment of ``plan``, each
    checked as a funnel of the plan's rest
    (:func:`~.segment_funnels.certify_segment_funnels`), from the runs that certified
    its box.

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose.
    plan : Plan
        The plan the certificate is of.
    certificate : RegionCertificate
        Of :func:`certify_region` (a certified box, with its runs).
    draws : int
        States drawn per entry region (>= 0; FUNNEL_DRAWS).
    seed : int
        The seed of the drawn states.
    workers, pool, start_method, should_stop
        As for :func:`certify_region`.

    Returns
    -------
    RegionCertificate
        ``certificate`` with its ``segment_funnels`` (unchanged without a certified box).

    Raises
    ------
    PlanError
        ``draws`` is not a whole number >= 0.
    PlanCancelled
        ``should_stop()`` returned True.
    """
    if isinstance(draws, bool) or not isinstance(draws, int) or draws < 0:
        raise PlanError(f"draws must be a whole number >= 0, got {draws!r}")
    if certificate.certified is None or not certificate.evidence:
        return certificate
    runner = _Runner(scene, plan, workers, pool, start_method, should_stop)

    def run_from(segment: int, states, models) -> list[RunResult]:
        jobs = [(tuple(st[:3]), m, f"funnel {segment}", DEFAULT_ENGINE, segment,
                 tuple(st[3:])) for st, m in zip(states, models)]

        def judge(r: RunResult) -> bool:
            # the fixels the plan starts on may be touched again (as from a start of
            # the box), and those touching at the drawn state
            start = scene.with_pose(*r.start)
            contacts = {i + 1 for i, c in enumerate(start.in_contact) if c}
            return as_planned_from(plan, segment, runner.contacts | contacts, r)
        return runner.run(jobs, stop_at_failure=False, judge=judge)

    try:
        funnels = certify_segment_funnels(scene, plan, certificate.evidence, run_from,
                                          draws=draws, seed=seed, beta=REGION_BETA)
    finally:
        runner.close()
    return replace(certificate, segment_funnels=funnels)


def _epsilon(n: int, beta: float) -> float:
    """The smallest eps with (1 - eps) ** n <= beta: n draws without a failure rule out
    a failure probability above eps at confidence 1 - beta."""
    return 1.0 - beta ** (1.0 / n)


def sample_starts(scene: Scene, region, count: int, seed: int
                  ) -> list[tuple[float, float, float]]:
    """``count`` start poses drawn uniformly in a start region (the offsets uniform in
    the box from ``numpy.random.default_rng(seed)``; a draw at which a fixel overlaps the
    part is drawn again), as absolute poses (x m, y m, theta rad).

    Parameters
    ----------
    scene : Scene
        The scene at its nominal start pose.
    region : StartRegion or sequence of 3 float
        The box.
    count : int
        How many starts.
    seed : int
        The seed.

    Returns
    -------
    list of (float, float, float)
        The starts; fewer than ``count`` when SAMPLE_ATTEMPTS * count draws did not
        find them (a box that is nearly all overlap).
    """
    region = StartRegion.of(region)
    rng = np.random.default_rng(seed)
    h = np.array(region.half_widths)
    out: list[tuple[float, float, float]] = []
    for _ in range(SAMPLE_ATTEMPTS * count):
        if len(out) >= count:
            break
        off = tuple(map(float, h * (2.0 * rng.random(3) - 1.0)))
        s = start_scene(scene, off)
        if s is not None:
            out.append(tuple(s.pose))
    return out


def run_starts(scene: Scene, plan: Plan, starts: Sequence, models: Sequence,
               workers: int = DEFAULT_WORKERS,
               progress: Callable[[int, int], None] | None = None,
               should_stop: Callable[[], bool] | None = None,
               start_method: str | None = None,
               pool: Executor | None = None) -> list[RunResult]:
    """``plan`` run from each start under the model paired with it (``starts[k]`` with
    ``models[k]``), in parallel processes; each result has its ``start`` and ``matches``
    says whether it seated as planned from that start (:func:`as_planned`).

    Parameters
    ----------
    scene : Scene
        The scene at its nominal start pose.
    plan : Plan
        The plan.
    starts : sequence of (float, float, float)
        Start poses (x m, y m, theta rad), e.g. of :func:`sample_starts`.
    models : sequence of Model
        One model per start.
    workers : int
        Processes (1: in this process).
    progress : callable, optional
        ``progress(done, total)`` after each batch.
    should_stop : callable, optional
        Polled between batches; True raises PlanCancelled.
    start_method : str, optional
        multiprocessing's start method.
    pool : concurrent.futures.Executor, optional
        Worker processes the caller owns.

    Returns
    -------
    list of RunResult
        One per start, in order.
    """
    jobs = [(tuple(s), m, "sampled", DEFAULT_ENGINE) for s, m in zip(starts, models)]
    runner = _Runner(scene, plan, workers, pool, start_method, should_stop)
    try:
        return runner.run(jobs, stop_at_failure=False, progress=progress)
    finally:
        runner.close()


def run_region_samples(scene: Scene, plan: Plan, region, uncertainty: Uncertainty,
                       runs: int, seed: int, workers: int = DEFAULT_WORKERS,
                       progress: Callable[[int, int], None] | None = None,
                       should_stop: Callable[[], bool] | None = None,
                       start_method: str | None = None,
                       pool: Executor | None = None) -> list[RunResult]:
    """The Monte Carlo of a plan over a start region: ``runs`` starts drawn uniformly in
    ``region`` (:func:`sample_starts`, seeded by ``seed``), each run under its own model
    drawn from ``uncertainty`` (:func:`~.execution.sample_models`, the same seed), with
    :func:`run_starts`.

    Parameters
    ----------
    scene : Scene
        The scene at its nominal start pose (the box's centre).
    plan : Plan
        The plan.
    region : StartRegion or sequence of 3 float
        The box (e.g. the certified one, ``plan.start_region``).
    uncertainty : Uncertainty
        The model set the models are drawn from.
    runs : int
        How many starts (fewer when the box is nearly all overlap: :func:`sample_starts`).
    seed : int
        The seed of the starts and of the models.
    workers, progress, should_stop, start_method, pool
        As for :func:`run_starts`.

    Returns
    -------
    list of RunResult
        One per start, in order, each with its ``start``.
    """
    starts = sample_starts(scene, region, runs, seed)
    return run_starts(scene, plan, starts, sample_models(scene, uncertainty, len(starts), seed),
                      workers, progress, should_stop, start_method, pool=pool)
