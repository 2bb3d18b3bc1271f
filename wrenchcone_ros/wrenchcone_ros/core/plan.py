# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans of tilts (or spring pulls) from a start pose to a seated part, checked in pymunk.

``plan_seating(scene, target, actuator)`` answers: which sequence of force directions
brings the workpiece from the scene's pose to a pose where every ``target`` fixel
touches it, and holds it there. It is the paper's own task (its Figure 1: "slide right
over fixels 2 and 3 until fixel 1 is reached") made into a search.

One segment (:func:`plan_segment`)
----------------------------------
At a pose with contacts C, the candidate modes keep every needed contact (a target fixel
in C slides or rolls: l, r or n; another may also separate, s) and approach at least one
target fixel not yet touched (a; the other free fixels a or s). For each candidate, best
margin first:

1. the directions that give only this mode at the pose (``force_directions(...,
   exclusive=True)``, at the actuator's point; robust to the uncertainty when one is
   given: :func:`robust_directions`);
2. the motion from the pose under the best of them, simulated (:mod:`.simulate`) until
   the next contact event: a fixel comes within the simulation's contact band, a kept
   contact is lost, the part stops, or time runs out;
3. the path: poses of that motion, each projected onto the kept contacts (Gauss-Newton
   on their gaps, until every gap is within GAP_CONVERGENCE of the contact tolerance),
   the last one onto the kept contacts and the new one;
4. ``sweep`` of the mode along the path (robust when an uncertainty is given): the
   directions valid along the whole segment (``interval``) and the ``margin`` of the
   segment's ``direction``, its worst case (the smallest over the poses and, with an
   uncertainty, over the models). The sweep stops at the last pose because the new
   contact is made: that is the predicted ``event``, compared with the simulated one.
   When the simulated direction is not in the interval of its own path, steps 2-4 are
   repeated with the interval's best direction (at most PLAN_REFINEMENTS times).

The segment is accepted when the simulated event is a target fixel reached, no needed
contact is lost, and the direction lies in the interval. The first candidate accepted
is taken (depth first, no backtracking over earlier segments).

The seat (:func:`hold_segment`)
-------------------------------
When the target is reached, a last segment holds the seated pose: mode n at every contact
and s at the free fixels, for every model. Holding is not enough for a part that moves:
it may stop just short of the seat (bounced off the last fixel, or wedged against it and
one other fixel, turned by a fraction of a milliradian) and stay there if that pose is an
equilibrium too. So the hold's direction must also make a funnel (Erdmann and Mason's
sensorless plans): at the near-seated poses (:func:`funnel_checks`: the seated part
lifted off each target fixel by FUNNEL_LIFTS times L, the other target contacts kept,
computed from the geometry by :func:`lifted_scene`) only modes that approach the missing
fixel may be consistent, for every model (``force_directions(..., exclusive=True,
uncertainty=...)`` of each such mode, their union). The hold's interval is the
intersection of the hold interval and those unions (:func:`~.directions.common_directions`);
its direction is the previous one when it lies there (no tilt change), else the one of
largest margin; its ``margin`` is the smallest of the hold margin and the funnel margins
(``hold_margin`` keeps the first). When the intersection is empty the plan is still made
(held under the previous direction), its last margin is not positive and ``reason`` says
that the seating is not guaranteed and which fixel's funnel is empty. A plan is
``guaranteed`` when every segment's margin is positive.

Evidence (:func:`execute`)
--------------------------
The plan is run open loop in the engine, switching to the next segment's direction when
the simulation sees the previous segment's contact event, then holding for
HOLD_TIME T. A run succeeds when every target fixel is a contact at the end and the part
is at rest: over the last quarter of the hold no point of it moved more than the contact
band (SIM_CONTACT_BAND L; the engine's contacts jitter by far less, but its velocities
spike now and then, so a speed read at one instant is no test). A part still moving then
(a slow slide after the impact) is held on, window after window, until it is at rest or
HOLD_LIMIT T have passed. The nominal model and
``runs`` sampled models of the uncertainty (each fixel's mu uniform in its interval,
independently, seeded) are run in ``workers`` processes; ``success_rate`` is the share of
sampled runs that succeed. A run whose events differ from the plan's is counted and its
events kept: a plan the simulation contradicts is reported, never hidden.

