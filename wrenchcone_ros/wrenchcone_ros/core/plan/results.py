# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The answers of the seating planner: segments, simulated runs, plans.

Fixel numbers are 0-based everywhere inside the planner; the result types store them
1-based (``Segment.reached``, ``RunResult.events``, ``FunnelCheck.missing``,
``Plan.target``) because they are what the CLI, the messages and the files show.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from ..directions import DirectionInterval
from ..simulate import Actuator
from ..uncertainty import NOMINAL, Model, Uncertainty

#: Default Monte Carlo runs (sampled models), seed and worker processes.
DEFAULT_RUNS: int = 100
DEFAULT_SEED: int = 0
DEFAULT_WORKERS: int = 2


class PlanError(ValueError):
    """Bad input to the planner: says what was wrong and what is allowed."""


class PlanCancelled(Exception):
    """``should_stop()`` returned True: the planner stopped (nothing is returned)."""


@dataclass(frozen=True)
class FunnelCheck:
    """One near-seated pose of the funnel check: the seated part lifted by ``lift`` (m)
    off target fixel ``missing`` (1-based), the other target contacts kept, at ``pose``
    (x m, y m, theta rad). ``intervals``: the directions (lo, hi) rad under which only a
    mode that approaches the missing fixel is consistent, for every model; ``modes``:
    those modes, one per interval.

    Parameters
    ----------
    missing : int
        The target fixel lifted off (1-based).
    lift : float
        How far it is lifted off (m).
    pose : tuple of 3 float
        The near-seated pose (x m, y m, theta rad).
    intervals : tuple of (float, float)
        The directions (lo, hi) rad that move the part only towards the missing fixel.
    modes : tuple of str
        The mode of each interval.
    """

    missing: int
    lift: float
    pose: tuple[float, float, float]
    intervals: tuple[tuple[float, float], ...]
    modes: tuple[str, ...]

    def to_dict(self) -> dict:
        """The check as JSON-able data (intervals also in degrees).

        Returns
        -------
        dict
            ``missing``, ``lift``, ``pose``, ``intervals``, ``intervals_deg``, ``modes``.
        """
        return {"missing": self.missing, "lift": self.lift, "pose": list(self.pose),
                "intervals": [list(v) for v in self.intervals],
                "intervals_deg": [[math.degrees(a) for a in v] for v in self.intervals],
                "modes": list(self.modes)}


@dataclass(frozen=True)
class Segment:
    """One step of a plan: under ``direction`` (rad, fixture frame), with ``scale`` times
    the actuator's force, the part moves in ``mode`` from ``start_pose`` to ``end_pose``
    ((x m, y m, theta rad)) until ``event``.

    ``interval``: the directions valid along the whole segment for every model (a
    :class:`~..directions.DirectionInterval`: lo, hi rad, its best direction, margin and
    guarantee); ``margin``: the direction's worst-case margin (smallest over the path's poses,
    up to the last one before the contact, and over the models); ``predicted_event``:
    the contact event from the geometry (the sweep's stop), ``event`` the simulated one;
    ``duration``: simulated time (s) under the full force. ``scale`` in (0, 1]: a tray
    tilted less (sin of its angle times ``scale``) or a weaker spring; a smaller force
    gives the same modes and the same path from rest, but the part arrives at its next
    contact with ``scale`` times the kinetic energy.

    Parameters
    ----------
    mode : str
        The contact mode of the segment.
    interval : DirectionInterval
        The directions valid along the whole segment for every model.
    direction : float
        The applied direction (rad, fixture frame).
    margin : float
        The direction's worst-case margin (dimensionless).
    start_pose, end_pose : tuple of 3 float
        (x m, y m, theta rad).
    event : str
        The simulated contact event that ends the segment.
    predicted_event : str
        The contact event the geometry predicts.
    reached : tuple of int, optional
        The fixels (1-based) that came into contact.
    duration : float, optional
        Simulated time (s) under the full force.
    hold : bool, optional
        Whether this is the hold segment (the seated part held).
    hold_margin : float or None, optional
        The hold segment's margin of holding alone.
    funnel : tuple of FunnelCheck, optional
        The hold segment's near-seated poses.
    scale : float, optional
        The fraction of the actuator's force, in (0, 1].
    """

    mode: str
    interval: DirectionInterval
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
    scale: float = 1.0

    @property
    def accuracy(self) -> float:
        """How far (rad) the applied direction may be off and still lie in the interval:
        its distance to the nearer edge (the tilt accuracy the segment needs)."""
        lo, hi = self.interval.lo, self.interval.hi
        return max(0.0, min(self.direction - lo, hi - self.direction))

    def to_dict(self) -> dict:
        """The segment as JSON-able data (angles also in degrees).

        Returns
        -------
        dict
            The fields, ``accuracy`` and the angles in degrees.
        """
        lo, hi = self.interval.lo, self.interval.hi
        return {"mode": self.mode, "interval": [lo, hi],
                "interval_deg": [math.degrees(lo), math.degrees(hi)],
                "direction": self.direction, "direction_deg": math.degrees(self.direction),
                "margin": self.margin, "accuracy": self.accuracy,
                "accuracy_deg": math.degrees(self.accuracy), "scale": self.scale,
                "start_pose": list(self.start_pose),
                "end_pose": list(self.end_pose), "event": self.event,
                "predicted_event": self.predicted_event, "reached": list(self.reached),
                "duration": self.duration, "hold": self.hold,
                "hold_margin": self.hold_margin,
                "funnel": [c.to_dict() for c in self.funnel]}


