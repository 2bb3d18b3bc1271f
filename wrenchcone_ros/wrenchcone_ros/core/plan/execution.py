# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Executing a plan in the engine: one model, the capture test's models, the Monte Carlo.

A plan is run open loop from the scene's pose (:func:`trace`): each segment's direction
and force scale until the simulation sees its contact event, then the hold segment's
for HOLD_TIME T. A run succeeds when every target fixel is a contact at the end and the
part is at rest: over the last quarter of the hold no point of it moved more than the
contact band (SIM_CONTACT_BAND L; the engine's contacts jitter by far less, but its
velocities spike now and then, so a speed read at one instant is no test). A part still
moving then (a slow slide after the impact) is held on, window after window, until it
is at rest or HOLD_LIMIT T have passed.

Models (:class:`~.uncertainty.Model`): the engine takes each fixel's mu, the mass, the
inertia and the centre of mass of the model. The contact-normal error of an uncertainty
is not simulated (the engine's pins are circles with exact normals): it enters the
plans through the robust cones only.
"""

from __future__ import annotations

import math
import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from contextlib import closing
from dataclasses import dataclass, replace

import numpy as np

from ..scene import Scene
from ..scene_yaml import scene_from_dict
from ..simulate import DEFAULT_ENGINE, EngineSettings, Readout, Simulation
from ..tolerances import SIM_CONTACT_BAND
from ..uncertainty import Model, Uncertainty, nominal_model
from .results import DEFAULT_WORKERS, Plan, PlanCancelled, RunResult

#: Dimensionless (times T): a segment's motion is simulated for at most this long.
SEGMENT_TIMEOUT: float = 40.0

#: Dimensionless (times T): how long the seated part is held under the final direction
#: at least; its last quarter is the window in which it must not move (:func:`trace`).
HOLD_TIME: float = 2.0

#: Dimensionless (times T): how long the hold may go on while the part still moves (a slow
#: slide after an impact); a part not at rest by then fails the run.
HOLD_LIMIT: float = 10.0


def check_stop(should_stop: Callable[[], bool] | None) -> None:
    """Raise PlanCancelled when ``should_stop()`` says so."""
    if should_stop is not None and should_stop():
        raise PlanCancelled("the plan was cancelled")


# --- models ---------------------------------------------------------------------------
def as_model(scene: Scene, model) -> Model:
    """A :class:`~.uncertainty.Model` from None (nominal), a Model (its friction None:
    the scene's) or a sequence of mu, one per fixel."""
    if model is None:
        return nominal_model(scene)
    if isinstance(model, Model):
        if model.friction is None:
            return replace(model, friction=nominal_model(scene).friction)
        return model
    return replace(nominal_model(scene), friction=tuple(float(m) for m in model))


def model_scene(scene: Scene, model: Model) -> Scene:
    """The scene with the model's mass, inertia and centre of mass."""
    wp = scene.workpiece
    if (model.mass, model.inertia, tuple(model.com)) == (wp.mass, wp.inertia, tuple(wp.com)):
        return scene
    return replace(scene, workpiece=replace(wp, mass=model.mass, inertia=model.inertia,
                                            com=tuple(model.com)))


#: The engine settings a guaranteed plan must also seat the part under (its nominal
#: model, from the start, inelastic impacts), beside the defaults: the time step a
#: quarter and twice the default, the solver iterations half and four times, the
#: collision slop a quarter and four times. A plan that seats only under the defaults
#: rests on the engine's numerics, not on the mechanics.
ENGINE_VARIATIONS: tuple[EngineSettings, ...] = (
    EngineSettings(step=0.25), EngineSettings(step=2.0),
    EngineSettings(iterations=0.5), EngineSettings(iterations=4.0),
    EngineSettings(slop=0.25), EngineSettings(slop=4.0))


def capture_models(scene: Scene, uncertainty: Uncertainty) -> list[tuple[str, Model]]:
    """The models of the capture test, labelled: the nominal one, then the boundary of
    the uncertainty: every fixel's mu at its interval's low end, at its high end; the
    mass-to-inertia ratio at its two extremes (m low with I high, m high with I low);
    the centre of mass at the four extremes of its region (+-x, +-y).

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model only).

    Returns
    -------
    list of (str, Model)
        The labelled models, the nominal one first.
    """
    nom = nominal_model(scene)
    out = [("nominal", nom)]
    fr = uncertainty.friction_intervals(scene)
    if any(lo < hi for lo, hi in fr):
        out.append(("friction lo", replace(nom, friction=tuple(lo for lo, _ in fr))))
        out.append(("friction hi", replace(nom, friction=tuple(hi for _, hi in fr))))
    (m0, m1), (i0, i1) = uncertainty.mass_interval(scene), uncertainty.inertia_interval(scene)
    if m0 < m1 or i0 < i1:
        out.append(("mass lo, inertia hi", replace(nom, mass=m0, inertia=i1)))
        out.append(("mass hi, inertia lo", replace(nom, mass=m1, inertia=i0)))
    cx, cy = nom.com
    if uncertainty.com_radius:
        r = uncertainty.com_radius
        hx = hy = r
    elif uncertainty.com_box is not None and any(uncertainty.com_box):
        hx, hy = uncertainty.com_box
    else:
        hx = hy = 0.0
    for label, c in (("com +x", (cx + hx, cy)), ("com -x", (cx - hx, cy)),
                     ("com +y", (cx, cy + hy)), ("com -y", (cx, cy - hy))):
        if c != (cx, cy):
            out.append((label, replace(nom, com=c)))
    return out


def sample_models(scene: Scene, uncertainty: Uncertainty, count: int, seed: int
                  ) -> list[Model]:
    """``count`` models of the uncertainty, seeded.

    Every fixel's mu is uniform in its interval (lo + (hi - lo) U(0, 1) per fixel from
    ``numpy.random.default_rng(seed)``); the mass, inertia, centre of mass and normals
    are drawn as :meth:`~.uncertainty.Uncertainty.sample` draws them (seeded by
    ``seed``).

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    uncertainty : Uncertainty
        The set of models to draw from.
    count : int
        How many models.
    seed : int
        The seed of the draw.

    Returns
    -------
    list of Model
    """
    rng = np.random.default_rng(seed)
    fr = uncertainty.friction_intervals(scene)
    lo = np.array([p[0] for p in fr])
    hi = np.array([p[1] for p in fr])
    mus = [tuple(map(float, lo + (hi - lo) * rng.random(len(lo)))) for _ in range(count)]
    rest = uncertainty.sample(scene, count, seed=seed)
    return [replace(m, friction=f) for m, f in zip(rest, mus)]


# --- one run ----------------------------------------------------------------------------
@dataclass(frozen=True)
class TraceFrame:
    """One recorded instant of an executed plan: the readout, the direction applied
    (rad) and the segment being executed (0-based; the hold segment last).

    Parameters
    ----------
    readout : Readout
        The simulation's state.
    direction : float
        The direction applied (rad, fixture frame).
    segment : int
        The segment being executed (0-based).
    """

    readout: Readout
    direction: float
    segment: int


def execute(scene: Scene, plan: Plan, model=None, restitution: float = 0.0,
            label: str = "", engine: EngineSettings = DEFAULT_ENGINE) -> RunResult:
    """Run ``plan`` open loop in the physics engine (pymunk) from the scene's pose.

    Parameters
    ----------
    scene : Scene
        The part at its start pose.
    plan : Plan
        A plan of :func:`plan_seating`.
    model : Model, sequence of float or None
        The physical model run: None (the scene's), a Model (friction, mass, inertia,
        centre of mass, normals), or one mu per fixel.
    restitution : float
        The impacts' coefficient of restitution (0: inelastic).
    label : str
        A name for the run, kept in the result.
    engine : EngineSettings, optional
        The engine's time step, solver iterations and collision slop, as factors on the
        defaults.

    Returns
    -------
    RunResult
        Whether the part ended seated (every target fixel touching, at rest), the
        fixels reached in order (1-based), the final pose and why a run failed.

    Raises
    ------
    SimulationUnavailable
        pymunk is not installed.
    """
    return trace(scene, plan, model, record_every=0, restitution=restitution,
                 label=label, engine=engine)[0]


def trace(scene: Scene, plan: Plan, model=None, record_every: int = 10,
          restitution: float = 0.0, label: str = "",
          engine: EngineSettings = DEFAULT_ENGINE, start_segment: int = 1,
          twist: Sequence[float] | None = None
          ) -> tuple[RunResult, list[TraceFrame]]:
    """:func:`execute`, recording a :class:`TraceFrame` every ``record_every`` steps
    (0: none) and at every change of direction.

    Parameters
    ----------
    scene : Scene
        The part at its start pose.
    plan : Plan
        A plan of :func:`plan_seating`.
    model : Model, sequence of float or None, optional
        As in :func:`execute`.
    record_every : int, optional
        Steps between frames (0: none).
    restitution : float, optional
        The impacts' coefficient of restitution (0: inelastic).
    label : str, optional
        A name for the run, kept in the result.
    engine : EngineSettings, optional
        As in :func:`execute`.
    start_segment : int, optional
        The segment (1-based) the run starts with: the plan's suffix from it (a funnel's
        check, :mod:`.funnels`); a fixel touching at the start counts as reached.
    twist : sequence of 3 float or None, optional
        The velocity to start with (:meth:`~.simulate.Simulation.set_twist`; None: at
        rest).

    Returns
    -------
    result : RunResult
        As :func:`execute`, with the state at which each later segment began
        (``entries``).
    frames : list of TraceFrame
        The recorded frames.

    Raises
    ------
    SimulationUnavailable
        pymunk is not installed.
    ValueError
        ``start_segment`` is not one of the plan's segments.
    """
    model = as_model(scene, model)
    moving = [s for s in plan.segments if not s.hold]
    hold = plan.segments[-1]
    if not 1 <= start_segment <= len(moving) + 1:
        raise ValueError(f"start_segment must be in 1..{len(moving) + 1}, got "
                         f"{start_segment!r}")
    k = start_segment - 1
    first = moving[k] if k < len(moving) else hold
    sim = Simulation(model_scene(scene, model), plan.actuator, first.direction,
                     model.friction, restitution=restitution, scale=first.scale,
                     engine=engine)
    if twist is not None:
        sim.set_twist(twist)
    T, band = sim.sp.time_scale, SIM_CONTACT_BAND * sim.sp.length_scale
    target0 = [i - 1 for i in plan.target]
    touched = {i for i, c in enumerate(scene.in_contact) if c}
    events: list[int] = []
    # set(events), kept as events grows; from a later segment, what touches counts
    seen: set[int] = set() if k == 0 else {i + 1 for i in touched}
    reached = [set(s.reached) for s in moving]
    frames: list[TraceFrame] = []
    entries: list[tuple[float, ...]] = []
    limit = (sum(s.duration / math.sqrt(s.scale) for s in moving[k:]) * 3.0
             + (SEGMENT_TIMEOUT + HOLD_LIMIT) * T)
    t_seated, window_start, at_rest = None, None, False
    window, L = 0.25 * HOLD_TIME, sim.sp.length_scale
    if record_every:
        frames.append(TraceFrame(sim.readout(), sim.direction, 0))
    for step in range(int(math.ceil(limit / sim.dt))):
        sim.step()
        g = sim.gaps()
        for i in range(scene.n_fixels):
            if i not in touched and g[i] <= band:
                touched.add(i)
                events.append(i + 1)
                seen.add(i + 1)
        changed = False
        if k < len(moving) and reached[k] <= seen:
            k += 1
            nxt = moving[k] if k < len(moving) else hold
            sim.set_direction(nxt.direction, nxt.scale)
            entries.append(sim.pose + sim.twist())
            changed = True
        if k >= len(moving) and t_seated is None:
            t_seated = sim.t
        if record_every and (changed or (step + 1) % record_every == 0):
            frames.append(TraceFrame(sim.readout(), sim.direction, k))
        if t_seated is None:
            continue
        held = sim.t - t_seated
        if window_start is None and held >= (HOLD_TIME - window) * T:
            window_start = (sim.t, sim.pose)  # the impact has settled, the overlap undone
        elif window_start is not None and sim.t - window_start[0] >= window * T:
            at_rest = moved(window_start[1], sim.pose, L) <= band
            if at_rest or held >= HOLD_LIMIT * T:
                break
            window_start = (sim.t, sim.pose)  # still moving: hold on, one more window
    final = sim.readout()
    if record_every:
        frames.append(TraceFrame(final, sim.direction, k))
    in_contact = all(final.gaps[i] <= band for i in target0)
    group = {e: j for j, s in enumerate(moving) for e in s.reached}
    order = [group.get(e, -1) for e in events]
    matches = set(events) == set(group) and order == sorted(order)
    if k < len(moving):
        why = f"segment {k + 1}'s event ({moving[k].event}) never came"
    elif not in_contact:
        lost = [i + 1 for i in target0 if final.gaps[i] > band]
        far = min(final.gaps) > 2.0 * L
        why = (f"target fixel(s) {lost} not in contact at the end"
               + (" (the part is lost: no fixel within 2 L)" if far else
                  f" (it ends turned to theta = {math.degrees(final.pose[2]):.1f} deg)"))
    elif not at_rest:
        why = "the part still moves at the end"
    else:
        why = ""
    return RunResult(tuple(float(m) for m in model.friction), not why, tuple(events),
                     matches, final.pose, why, sim.t, model, float(restitution),
                     label, entries=tuple(entries)), frames


def moved(a: tuple, b: tuple, L: float) -> float:
    """How far a point of the part moved between poses a and b (m): the com's travel
    plus the turn times the part's length scale L (the test of rest of a run).

    Parameters
    ----------
    a, b : tuple of 3 float
        Poses (x m, y m, theta rad).
    L : float
        The part's length scale (m).

    Returns
    -------
    float
        An upper bound on any point's travel (m).
    """
    return math.hypot(b[0] - a[0], b[1] - a[1]) + abs(b[2] - a[2]) * L


def _execute_job(args) -> RunResult:
    scene_dict, plan, model, restitution = args
    return execute(scene_from_dict(scene_dict), plan, model, restitution)


#: Most Monte Carlo runs a worker process takes at once (about 0.1 s each on the pawl):
#: what a cancel may have to wait for.
MC_CHUNK = 4


def run_models(scene: Scene, plan: Plan, models: Sequence,
               workers: int = DEFAULT_WORKERS,
               progress: Callable[[int, int], None] | None = None,
               should_stop: Callable[[], bool] | None = None,
               start_method: str | None = None, restitution: float = 0.0,
               pool: Executor | None = None) -> list[RunResult]:
    """:func:`execute` for every model, in parallel processes.

    Parameters
    ----------
    scene : Scene
        The part at its start pose.
    plan : Plan
        A plan of :func:`plan_seating`.
    models : sequence
        Models (a Model, or one mu per fixel each), e.g. of :func:`sample_models`.
    workers : int
        Processes of a pool made for this call (1: in this process), or of ``pool``
        (for the chunk size).
    progress : callable, optional
        ``progress(done, total)`` after each run.
    should_stop : callable, optional
        Polled after each run; True cancels the runs not yet started (at most a chunk
        of :data:`MC_CHUNK` runs per worker is in flight).
    start_method : str, optional
        multiprocessing's start method (None: the platform's default).
    restitution : float
        The impacts' coefficient of restitution.
    pool : concurrent.futures.Executor, optional
        An executor the caller owns and keeps (a ROS node's worker processes, started
        once); used instead of a pool made for this call, and not shut down here.

    Returns
    -------
    list of RunResult
        One per model, in order.

    Raises
    ------
    PlanCancelled
        ``should_stop()`` returned True.
    """
    total = len(models)
    out: list[RunResult] = []
    if pool is None and (workers <= 1 or total <= 1):
        for m in models:
            check_stop(should_stop)
            out.append(execute(scene, plan, m, restitution))
            if progress:
                progress(len(out), total)
        return out
    plan = replace(plan, region=None)  # the runs do not need it: less to send
    jobs = [(scene.to_dict(), plan, m if isinstance(m, Model) else tuple(m), restitution)
            for m in models]
    own = pool is None
    if own:
        pool = ProcessPoolExecutor(max_workers=workers,
                                   mp_context=multiprocessing.get_context(start_method))
    try:
        # small chunks: a cancel waits only for the runs in flight (a chunk per worker);
        # closing the map cancels the chunks not started
        chunk = min(MC_CHUNK, max(1, total // (4 * max(1, workers))))
        with closing(pool.map(_execute_job, jobs, chunksize=chunk)) as results:
            for r in results:
                out.append(r)
                if progress:
                    progress(len(out), total)
                check_stop(should_stop)
    finally:
        if own:
            pool.shutdown(wait=True, cancel_futures=True)
    return out