Uncertainty: a friction interval per fixel (:class:`~.uncertainty.Uncertainty`). The
intervals and margins are the package's robust answers, exact for friction intervals:
``force_directions``/``sweep`` with ``uncertainty=`` (the mode for every model, no other
mode for any model) and the worst-case margin in the robust "all" cone. The Monte Carlo
runs are the check in the engine.
"""

from __future__ import annotations

import itertools
import math
import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np

from .api import wrench_cone
from .classify import ModeClassifier
from .directions import (
    DirectionInterval,
    common_directions,
    force_basis,
    force_directions,
    sweep,
)
from .modes import ModeError, expand_mode
from .robust import robust_classification_cones, robust_cone
from .scene import Scene, SceneError, scene_from_dict
from .simulate import Actuator, Readout, Simulation
from .tolerances import SIM_CONTACT_BAND
from .uncertainty import Uncertainty, UncertaintyError

#: Most segments a plan may have (the hold segment included).
MAX_SEGMENTS: int = 8

#: Most times a segment's path is simulated again with a moved best direction.
PLAN_REFINEMENTS: int = 3

#: Dimensionless (times T): a segment's motion is simulated for at most this long.
SEGMENT_TIMEOUT: float = 40.0

#: Dimensionless (times T): how long the seated part is held under the final direction
#: at least; its last quarter is the window in which it must not move (:func:`trace`).
HOLD_TIME: float = 2.0

#: Dimensionless (times T): how long the hold may go on while the part still moves (a slow
#: slide after an impact); a part not at rest by then fails the run.
HOLD_LIMIT: float = 10.0

#: Poses of a segment's path handed to ``sweep`` (the end pose included).
PATH_POSES: int = 12

#: Dimensionless (a fraction of the scene's contact tolerance): how close to its goal
#: every gap must come when a pose is solved onto contacts (:func:`project_pose`,
#: :func:`lifted_scene`).
GAP_CONVERGENCE: float = 1e-3

#: Dimensionless (times L): how far the seated part is lifted off each target fixel, the
#: other target contacts kept, to make the near-seated poses of the funnel check
#: (:func:`funnel_checks`). For the pawl (L = 0.042 m) the part then turns by 0.3 to 6
#: mrad about the stop and one pin, or slides 10 to 170 micrometres back along both pins.
FUNNEL_LIFTS: tuple[float, ...] = (2.5e-4, 1e-3, 4e-3)

#: Default Monte Carlo runs (sampled models), seed and worker processes.
DEFAULT_RUNS: int = 100
DEFAULT_SEED: int = 0
DEFAULT_WORKERS: int = 2


class PlanError(ValueError):
    """Bad input to the planner: says what was wrong and what is allowed."""


class PlanCancelled(Exception):
    """``should_stop()`` returned True: the planner stopped (nothing is returned)."""


def _check(should_stop: Callable[[], bool] | None) -> None:
    if should_stop is not None and should_stop():
        raise PlanCancelled("the plan was cancelled")


# --- uncertainty: friction intervals ----------------------------------------------------
def as_uncertainty(scene: Scene, uncertainty) -> Uncertainty | None:
    """The :class:`~.uncertainty.Uncertainty` of ``uncertainty``: None (the nominal
    model), an Uncertainty, a friction interval (lo, hi) for every fixel or one per
    fixel. Only friction intervals can be simulated (PlanError otherwise)."""
    if uncertainty is None:
        return None
    if not isinstance(uncertainty, Uncertainty):
        try:
            uncertainty = Uncertainty(friction=uncertainty)
        except UncertaintyError as exc:
            raise PlanError(f"friction uncertainty: {exc}") from None
    if uncertainty.nonlinear(scene):
        raise PlanError("plans are checked in simulation for friction intervals only; "
                        "mass, inertia, centre-of-mass and normal uncertainty are not "
                        "simulated (give Uncertainty(friction=...))")
    try:
        uncertainty.friction_intervals(scene)
    except UncertaintyError as exc:
        raise PlanError(f"friction uncertainty: {exc}") from None
    return uncertainty


def _margin_fn(scenes: Sequence[Scene], mode: str, point, uncertainty
               ) -> Callable[[float], float]:
    """phi -> the smallest margin over ``scenes`` of the force along phi in ``mode``'s
    cone, or in its robust "all" cone (the worst case over the models)."""
    frame = "com" if point is None else "nominal"
    cones = [((wrench_cone(s, mode) if uncertainty is None else
               robust_cone(s, mode, uncertainty, "all", frame=frame)), force_basis(s, point))
             for s in scenes]

    def margin(phi: float) -> float:
        f = np.array([math.cos(phi), math.sin(phi)])
        return min(c.margin(B @ f) for c, B in cones)
    return margin


def robust_directions(scene: Scene, mode: str, point, uncertainty
                      ) -> list[DirectionInterval]:
    """Directions giving only ``mode`` at the scene's pose (for every model of
    ``uncertainty``, and no other mode for any model: ``force_directions(...,
    exclusive=True, uncertainty=...)``)."""
    try:
        if uncertainty is None:
            return force_directions(scene, mode, point, exclusive=True,
                                    classifier=ModeClassifier(scene))
        return force_directions(scene, mode, point, exclusive=True, uncertainty=uncertainty)
    except ModeError:
        return []


# --- projection of simulated poses onto the kept contacts --------------------------------
def project_pose(sim: Simulation, pose, fixels: Sequence[int], iterations: int = 20
                 ) -> tuple[float, float, float]:
    """The pose nearest ``pose`` (minimum-norm Gauss-Newton steps in (x, y, L theta))
    at which every fixel in ``fixels`` (0-based) touches the workpiece exactly (its gap
    within GAP_CONVERGENCE of the scene's contact tolerance), in the engine's geometry."""
    body, space = sim.sp.body, sim.sp.space
    saved = (body.position, body.angle)
    L = sim.sp.length_scale
    tol = GAP_CONVERGENCE * sim.scene.effective_contact_tolerance
    x, y, th = (float(v) for v in pose)
    try:
        for _ in range(iterations):
            body.angle, body.position = th, (x, y)  # the angle first (about the com)
            space.reindex_shapes_for_body(body)
            rows, gaps = [], []
            for i in fixels:
                distance, point, n = sim.closest(i)
                px, py = point.x - x, point.y - y
                rows.append([n.x, n.y, (n.y * px - n.x * py) / L])
                gaps.append(distance - sim.scene.fixels[i].radius)
            if not fixels or max(abs(g) for g in gaps) <= tol:
                break
            d = np.linalg.lstsq(np.array(rows), -np.array(gaps), rcond=None)[0]
            x, y, th = x + float(d[0]), y + float(d[1]), th + float(d[2]) / L
    finally:
        body.angle, body.position = saved[1], saved[0]
        space.reindex_shapes_for_body(body)
    return (x, y, th)


# --- results -----------------------------------------------------------------------------
@dataclass(frozen=True)
class FunnelCheck:
    """One near-seated pose of the funnel check (:func:`funnel_checks`): the seated part
    lifted by ``lift`` (m) off target fixel ``missing`` (1-based), the other target
    contacts kept, at ``pose`` (x m, y m, theta rad). ``intervals``: the directions (lo,
    hi) rad under which only a mode that approaches the missing fixel is consistent, for
    every model; ``modes``: those modes, one per interval."""

    missing: int
    lift: float
    pose: tuple[float, float, float]
    intervals: tuple[tuple[float, float], ...]
    modes: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"missing": self.missing, "lift": self.lift, "pose": list(self.pose),
                "intervals": [list(v) for v in self.intervals],
                "intervals_deg": [[math.degrees(a) for a in v] for v in self.intervals],
                "modes": list(self.modes)}


@dataclass(frozen=True)
class Segment:
    """One step of a plan: under ``direction`` (rad, fixture frame) the part moves in
    ``mode`` from ``start_pose`` to ``end_pose`` ((x m, y m, theta rad)) until ``event``.

    ``interval``: (lo, hi) rad, the directions valid along the whole segment for every
    model; ``margin``: the direction's worst-case margin (smallest over the path's poses
    and the models); ``predicted_event``: the contact event from the geometry (the
    sweep's stop), ``event`` the simulated one; ``duration``: simulated time (s)."""

    mode: str
    interval: tuple[float, float]
    direction: float
    margin: float
    start_pose: tuple[float, float, float]
    end_pose: tuple[float, float, float]
    event: str
    predicted_event: str
    reached: tuple[int, ...] = ()  # fixels (1-based) that came into contact
    duration: float = 0.0
    hold: bool = False
    hold_margin: float | None = None  # the hold segment: margin of holding alone
    funnel: tuple[FunnelCheck, ...] = ()  # the hold segment: its near-seated poses

    def to_dict(self) -> dict:
        return {"mode": self.mode, "interval": list(self.interval),
                "interval_deg": [math.degrees(v) for v in self.interval],
                "direction": self.direction, "direction_deg": math.degrees(self.direction),
                "margin": self.margin, "start_pose": list(self.start_pose),
                "end_pose": list(self.end_pose), "event": self.event,
                "predicted_event": self.predicted_event, "reached": list(self.reached),
                "duration": self.duration, "hold": self.hold,
                "hold_margin": self.hold_margin,
                "funnel": [c.to_dict() for c in self.funnel]}


@dataclass(frozen=True)
class RunResult:
    """One simulated execution of a plan: the friction model, success, the events seen
    (fixels reached, 1-based, in order), and why it failed."""

    friction: tuple[float, ...]
    success: bool
    events: tuple[int, ...]
    matches: bool  # events as the plan predicts
    final_pose: tuple[float, float, float]
    reason: str = ""
    time: float = 0.0


@dataclass(frozen=True)
class Plan:
    """The answer of :func:`plan_seating`."""

    segments: tuple[Segment, ...]
    feasible: bool
    reason: str
    target: tuple[int, ...]
    actuator: Actuator
    friction: tuple[tuple[float, float], ...] | None
    nominal: RunResult | None = None
    runs: tuple[RunResult, ...] = ()
    seed: int = DEFAULT_SEED
    tried: tuple[str, ...] = field(default=())

    @property
    def success_rate(self) -> float | None:
        """Share of the sampled runs that succeed (the nominal run when there is no
        uncertainty); None when nothing was simulated."""
        runs = self.runs or ((self.nominal,) if self.nominal else ())
        if not runs:
            return None
        return sum(r.success for r in runs) / len(runs)

    @property
    def contradicted(self) -> int:
        """Simulated runs whose contact events differ from the plan's."""
        return sum(not r.matches for r in (self.runs or ((self.nominal,) if self.nominal
                                                          else ())))

    @property
    def worst_margin(self) -> float | None:
        return min((s.margin for s in self.segments), default=None)

    @property
    def guaranteed(self) -> bool:
        """A plan was found and every segment's worst-case margin is positive: every
        model moves as planned along every segment, holds the seated pose, and from every
        near-seated pose checked moves only towards the seat (module docstring)."""
        return self.feasible and all(s.margin > 0 for s in self.segments)

    def to_dict(self) -> dict:
        def run(r: RunResult) -> dict:
            return {"friction": list(r.friction), "success": r.success,
                    "events": list(r.events), "matches": r.matches,
                    "final_pose": list(r.final_pose), "reason": r.reason, "time": r.time}
        return {"feasible": self.feasible, "reason": self.reason,
                "target": list(self.target), "actuator": self.actuator.to_dict(),
                "friction": None if self.friction is None else [list(p) for p in self.friction],
                "segments": [s.to_dict() for s in self.segments],
                "guaranteed": self.guaranteed,
                "success_rate": self.success_rate, "runs": len(self.runs),
                "successes": sum(r.success for r in self.runs),
                "contradicted": self.contradicted, "seed": self.seed,
                "nominal": None if self.nominal is None else run(self.nominal),
                "failures": [run(r) for r in self.runs if not r.success][:20],
                "tried": list(self.tried)}


# --- planning ----------------------------------------------------------------------------
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


def candidate_modes(in_contact: Sequence[bool], target0: set[int]) -> list[str]:
    """Modes that keep the needed contacts and approach a target fixel (module docstring);
    ``target0``: target fixels, 0-based."""
    options = []
    for i, c in enumerate(in_contact):
        if c:
            options.append("lrn" if i in target0 else "lrns")
        else:
            options.append("as")
    out = []
    for letters in itertools.product(*options):
        if any(ch == "a" and i in target0 for i, ch in enumerate(letters)):
            out.append("".join(letters))
    return out


def _hold_mode(in_contact: Sequence[bool]) -> str:
    return "".join("n" if c else "s" for c in in_contact)


def _fixels(ix) -> str:
    ix = sorted(ix)
    return "fixel " + str(ix[0] + 1) if len(ix) == 1 else \
        "fixels " + ", ".join(str(i + 1) for i in ix)


@dataclass
class _Motion:
    """A simulated segment: the stop reason, the fixels reached, lost, and the poses."""

    reason: str
    reached: tuple[int, ...]
    lost: tuple[int, ...]
    poses: list
    duration: float


def _simulate_segment(scene: Scene, actuator: Actuator, phi: float, kept: Sequence[int],
                      friction=None) -> tuple[Simulation, _Motion]:
    """Simulate from rest at the scene's pose under phi until a contact event."""
    sim = Simulation(scene, actuator, phi, friction)
    band = SIM_CONTACT_BAND * sim.sp.length_scale
    free = [i for i in range(scene.n_fixels) if not scene.in_contact[i]]
    T = sim.sp.time_scale
    state: dict = {}

    def stop(s: Simulation) -> str | None:
        g = s.gaps()
        reached = tuple(i for i in free if g[i] <= band)
        lost = tuple(i for i in kept if g[i] > band)
        if reached:
            state["reached"] = reached
            return "reached"
        if lost:
            state["lost"] = lost
            return "lost"
        if s.t > T and s.speed() <= s.velocity_tolerance():
            return "stopped"
        return None

    traj = sim.run(SEGMENT_TIMEOUT * T, stop, record_every=5)
    return sim, _Motion(traj.reason, state.get("reached", ()), state.get("lost", ()),
                        [f.pose for f in traj.frames], sim.t)


def _path(sim: Simulation, motion: _Motion, kept: Sequence[int]) -> list:
    """PATH_POSES poses of the motion projected onto the kept contacts, the last one
    onto the kept contacts and the contacts made."""
    poses = motion.poses
    idx = sorted(set(np.linspace(0, len(poses) - 1, PATH_POSES).round().astype(int)))
    out = [project_pose(sim, poses[k], kept) for k in idx[:-1]]
    out.append(project_pose(sim, poses[-1], list(kept) + list(motion.reached)))
    return out


def plan_segment(scene: Scene, mode: str, interval: DirectionInterval, actuator: Actuator,
                 uncertainty: Uncertainty | None, kept: Sequence[int], target0: set[int]
                 ) -> tuple[Segment | None, str]:
    """One segment in ``mode`` from the scene's pose (module docstring), or None and why
    it was rejected."""
    point = actuator.directions_point
    phi = interval.best
    nominal = [scene.mu(i) for i in range(scene.n_fixels)]
    for _attempt in range(PLAN_REFINEMENTS):
        sim, motion = _simulate_segment(scene, actuator, phi, kept, nominal)
        if motion.reason != "reached":
            what = {"lost": f"{_fixels(motion.lost)} lost" if motion.lost else "",
                    "stopped": "the part stopped", "time": "no contact within the time limit"}
            return None, f"{mode}: {what.get(motion.reason, motion.reason)} (simulated)"
        if not set(motion.reached) & target0:
            return None, f"{mode}: reaches {_fixels(motion.reached)}, not a target (simulated)"
        path = _path(sim, motion, kept)
        try:
            sw = sweep(scene, path, mode, point=point, exclusive=True,
                       uncertainty=uncertainty)
        except SceneError as exc:
            return None, f"{mode}: the simulated path is not valid in the scene ({exc})"
        if sw.stop != len(path) - 1:
            return None, (f"{mode}: not valid along the simulated path (stops at pose "
                          f"{sw.stop} of {len(path)})")
        common = sw.common
        if not common:
            return None, f"{mode}: no direction valid along the whole simulated path"
        inside = [v for v in common if v.contains(phi)]
        if inside:  # the direction simulated is valid along its own path
            iv = inside[0]
            break
        phi = max(common, key=lambda v: v.margin).best
    else:
        return None, f"{mode}: the direction leaves its interval along its own path"
    margin = _margin_fn([scene.with_pose(*p) for p in path[:-1]], mode, point, uncertainty)
    end_scene = scene.with_pose(*path[-1])
    predicted = tuple(i for i in range(scene.n_fixels)
                      if end_scene.in_contact[i] and not scene.in_contact[i])
    return Segment(mode=mode, interval=(iv.lo, iv.hi), direction=phi, margin=margin(phi),
                   start_pose=tuple(scene.pose), end_pose=tuple(path[-1]),
                   event=f"{_fixels(motion.reached)} reached",
                   predicted_event=(f"{_fixels(predicted)} reached" if predicted
                                    else "no new contact"),
                   reached=tuple(i + 1 for i in motion.reached),
                   duration=motion.duration), ""


# --- the seated pose: hold, and the funnel around it ---------------------------------------
def lifted_scene(scene: Scene, missing: int, keep: Sequence[int], lift: float,
                 iterations: int = 30) -> Scene | None:
    """The scene with the part lifted by ``lift`` (m) off fixel ``missing`` while every
    fixel in ``keep`` still touches it (all 0-based), or None when no such pose exists
    nearby (the kept contacts leave no motion that lifts it, or a fixel penetrates).

    Gauss-Newton from the scene's pose, minimum-norm steps in (x, y, L theta) on the gaps
    (:attr:`~.scene.Scene.gaps`), the gap of fixel i changing by n_i . dq at its closest
    point q, until every gap is within GAP_CONVERGENCE of the contact tolerance of its
    goal. Pure geometry: no engine."""
    L, tol = scene.length_scale, GAP_CONVERGENCE * scene.effective_contact_tolerance
    rows_of = [*keep, missing]
    goal = np.array([0.0] * len(keep) + [float(lift)])
    # the iterates may overlap a fixel by up to about the lift: a scene that allows it
    loose = replace(scene, contact_tolerance=max(scene.contact_tolerance, 4.0 * lift))
    x, y, th = scene.pose
    for _ in range(iterations):
        try:
            ca = loose.with_pose(x, y, th).contact_arrays
        except SceneError:
            return None
        res = np.array([ca.gap[i] for i in rows_of]) - goal
        if np.max(np.abs(res)) <= tol:
            break
        rows = [[ca.n[i][0], ca.n[i][1],
                 ((ca.p[i][0] - x) * ca.n[i][1] - (ca.p[i][1] - y) * ca.n[i][0]) / L]
                for i in rows_of]
        d = np.linalg.lstsq(np.array(rows), -res, rcond=None)[0]
        x, y, th = x + float(d[0]), y + float(d[1]), th + float(d[2]) / L
    else:
        return None
    try:
        out = scene.with_pose(x, y, th)
    except SceneError:
        return None
    if not all(out.in_contact[i] for i in keep) or out.in_contact[missing]:
        return None
    return out


def _approach_margin(scene: Scene, missing: int, point, uncertainty: Uncertainty | None
                     ) -> tuple[Callable[[float], float], list[str], list]:
    """The modes of ``scene`` that approach fixel ``missing`` (0-based), the
    intervals of directions under which each is the only consistent mode for every model
    (``force_directions(..., exclusive=True, uncertainty=...)``), and phi -> the largest
    of their exclusive margins (the mode's margin in its cone, its robust "all" cone,
    and minus the margin in every other mode's cone, its robust "any" set: > 0 inside
    the intervals)."""
    modes = expand_mode("*" * scene.n_fixels, scene.in_contact)
    if uncertainty is None:
        clf = ModeClassifier(scene)
        alls = anys = [clf.cone(m) for m in modes]
    else:
        alls, anys = robust_classification_cones(
            scene, uncertainty, frame="com" if point is None else "nominal")
    approach = [k for k, m in enumerate(modes) if m[missing] == "a" and alls[k].feasible]
    found: list[tuple[str, DirectionInterval]] = []
    for k in approach:
        found += [(modes[k], iv) for iv in robust_directions(scene, modes[k], point,
                                                               uncertainty)]
    B = force_basis(scene, point)
    feasible_any = [k for k, c in enumerate(anys) if c.feasible]

    def margin(phi: float) -> float:
        g = B @ np.array([math.cos(phi), math.sin(phi)])
        y = {k: anys[k].margin(g) for k in feasible_any}
        return max((min([alls[k].margin(g)] + [-v for j, v in y.items() if j != k])
                    for k in approach), default=-1.0)
    return margin, [m for m, _ in found], [iv for _, iv in found]


def funnel_checks(seated: Scene, target0: set[int], point, uncertainty: Uncertainty | None
                  ) -> list[tuple[FunnelCheck, Callable[[float], float], list]]:
    """The near-seated poses of the seated scene and what a direction must do there.

    For every target fixel m and lift in FUNNEL_LIFTS (times L): the part lifted off m by
    the lift, the other target contacts kept (:func:`lifted_scene`: a turn about the two
    contacts kept, or a slide back along them), when that pose exists. There the
    direction must give only modes that approach m, for every model (Erdmann and Mason's
    funnel: a part that stops short of its seat, wedged or bounced, is driven on into it,
    not held where it is). Each check comes with its margin function and its intervals
    (:func:`_approach_margin`)."""
    out = []
    for m in sorted(target0):
        keep = sorted(target0 - {m})
        if not keep:
            continue
        for lift in FUNNEL_LIFTS:
            near = lifted_scene(seated, m, keep, lift * seated.length_scale)
            if near is None:
                continue
            margin, modes, ivs = _approach_margin(near, m, point, uncertainty)
            check = FunnelCheck(m + 1, lift * seated.length_scale, tuple(near.pose),
                                tuple((iv.lo, iv.hi) for iv in ivs), tuple(modes))
            out.append((check, margin, ivs))
    return out


def hold_segment(scene: Scene, previous: float | None, actuator: Actuator,
                 uncertainty: Uncertainty | None, target0: set[int] | None = None
                 ) -> tuple[Segment | None, str]:
    """The last segment: the seated pose holds (n at every contact, s at free fixels)
    and every near-seated pose funnels into it (:func:`funnel_checks`).

    The direction: the previous one when it does both, else the one of largest margin
    that does; its ``margin`` is the smallest of its hold margin and its margins at the
    near-seated poses. When no direction does both, the segment holds under the previous
    direction (or the best holding one) and the second value says why the seating is not
    guaranteed (its margin is then not positive)."""
    mode = _hold_mode(scene.in_contact)
    point = actuator.directions_point
    ivs = robust_directions(scene, mode, point, uncertainty)
    if not ivs:
        return None, f"the seated pose holds under no direction (mode {mode})"
    hold_margin = _margin_fn([scene], mode, point, uncertainty)
    checks = funnel_checks(scene, set(range(scene.n_fixels)) if target0 is None
                           else target0, point, uncertainty)

    def margin(phi: float) -> float:
        return min([hold_margin(phi)] + [f(phi) for _c, f, _iv in checks])

    both = common_directions([ivs] + [iv for _c, _f, iv in checks], margin)
    why = ""
    pool = both or ivs
    keep = previous is not None and any(iv.contains(previous) for iv in pool)
    if keep:
        iv = next(iv for iv in pool if iv.contains(previous))
        phi = previous
    else:
        iv = max(pool, key=lambda v: v.margin)
        phi = iv.best
    if not both:
        empty = sorted({c.missing for c, _f, v in checks if not v})
        why = ("seating not guaranteed: no direction holds the seated pose and drives every "
               "near-seated pose into it for every model"
               + (f" (lifted off {_fixels([m - 1 for m in empty])}, no direction gives only "
                  f"modes that approach it)" if empty else ""))
    event = "seated: holds" + ("" if keep else " (direction changed)")
    return Segment(mode=mode, interval=(iv.lo, iv.hi), direction=phi, margin=margin(phi),
                   start_pose=tuple(scene.pose), end_pose=tuple(scene.pose),
                   event=event, predicted_event=event, hold=True,
                   hold_margin=hold_margin(phi),
                   funnel=tuple(c for c, _f, _iv in checks)), why


def plan_seating(scene: Scene, target: Sequence[int], actuator: Actuator | str | None = None,
                 uncertainty=None, *, runs: int = DEFAULT_RUNS, seed: int = DEFAULT_SEED,
                 workers: int = DEFAULT_WORKERS,
                 progress: Callable[[int, int], None] | None = None,
                 simulate_runs: bool = True,
                 on_segment: Callable[[int], None] | None = None,
                 should_stop: Callable[[], bool] | None = None,
                 start_method: str | None = None) -> Plan:
    """A plan of force directions that seats the part on the ``target`` fixels (1-based
    numbers, as in the scene file), and its evidence from the simulation.

    ``actuator``: "tilt" (default), "spring:X,Y" or an :class:`~.simulate.Actuator`.
    ``uncertainty``: None, a friction interval (lo, hi) for every fixel, one per fixel,
    or an object with such a ``friction`` attribute. ``runs`` sampled models are
    simulated (seeded by ``seed``, in ``workers`` processes; ``progress(done, total)``
    after each); ``simulate_runs=False`` plans and runs only the nominal model.
    ``on_segment(k)`` is called when the k-th segment is planned; ``should_stop()`` is
    polled between candidate modes and between runs, and True raises PlanCancelled.
    ``start_method``: how the worker processes start (multiprocessing; None: the
    platform's default; a program with threads of its own, a ROS node, passes "spawn").
    Returns a :class:`Plan` (``feasible`` False with the ``reason`` when no plan exists).
    """
    if not isinstance(scene, Scene):
        raise PlanError(f"scene must be a Scene, got {type(scene).__name__}")
    act = Actuator.parse(actuator)
    t1 = _targets(scene, target)
    target0 = {i - 1 for i in t1}
    unc = as_uncertainty(scene, uncertainty)
    intervals = None if unc is None else unc.friction_intervals(scene)
    if not isinstance(runs, int) or runs < 0:
        raise PlanError(f"runs must be a whole number >= 0, got {runs!r}")
    state = scene
    segments: list[Segment] = []
    tried: list[str] = []
    feasible, reason = False, ""
    for step in range(MAX_SEGMENTS):
        contact = set(i for i, c in enumerate(state.in_contact) if c)
        if target0 <= contact:
            seg, why = hold_segment(state, segments[-1].direction if segments else None,
                                    act, unc, target0)
            if seg is None:
                reason = f"step {step + 1}: {why}"
            else:
                segments.append(seg)
                feasible = True
                reason = f"step {step + 1}: {why}" if why else ""
                if on_segment is not None:
                    on_segment(len(segments))
            break
        kept = sorted(contact)
        scored = []
        for mode in candidate_modes(state.in_contact, target0):
            ivs = robust_directions(state, mode, act.directions_point, unc)
            scored += [(iv.margin, mode, iv) for iv in ivs]
        scored.sort(key=lambda x: -x[0])
        seg = None
        why_not = []
        for _m, mode, iv in scored:
            _check(should_stop)
            seg, why = plan_segment(state, mode, iv, act, unc, kept, target0)
            if seg is not None:
                break
            why_not.append(why)
        tried += why_not
        if seg is None:
            need = _fixels(sorted(target0 - contact))
            if not scored:
                reason = (f"step {step + 1}: no direction gives a mode that keeps "
                          f"{_fixels(kept) if kept else 'the contacts'} and approaches "
                          f"{need} (for every friction model checked)")
            else:
                reason = (f"step {step + 1}: no candidate mode reaches {need} in the "
                          f"simulation ({'; '.join(why_not)})")
            break
        segments.append(seg)
        if on_segment is not None:
            on_segment(len(segments))
        state = scene.with_pose(*seg.end_pose)
    else:
        reason = f"no plan within {MAX_SEGMENTS} segments"
    plan = Plan(tuple(segments), feasible, reason, t1, act,
                None if intervals is None else tuple(intervals), seed=seed,
                tried=tuple(tried))
    if not feasible:
        return plan
    _check(should_stop)
    nominal = execute(scene, plan, [scene.mu(i) for i in range(scene.n_fixels)])
    results: tuple[RunResult, ...] = ()
    if intervals is not None and simulate_runs and runs:
        rng = np.random.default_rng(seed)
        lo = np.array([p[0] for p in intervals])
        hi = np.array([p[1] for p in intervals])
        samples = [tuple(map(float, lo + (hi - lo) * rng.random(len(lo))))
                   for _ in range(runs)]
        results = tuple(run_models(scene, plan, samples, workers, progress, should_stop,
                                   start_method))
    plan = replace(plan, nominal=nominal, runs=results)
    if not nominal.success:
        plan = replace(plan, reason="; ".join(filter(None, [
            plan.reason, f"the nominal simulation does not seat the part: {nominal.reason}"])))
    return plan


# --- executing a plan in the engine -----------------------------------------------------
@dataclass(frozen=True)
class TraceFrame:
    """One recorded instant of an executed plan: the readout, the direction applied
    (rad) and the segment being executed (0-based; the hold segment last)."""

    readout: Readout
    direction: float
    segment: int


def execute(scene: Scene, plan: Plan, friction: Sequence[float]) -> RunResult:
    """Run ``plan`` open loop from the scene's pose with one friction model (module
    docstring): each segment's direction until the simulation sees its contact event,
    then the hold segment's for HOLD_TIME T."""
    return trace(scene, plan, friction, record_every=0)[0]


def trace(scene: Scene, plan: Plan, friction: Sequence[float] | None = None,
          record_every: int = 10) -> tuple[RunResult, list[TraceFrame]]:
    """:func:`execute`, recording a :class:`TraceFrame` every ``record_every`` steps
    (0: none) and at every change of direction; friction None: the scene's."""
    if friction is None:
        friction = [scene.mu(i) for i in range(scene.n_fixels)]
    moving = [s for s in plan.segments if not s.hold]
    hold = plan.segments[-1]
    sim = Simulation(scene, plan.actuator, moving[0].direction if moving else hold.direction,
                     friction)
    T, band = sim.sp.time_scale, SIM_CONTACT_BAND * sim.sp.length_scale
    target0 = [i - 1 for i in plan.target]
    touched = {i for i, c in enumerate(scene.in_contact) if c}
    events: list[int] = []
    frames: list[TraceFrame] = []
    k = 0
    limit = sum(s.duration for s in moving) * 3.0 + (SEGMENT_TIMEOUT + HOLD_LIMIT) * T
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
        changed = False
        if k < len(moving) and set(moving[k].reached) <= set(events):
            k += 1
            sim.set_direction(moving[k].direction if k < len(moving) else hold.direction)
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
            at_rest = _moved(window_start[1], sim.pose, L) <= band
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
        why = "a target fixel is not in contact at the end"
    elif not at_rest:
        why = "the part still moves at the end"
    else:
        why = ""
    return RunResult(tuple(float(m) for m in friction), not why, tuple(events), matches,
                     final.pose, why, sim.t), frames


def _moved(a: tuple, b: tuple, L: float) -> float:
    """How far a point of the part moved between poses a and b (m): the com's travel
    plus the turn times the part's length scale L."""
    return math.hypot(b[0] - a[0], b[1] - a[1]) + abs(b[2] - a[2]) * L


def _execute_job(args) -> RunResult:
    scene_dict, plan, friction = args
    return execute(scene_from_dict(scene_dict), plan, friction)


#: Most Monte Carlo runs a worker process takes at once (about 0.1 s each on the pawl):
#: what a cancel may have to wait for.
MC_CHUNK = 4


def run_models(scene: Scene, plan: Plan, frictions: Sequence[Sequence[float]],
               workers: int = DEFAULT_WORKERS,
               progress: Callable[[int, int], None] | None = None,
               should_stop: Callable[[], bool] | None = None,
               start_method: str | None = None) -> list[RunResult]:
    """:func:`execute` for every friction model, in ``workers`` processes (1: here);
    ``should_stop()`` polled after each run (True: PlanCancelled, the rest cancelled)."""
    total = len(frictions)
    out: list[RunResult] = []
    if workers <= 1 or total <= 1:
        for f in frictions:
            _check(should_stop)
            out.append(execute(scene, plan, f))
            if progress:
                progress(len(out), total)
        return out
    jobs = [(scene.to_dict(), plan, tuple(f)) for f in frictions]
    pool = ProcessPoolExecutor(max_workers=workers,
                               mp_context=multiprocessing.get_context(start_method))
    try:
        # small chunks: a cancel waits only for the runs in flight (a chunk per worker)
        chunk = min(MC_CHUNK, max(1, total // (4 * workers)))
        for r in pool.map(_execute_job, jobs, chunksize=chunk):
            out.append(r)
            if progress:
                progress(len(out), total)
            _check(should_stop)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    return out


__all__ = ["FunnelCheck", "Plan", "PlanCancelled", "PlanError", "RunResult", "Segment",
           "TraceFrame", "as_uncertainty", "candidate_modes", "execute", "funnel_checks",
           "hold_segment", "lifted_scene", "plan_seating", "plan_segment", "project_pose",
           "robust_directions", "run_models", "trace"]