@dataclass(frozen=True)
class RunResult:
    """One simulated execution of a plan: the model (``friction`` per fixel, and the
    whole :class:`~.uncertainty.Model` when other parameters vary), the impacts'
    ``restitution``, success, the events seen (fixels reached, 1-based, in order), and
    why it failed.

    Parameters
    ----------
    friction : tuple of float
        The model's mu per fixel.
    success : bool
        Whether the part came to rest seated.
    events : tuple of int
        The fixels reached (1-based), in order.
    matches : bool
        Whether the events are those the plan predicts.
    final_pose : tuple of 3 float
        (x m, y m, theta rad).
    reason : str, optional
        Why the run failed.
    time : float, optional
        The simulated time (s).
    model : Model or None, optional
        The whole model when parameters other than friction vary.
    restitution : float, optional
        The impacts' coefficient of restitution.
    label : str, optional
        Which model ("nominal", "friction lo", ...) in the capture test.
    start : tuple of 3 float or None, optional
        The start pose (x m, y m, theta rad) when the run started elsewhere than at the
        scene's pose (a start of a :class:`StartRegion`); None: the scene's.
    entries : tuple of tuple of 6 float, optional
        The state at which each later segment began, in order: (x m, y m, theta rad,
        vx m/s, vy m/s, omega rad/s), the pose and the centre of mass's velocity,
        fixture frame (the entry states of :mod:`.segment_funnels`).
    """

    friction: tuple[float, ...]
    success: bool
    events: tuple[int, ...]
    matches: bool  # events as the plan predicts
    final_pose: tuple[float, float, float]
    reason: str = ""
    time: float = 0.0
    model: Model | None = None
    restitution: float = 0.0
    label: str = ""  # which model: "nominal", "friction lo", ... (capture checks)
    start: tuple[float, float, float] | None = None  # a start of a region (None: the scene's)
    entries: tuple[tuple[float, ...], ...] = ()  # the state as each later segment began

    @property
    def seats_as_planned(self) -> bool:
        """Whether the run succeeded with the contact events the plan predicts."""
        return self.success and self.matches

    def to_dict(self) -> dict:
        """The run as JSON-able data.

        Returns
        -------
        dict
            The fields (and the model's mass, inertia and com when it has one).
        """
        out = {"friction": list(self.friction), "success": self.success,
               "events": list(self.events), "matches": self.matches,
               "final_pose": list(self.final_pose), "reason": self.reason,
               "time": self.time, "restitution": self.restitution, "label": self.label,
               "start": None if self.start is None else list(self.start)}
        if self.model is not None:
            out.update(mass=self.model.mass, inertia=self.model.inertia,
                       com=list(self.model.com))
        return out


#: The label of a capture run of the nominal model under other engine settings:
#: this prefix, then the settings (``EngineSettings.label``).
ENGINE_CHECK_PREFIX = "nominal, engine "

#: The axes of a :class:`StartRegion`, in order, with their units.
REGION_AXES: tuple[tuple[str, str], ...] = (("dx", "m"), ("dy", "m"), ("dtheta", "rad"))


@dataclass(frozen=True)
class StartRegion:
    """A box of start poses around the scene's pose: x in [x0 - dx, x0 + dx], y in
    [y0 - dy, y0 + dy], theta in [theta0 - dtheta, theta0 + dtheta] (fixture frame).

    A pose of the box at which a fixel overlaps the part is not a start (a part cannot
    lie there); the others are, the part at rest there, touching the fixels it touches.

    Parameters
    ----------
    dx, dy : float
        Half-widths in x and y (m), finite, >= 0.
    dtheta : float
        Half-width in theta (rad), finite, in [0, pi].

    Raises
    ------
    PlanError
        A half-width that is not a finite number >= 0 (dtheta above pi), with what is
        allowed.
    """

    dx: float
    dy: float
    dtheta: float

    def __post_init__(self) -> None:
        for (name, unit), v in zip(REGION_AXES, (self.dx, self.dy, self.dtheta)):
            if isinstance(v, bool) or not isinstance(v, (int, float)) \
                    or not math.isfinite(v) or v < 0:
                raise PlanError(f"start region: {name} must be a finite number >= 0 "
                                f"({unit}), got {v!r}")
            object.__setattr__(self, name, float(v))
        if self.dtheta > math.pi:
            raise PlanError(f"start region: dtheta must be at most pi rad (a half-turn), "
                            f"got {self.dtheta!r}")

    @classmethod
    def of(cls, value) -> StartRegion:
        """A StartRegion from a StartRegion or a sequence (dx m, dy m, dtheta rad).

        Parameters
        ----------
        value : StartRegion or sequence of 3 float
            The region.

        Returns
        -------
        StartRegion

        Raises
        ------
        PlanError
            Not a StartRegion nor three numbers, or a bad half-width.
        """
        if isinstance(value, cls):
            return value
        try:
            if isinstance(value, (str, bytes)):
                raise TypeError  # three characters are not three numbers
            dx, dy, dtheta = value
        except (TypeError, ValueError):
            raise PlanError("start region must be a StartRegion or three half-widths "
                            f"(dx m, dy m, dtheta rad), got {value!r}") from None
        return cls(dx, dy, dtheta)

    @property
    def half_widths(self) -> tuple[float, float, float]:
        """(dx m, dy m, dtheta rad)."""
        return (self.dx, self.dy, self.dtheta)

    def fraction_of(self, asked: StartRegion) -> float:
        """This box's size as a fraction of ``asked``'s: the product, over the axes
        ``asked`` spans (half-width > 0), of this half-width over that one.

        Parameters
        ----------
        asked : StartRegion
            The box asked for (containing this one).

        Returns
        -------
        float
            The fraction of its volume, in [0, 1] for a box inside ``asked`` (1 when
            ``asked`` is a single pose).
        """
        out = 1.0
        for a, b in zip(self.half_widths, asked.half_widths):
            if b > 0:
                out *= a / b
        return out

    def to_dict(self) -> dict:
        """The region as JSON-able data (dtheta also in degrees).

        Returns
        -------
        dict
            ``dx``, ``dy`` (m), ``dtheta`` (rad), ``dtheta_deg``.
        """
        return {"dx": self.dx, "dy": self.dy, "dtheta": self.dtheta,
                "dtheta_deg": math.degrees(self.dtheta)}

    def text(self) -> str:
        """The box in words.

        Returns
        -------
        str
            E.g. '+-2 mm x +-2 mm x +-5 deg'.
        """
        return (f"+-{self.dx * 1e3:.4g} mm x +-{self.dy * 1e3:.4g} mm x "
                f"+-{math.degrees(self.dtheta):.4g} deg")


def failure_rate_bound(n: int, failures: int, beta: float) -> float:
    """The smallest eps such that ``failures`` or fewer failures in ``n`` independent
    draws would happen with probability at most ``beta`` if the failure rate were eps:
    the binomial tail, sum over i <= failures of C(n, i) eps^i (1 - eps)^(n - i) = beta
    (for no failure, 1 - beta ** (1 / n)). Draws with that many failures rule out a
    failure rate above eps with confidence 1 - beta.

    Parameters
    ----------
    n : int
        Draws (>= 1).
    failures : int
        Failures seen (0 .. n).
    beta : float
        In (0, 1).

    Returns
    -------
    float
        eps in (0, 1].
    """
    if failures >= n:
        return 1.0

    def tail(eps: float) -> float:
        return sum(math.comb(n, i) * eps ** i * (1.0 - eps) ** (n - i)
                   for i in range(failures + 1))

    lo, hi = 0.0, 1.0
    for _ in range(60):  # the tail falls as eps grows: bisection to 1e-18
        mid = 0.5 * (lo + hi)
        if tail(mid) > beta:
            lo = mid
        else:
            hi = mid
    return hi


#: The axes of an entry state, in order, with their units.
STATE_AXES: tuple[tuple[str, str], ...] = (
    ("x", "m"), ("y", "m"), ("theta", "rad"), ("vx", "m/s"), ("vy", "m/s"),
    ("omega", "rad/s"))


@dataclass(frozen=True)
class SegmentFunnel:
    """A later segment's entry region and its check as a funnel of the plan's rest
    (:mod:`.segment_funnels`): the poses within ``tube`` times the half-widths of
    [``lo``, ``hi``] (per pose axis) of an entry state's pose, with that state's
    velocity.

    Parameters
    ----------
    segment : int
        The segment (1-based) the region is the entry of (>= 2).
    lo, hi : tuple of 6 float
        The box holding every entry state (:data:`STATE_AXES`: m, m, rad, m/s, m/s,
        rad/s).
    observed : int
        The entry states.
    draws : int
        States drawn in the region, each run from the segment on.
    passed : int
        Of those, the runs that seated the part as planned.
    beta : float
        The confidence parameter of the scenario bound.
    failure : str, optional
        The first run that did not pass: its state, model and why ("" when all did).
    tube : float, optional
        The boxes around the entry states, as a fraction of [lo, hi]'s half-widths.
    entries : tuple of tuple of 6 float, optional
        The entry states (left out of comparisons, repr and JSON).
    models : tuple, optional
        The model of the run behind each entry state (a Model, or mu per fixel), in
        order (left out of comparisons, repr and JSON).
    wider : str, optional
        When the tube was halved: the last wider region checked that was not a funnel,
        its count and first failure ("" when the first tube held or none did).
    checks : int, optional
        Regions checked (1, or more when the tube was halved), each with its own draws.
    """

    segment: int
    lo: tuple[float, ...]
    hi: tuple[float, ...]
    observed: int
    draws: int
    passed: int
    beta: float
    failure: str = ""
    tube: float = 0.1
    entries: tuple[tuple[float, ...], ...] = field(default=(), repr=False, compare=False)
    models: tuple = field(default=(), repr=False, compare=False)
    wider: str = ""
    checks: int = 1

    @property
    def holds(self) -> bool:
        """Whether every drawn state seated the part (and some were drawn)."""
        return self.draws > 0 and self.passed == self.draws

    @property
    def epsilon(self) -> float | None:
        """The failure rate of such draws ruled out at confidence 1 - beta, given the
        failures seen (:func:`failure_rate_bound`; None without draws)."""
        if not self.draws:
            return None
        return failure_rate_bound(self.draws, self.draws - self.passed, self.beta)

    @property
    def pose_bounds(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The box holding every pose of the region: [lo, hi] on the pose axes, widened
        by the half-widths (m, m, rad)."""
        h = self.half_widths[:3]
        return (tuple(a - w for a, w in zip(self.lo[:3], h)),
                tuple(b + w for b, w in zip(self.hi[:3], h)))

    @property
    def half_widths(self) -> tuple[float, ...]:
        """The half-widths per axis of the boxes around the entry states: ``tube`` times
        the box's on the pose axes, 0 on the velocity axes."""
        return tuple(self.tube * 0.5 * (b - a) if i < 3 else 0.0
                     for i, (a, b) in enumerate(zip(self.lo, self.hi)))

    def near(self, pose: Sequence[float]) -> list[int]:
        """The entry states whose pose is within the region's half-widths of ``pose``:
        the part there, arriving as the chain brings it to one of them, is in the entry
        region.

        Parameters
        ----------
        pose : sequence of 3 float
            (x m, y m, theta rad), fixture frame.

        Returns
        -------
        list of int
            Their indices in ``entries`` (empty: the pose is not in the region).
        """
        h = self.half_widths[:3]
        return [i for i, e in enumerate(self.entries)
                if all(abs(v - c) <= w for v, c, w in zip(pose, e[:3], h))]

    def text(self) -> str:
        """The region in words.

        Returns
        -------
        str
            The box of the entry states (pose in mm and degrees, speeds in mm/s and
            deg/s) and the boxes around them.
        """
        lo, hi = self.lo, self.hi
        return (f"poses within {100.0 * self.tube:.0f} % of the half-widths of this box of "
                f"entry states of one of them, arriving as it does: x {lo[0] * 1e3:.2f}.."
                f"{hi[0] * 1e3:.2f} mm, y {lo[1] * 1e3:.2f}.."
                f"{hi[1] * 1e3:.2f} mm, theta {math.degrees(lo[2]):.2f}.."
                f"{math.degrees(hi[2]):.2f} deg, vx {lo[3] * 1e3:.1f}..{hi[3] * 1e3:.1f} "
                f"mm/s, vy {lo[4] * 1e3:.1f}..{hi[4] * 1e3:.1f} mm/s, omega "
                f"{math.degrees(lo[5]):.1f}..{math.degrees(hi[5]):.1f} deg/s")

    def verdict(self) -> str:
        """What the check found, in one line.

        Returns
        -------
        str
            The segment, its entry states and the check's outcome.
        """
        head = f"segment {self.segment}'s entry region ({self.observed} entry states)"
        shrunk = (f"; its boxes halved {self.checks - 1} time(s) to {100.0 * self.tube:.3g} "
                  f"% ({self.checks} regions checked): {self.wider}" if self.checks > 1
                  else "")
        if self.holds:
            return (f"{head}: a funnel: {self.passed} of {self.draws} states drawn in it "
                    f"seat the part from segment {self.segment} on (scenario bound: a "
                    f"failure rate above {100.0 * self.epsilon:.2g} % ruled out with "
                    f"confidence 1 - {self.beta:g}{' per region checked' if shrunk else ''})"
                    f"{shrunk}")
        if not self.draws:
            return f"{head}: not checked ({self.failure or 'no state drawn'})"
        return (f"{head}: not a funnel: {self.passed} of {self.draws} drawn states seat "
                f"the part (a failure rate above {100.0 * self.epsilon:.2g} % ruled out with "
                f"confidence 1 - {self.beta:g}); first failure: {self.failure}{shrunk}")

    def to_dict(self) -> dict:
        """The funnel as JSON-able data.

        Returns
        -------
        dict
            The fields but the entry states, ``holds``, ``epsilon``, ``half_widths`` and
            the axes' names and units.
        """
        return {"segment": self.segment, "axes": [f"{a} ({u})" for a, u in STATE_AXES],
                "lo": list(self.lo), "hi": list(self.hi), "tube": self.tube,
                "half_widths": list(self.half_widths), "observed": self.observed,
                "draws": self.draws, "passed": self.passed, "holds": self.holds,
                "epsilon": self.epsilon, "beta": self.beta, "failure": self.failure,
                "wider": self.wider, "checks": self.checks}


@dataclass(frozen=True)
class ConeSlice:
    """The poses of a box at which the part rests on a segment's contacts, and what the
    cones decide there (:mod:`.region_cones`): the margin of the segment's direction at
    every cover pose of the slice, for every model.

    Parameters
    ----------
    segment : int
        The segment (1-based).
    contacts : tuple of int
        The fixels the part rests on at every pose of the slice (1-based).
    lifted : int
        The fixel the part is lifted off (1-based; the hold segment's slices), 0 for a
        moving segment's slice.
    requirement : str
        What the direction must give there, in words ("mode arr alone", "only modes
        approaching fixel 1").
    box : str
        The box the slice is of, in words.
    dimension : int
        The slice's dimension (0: one pose, 1: a curve, 2: a surface).
    points : int
        Its cover poses in the box.
    grid : int
        Cover values per tangent axis.
    step : float
        The grid's step along the slice (m, in (x, y, L theta)).
    lo, hi : tuple of 3 float
        The cover poses' bounds (m, m, rad; empty without poses).
    worst : float or None
        The smallest margin over the cover poses (dimensionless; None without poses).
    worst_pose : tuple of 3 float or None
        Where.
    failed : int
        Cover poses whose margin is not positive.
    first_failure : tuple of 3 float or None
        The first of them.
    """

    segment: int
    contacts: tuple[int, ...]
    lifted: int
    requirement: str
    box: str
    dimension: int
    points: int
    grid: int
    step: float
    lo: tuple[float, ...]
    hi: tuple[float, ...]
    worst: float | None
    worst_pose: tuple[float, ...] | None
    failed: int
    first_failure: tuple[float, ...] | None

    @property
    def holds(self) -> bool:
        """Whether the margin is positive at every cover pose (and there is one)."""
        return self.points > 0 and self.failed == 0

    def verdict(self) -> str:
        """What the cones decide on the slice, in one line.

        Returns
        -------
        str
            The slice, its cover and the outcome.
        """
        shape = {0: "one pose", 1: "a curve", 2: "a surface"}.get(self.dimension,
                                                                  "the whole box")
        lift = f", lifted off fixel {self.lifted}" if self.lifted else ""
        head = (f"segment {self.segment} at rest on fixel(s) "
                f"{' '.join(str(i) for i in self.contacts)}{lift}, in {self.box}")
        if not self.points:
            return f"{head}: no pose of the box rests there (the cones decide nothing here)"
        lo, hi = self.lo, self.hi
        grid = (f"{self.points} cover poses, {self.step * 1e3:.3g} mm apart along it"
                if self.points > 1 else "1 cover pose")
        where = (f"{shape}; {grid} (x {lo[0] * 1e3:.2f}..{hi[0] * 1e3:.2f} mm, y "
                 f"{lo[1] * 1e3:.2f}..{hi[1] * 1e3:.2f} mm, theta "
                 f"{round(math.degrees(lo[2]), 2) + 0.0:.2f}.."
                 f"{round(math.degrees(hi[2]), 2) + 0.0:.2f} deg)")
        if self.holds:
            return (f"{head} ({where}): the direction gives {self.requirement} for every "
                    f"model at every cover pose (worst margin {self.worst:.3g}); between "
                    "cover poses nothing is proved")
        f = self.first_failure
        return (f"{head} ({where}): the direction does not give {self.requirement} for "
                f"every model at {self.failed} of the {self.points} cover poses (worst "
                f"margin {self.worst:.3g}; the first at x {f[0] * 1e3:.2f} mm, y "
                f"{f[1] * 1e3:.2f} mm, theta {math.degrees(f[2]):.2f} deg): a part at rest "
                "there may move otherwise")

    def to_dict(self) -> dict:
        """The slice as JSON-able data.

        Returns
        -------
        dict
            The fields, ``holds`` and ``verdict``.
        """
        return {"segment": self.segment, "contacts": list(self.contacts),
                "lifted": self.lifted, "requirement": self.requirement, "box": self.box,
                "dimension": self.dimension, "points": self.points, "grid": self.grid,
                "step": self.step, "lo": list(self.lo), "hi": list(self.hi),
                "worst": self.worst,
                "worst_pose": None if self.worst_pose is None else list(self.worst_pose),
                "failed": self.failed,
                "first_failure": (None if self.first_failure is None
                                  else list(self.first_failure)),
                "holds": self.holds, "verdict": self.verdict()}


@dataclass(frozen=True)
class RegionCertificate:
    """What a plan was checked for over a :class:`StartRegion`
    (:func:`~.region.certify_region`).

    ``certified`` is the largest box found (the asked one, or one shrunk per axis by
    bisection) at every point of whose cover the plan seats the part in the engine
    under every model of ``models``: a claim about those points, nothing between them.

    Parameters
    ----------
    asked : StartRegion
        The box asked for.
    certified : StartRegion or None
        The box certified (None: not even the scene's pose).
    fraction : float
        ``certified``'s volume as a fraction of ``asked``'s (0 when None).
    grid : int
        Cover points per axis (a grid of ``grid`` evenly spaced values from -1 to 1
        times each half-width; one point on an axis of half-width 0).
    points : int
        Cover points of the certified box that are starts (overlap no fixel).
    overlapping : int
        Cover points of the certified box at which a fixel overlaps the part (no start).
    models : tuple of str
        The models each cover point was run under (labels of the capture test).
    boxes : int
        Boxes checked (the asked one, the bisection's).
    runs : int
        Engine runs made.
    failure : str
        The last box that failed (the nearest to the certified one the bisection
        tried) and its first failed run ("" when the asked box holds).
    sampled : int, optional
        Models drawn from the uncertainty that each cover point was also run under.
    draws : int, optional
        Starts drawn uniformly in the certified box, each with a model drawn from the
        uncertainty, all of which seated.
    epsilon : float or None, optional
        The failure probability those draws rule out at confidence 1 - ``beta`` per box
        checked: 1 - beta ** (1 / draws) (None without draws).
    beta : float, optional
        The confidence parameter of ``epsilon``.
    compared : tuple of RegionCandidate, optional
        The plans the region search certified, in the search's order, this one's among
        them (:func:`~.search.plan_seating` with ``region_candidates`` > 1; empty: the
        search's plan was certified alone, ``region_candidates`` = 1).
    chosen : int, optional
        The place (1-based) in ``compared`` of the plan this certificate is of (0 without
        a comparison).
    limit : int, optional
        The most plans the region search would certify (``region_candidates``; 0
        without a comparison).
    segment_funnels : tuple of SegmentFunnel, optional
        The entry box of each later segment, checked as a funnel of the plan's rest
        (:func:`~.region.check_segment_funnels`; empty: not checked, or one segment).
    cone_slices : tuple of ConeSlice, optional
        The poses of the box and of each entry region at which the part rests on a
        segment's contacts, and what the cones decide there
        (:func:`~.region_cones.check_region_cones`; empty: not checked).
    evidence : tuple of RunResult, optional
        The runs that certified the box.
    """

    asked: StartRegion
    certified: StartRegion | None
    fraction: float
    grid: int
    points: int
    overlapping: int
    models: tuple[str, ...]
    boxes: int
    runs: int
    failure: str = ""
    sampled: int = 0
    draws: int = 0
    epsilon: float | None = None
    beta: float = 0.0
    compared: tuple[RegionCandidate, ...] = ()
    chosen: int = 0
    limit: int = 0
    segment_funnels: tuple[SegmentFunnel, ...] = ()
    cone_slices: tuple[ConeSlice, ...] = ()
    #: The runs that certified the box (with their entry states), for the funnels'
    #: check; not part of the answer (left out of comparisons, repr and JSON).
    evidence: tuple[RunResult, ...] = field(default=(), repr=False, compare=False)

    @property
    def axis_fraction(self) -> float:
        """The mean, over the axes the asked box spans (half-width > 0), of the certified
        half-width over the asked one (0 when none is certified; 1 when the asked box is
        a single pose and it holds): the tie-break of :attr:`fraction` between plans (a
        box of zero volume can still hold a turn, as the disc's does)."""
        if self.certified is None:
            return 0.0
        ratios = [c / a for c, a in zip(self.certified.half_widths, self.asked.half_widths)
                  if a > 0]
        return sum(ratios) / len(ratios) if ratios else 1.0

    @property
    def compared_runs(self) -> int:
        """The engine runs of every plan compared (:attr:`runs` without a comparison)."""
        return sum(c.certificate.runs for c in self.compared) if self.compared else self.runs

    @property
    def compared_boxes(self) -> int:
        """The boxes checked for every plan compared (:attr:`boxes` without one)."""
        return (sum(c.certificate.boxes for c in self.compared) if self.compared
                else self.boxes)

    @property
    def whole(self) -> bool:
        """Whether the whole asked box is certified."""
        return self.certified is not None and self.fraction >= 1.0

    @property
    def claim(self) -> str:
        """What is claimed, in words."""
        if self.certified is None:
            return ("no start region: the plan does not seat the part from the scene's "
                    "pose under every model checked")
        engines = sum(m.startswith(ENGINE_CHECK_PREFIX) for m in self.models)
        n = len(self.models) - engines
        models = "the nominal model" if n == 1 else f"the nominal and {n - 1} boundary models"
        under = f", the nominal one under {engines} other engine settings" if engines else ""
        drawn = f" and {self.sampled} models drawn from the uncertainty" if self.sampled else ""
        out = (f"every one of the {self.points} cover points (a grid of {self.grid} per "
               f"axis; {self.overlapping} more overlap a fixel and are no starts) seats "
               f"the part under {models}{under}{drawn}; between cover points nothing is "
               "proved")
        if self.draws:
            out += (f"; and {self.draws} starts drawn uniformly in the box, each with a "
                    "model drawn from the uncertainty, all seat: scenario bound, a "
                    f"failure rate above {100.0 * self.epsilon:.2g} % of such draws is "
                    f"ruled out with confidence 1 - {self.beta:g} per box checked "
                    f"({self.boxes})")
        return out

    def to_dict(self) -> dict:
        """The certificate as JSON-able data.

        Returns
        -------
        dict
            The fields (the boxes as :meth:`StartRegion.to_dict`), ``whole`` and
            ``claim``.
        """
        return {"asked": self.asked.to_dict(),
                "certified": None if self.certified is None else self.certified.to_dict(),
                "fraction": self.fraction, "whole": self.whole, "grid": self.grid,
                "points": self.points, "overlapping": self.overlapping,
                "models": list(self.models), "boxes": self.boxes, "runs": self.runs,
                "failure": self.failure, "sampled": self.sampled, "draws": self.draws,
                "epsilon": self.epsilon, "beta": self.beta, "claim": self.claim,
                "axis_fraction": self.axis_fraction, "chosen": self.chosen,
                "limit": self.limit,
                "compared": [c.to_dict() for c in self.compared],
                "compared_runs": self.compared_runs, "compared_boxes": self.compared_boxes,
                "segment_funnels": [f.to_dict() for f in self.segment_funnels],
                "cone_slices": [c.to_dict() for c in self.cone_slices]}


@dataclass(frozen=True)
class RegionCandidate:
    """One plan the region search certified (:func:`~.search.plan_seating` with
    ``region_candidates`` > 1): its place in the search and its certificate.

    Parameters
    ----------
    index : int
        Its place among the plans certified (1-based, in the search's order).
    candidate : int
        Its place among the complete candidates the search put to the capture test
        (1-based; 0: the last-resort constant direction, or a refuted candidate
        certified alone).
    plan : str
        Its modes, directions and force scales (``describe``).
    guaranteed : bool
        Whether the plan is guaranteed (from the scene's pose).
    certificate : RegionCertificate
        Its region (:func:`~.region.certify_region`, the same counts and seed for every
        plan compared).
    """

    index: int
    candidate: int
    plan: str
    guaranteed: bool
    certificate: RegionCertificate

    def text(self) -> str:
        """The candidate in words.

        Returns
        -------
        str
            E.g. 'candidate 2 (na -92.22 deg x0.1, nn -92.22 deg): 100.0 % of the asked
            volume, 100.0 % per axis (+-1 mm x +-1 mm x +-5 deg; 1 box(es), 2805 runs)'.
        """
        c = self.certificate
        box = "no box" if c.certified is None else c.certified.text()
        return (f"candidate {self.index} ({self.plan}): {100.0 * c.fraction:.1f} % of the "
                f"asked volume, {100.0 * c.axis_fraction:.1f} % per axis ({box}; "
                f"{c.boxes} box(es), {c.runs} runs)")

    def to_dict(self) -> dict:
        """The candidate as JSON-able data: its place, plan, the certified box and its
        fractions, the work (not the whole certificate: the chosen one is the
        region's).

        Returns
        -------
        dict
        """
        c = self.certificate
        return {"index": self.index, "candidate": self.candidate, "plan": self.plan,
                "guaranteed": self.guaranteed,
                "certified": None if c.certified is None else c.certified.to_dict(),
                "fraction": c.fraction, "axis_fraction": c.axis_fraction,
                "whole": c.whole, "boxes": c.boxes, "runs": c.runs, "failure": c.failure}



@dataclass(frozen=True)
class Plan:
    """The answer of :func:`~.search.plan_seating`.

    ``checks``: the capture test's runs (the nominal model first, then the boundary
    models of the uncertainty); ``tried``: every candidate the search rejected, with the
    reason; ``uncertainty``: the set of models planned for (NOMINAL: the nominal model).

    Parameters
    ----------
    segments : tuple of Segment
        The segments, in order; the last one holds the seated part.
    feasible : bool
        Whether a plan was found.
    reason : str
        Why not (empty when feasible).
    target : tuple of int
        The target fixels (1-based).
    actuator : Actuator
        What pulls the part.
    friction : tuple of (float, float) or None
        The friction interval of each fixel planned for.
    nominal : RunResult or None, optional
        The plan simulated for the nominal model.
    runs : tuple of RunResult, optional
        The Monte Carlo runs.
    seed : int, optional
        The seed of the sampled models.
    tried : tuple of str, optional
        Every candidate the search rejected, with the reason.
    checks : tuple of RunResult, optional
        The capture test's runs.
    uncertainty : Uncertainty, optional
        The set of models planned for (NOMINAL: the nominal model).
    out_of_time : bool, optional
        The search's opt-in time budget (CPU s) ended it: another machine may find
        another plan (a search ended by its work bounds or its candidates does not).
    candidates : int, optional
        The complete candidates the search put to the capture test.
    trials : int, optional
        The segments the search planned and simulated.
    region : RegionCertificate or None, optional
        The start region the plan was checked over (None: the scene's pose only).
    """

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
    checks: tuple[RunResult, ...] = ()
    uncertainty: Uncertainty = NOMINAL
    out_of_time: bool = False
    candidates: int = 0
    trials: int = 0
    region: RegionCertificate | None = None

    @property
    def start_region(self) -> StartRegion | None:
        """The certified start region (:class:`RegionCertificate`), None when no region
        was asked or none holds."""
        return None if self.region is None else self.region.certified

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
        """The smallest worst-case margin of the segments (None without a segment)."""
        return min((s.margin for s in self.segments), default=None)

    @property
    def margins_positive(self) -> bool:
        """Every segment's worst-case margin is positive (the quasi-static part)."""
        return self.feasible and all(s.margin > 0 for s in self.segments)

    @property
    def engine_checks(self) -> tuple[RunResult, ...]:
        """The capture test's runs under other engine settings (ENGINE_VARIATIONS)."""
        return tuple(r for r in self.checks if r.label.startswith(ENGINE_CHECK_PREFIX))

    @property
    def captured(self) -> bool:
        """The capture test passed: the nominal and every boundary model, simulated from
        the start with inelastic impacts, reach the contacts in the planned order and
        come to rest seated (docs/planning.md, "What guaranteed means")."""
        return bool(self.checks) and all(r.seats_as_planned for r in self.checks)

    @property
    def missing(self) -> tuple[str, ...]:
        """What the guarantee lacks (empty when the plan is guaranteed)."""
        if not self.feasible:
            return ("no plan",)
        out = []
        low = [k + 1 for k, s in enumerate(self.segments) if s.margin <= 0]
        if low:
            out.append("a positive worst-case margin in segment(s) "
                       + ", ".join(map(str, low)))
        if not self.checks:
            out.append("the capture test (not run)")
        else:
            bad = [r for r in self.checks if not r.seats_as_planned]
            if bad:
                out.append("capture at the contact events (" + "; ".join(
                    f"{r.label or 'a'} model: "
                    + (r.reason or "meets the contacts in another order")
                    for r in bad[:3]) + ")")
        if self.nominal is not None and not self.nominal.success \
                and not any(r.label == "nominal" for r in self.checks):
            out.append(f"the nominal simulation does not seat the part: {self.nominal.reason}")
        return tuple(out)

    @property
    def guaranteed(self) -> bool:
        """A plan was found, every segment's worst-case margin is positive (every model
        moves as planned along every segment from rest, holds the seated pose, and from
        every near-seated pose checked moves only towards the seat), and the capture test
        passed (the part arriving moving at each contact event is captured, for the
        nominal and the boundary models). docs/planning.md says what this assumes."""
        return not self.missing

    @property
    def guarantee(self) -> str:
        """How the quasi-static part of the guarantee holds per parameter (as the robust
        cones state it): exact for friction intervals, a scenario bound otherwise."""
        u = self.uncertainty
        parts = []
        if u.friction is not None:
            parts.append("friction intervals: exact (every mu in its interval)")
        if u.mass is not None or u.inertia is not None or u.com_radius or u.com_box \
                or u.normal_error is not None:
            parts.append(f"mass, inertia, centre of mass, contact normals: scenario "
                         f"(violation probability <= {u.epsilon:g} with confidence "
                         f"1 - {u.beta:g})")
        return "; ".join(parts) or "the nominal model"

    def tilt_deg(self, segment: Segment) -> float | None:
        """The tray tilt (degrees) of ``segment``: asin(scale sin(alpha)); None for a
        spring.

        Parameters
        ----------
        segment : Segment
            A segment of the plan.

        Returns
        -------
        float or None
            The tilt (degrees), or None.
        """
        if self.actuator.kind != "tilt":
            return None
        return math.degrees(math.asin(segment.scale * math.sin(self.actuator.tilt)))

    def to_dict(self) -> dict:
        """The plan as JSON-able data: the fields, the guarantee and what it lacks, the runs'
        statistics and the failed runs (at most 20).

        Returns
        -------
        dict
            The plan.
        """
        return {"feasible": self.feasible, "reason": self.reason,
                "target": list(self.target), "actuator": self.actuator.to_dict(),
                "friction": None if self.friction is None else [list(p) for p in self.friction],
                "uncertainty": self.uncertainty.to_dict(),
                "segments": [s.to_dict() for s in self.segments],
                "guaranteed": self.guaranteed, "missing": list(self.missing),
                "guarantee": self.guarantee,
                "margins_positive": self.margins_positive, "captured": self.captured,
                "checks": [r.to_dict() for r in self.checks],
                "success_rate": self.success_rate, "runs": len(self.runs),
                "successes": sum(r.success for r in self.runs),
                "contradicted": self.contradicted, "seed": self.seed,
                "nominal": None if self.nominal is None else self.nominal.to_dict(),
                "failures": [r.to_dict() for r in self.runs if not r.success][:20],
                "tried": list(self.tried), "candidates": self.candidates,
                "trials": self.trials, "out_of_time": self.out_of_time,
                "start_region": None if self.start_region is None
                else self.start_region.to_dict(),
                "region": None if self.region is None else self.region.to_dict()}


def fixels_text(ix) -> str:
    """'fixel 2' or 'fixels 1, 3' from 0-based numbers (the message boundary)."""
    ix = sorted(ix)
    return "fixel " + str(ix[0] + 1) if len(ix) == 1 else \
        "fixels " + ", ".join(str(i + 1) for i in ix)
