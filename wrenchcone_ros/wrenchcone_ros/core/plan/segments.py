# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""One segment of a plan: a mode, its directions along the simulated path, the seat.

A moving segment (:func:`plan_segment`)
---------------------------------------
At a pose with contacts C, the candidate modes (:func:`candidate_modes`) keep every
needed contact (a target fixel in C slides or rolls: l, r or n; another may also
separate, s) and approach at least one target fixel not yet touched (a; the other free
fixels a or s). For a candidate mode and one of its intervals of directions:

1. the directions that give only this mode at the pose (``force_directions(...,
   exclusive=True)``, at the actuator's point; robust to the uncertainty when one is
   given: :func:`robust_directions`);
2. the motion from rest at the pose under a direction, simulated until the next contact
   event: a fixel comes within the simulation's contact band, a kept contact is lost,
   the part stops, or time runs out;
3. the path: poses of that motion, each put back onto the kept contacts
   (:func:`~.poses.project_pose`), the last one before the contact too, and the end
   pose onto the kept contacts and the new one;
4. ``sweep`` of the mode along the path (robust when an uncertainty is given): the
   directions valid along the whole segment (``interval``), and the worst-case margin
   of a direction over every pose of the path up to the last one before the contact
   (and over the models): :func:`margin_function`. When no direction is valid all the
   way to the last pose before the contact (the part gets there by its momentum: the
   T-bar's swing), the interval and the direction are those of the path without that
   pose, and the margin, over the whole path, is not positive: the segment is not
   guaranteed at rest.

With no direction imposed, the segment's direction is the one of largest worst-case
margin over its own path: the interval's best direction at the start pose is simulated,
the direction maximising the worst case over that path is found, and the motion is
simulated again under it, until the direction moves by less than DIRECTION_SETTLE (at
most PLAN_REFINEMENTS simulations). The margin printed is the worst case over the path
of the direction applied. A direction imposed by the search is kept or rejected.

The seat (:func:`hold_segments`)
-------------------------------
When the target is reached, a last segment holds the seated pose: mode n at every
contact and s at the free fixels, for every model; and its direction must make a funnel
(Erdmann and Mason's sensorless plans): at the near-seated poses (:func:`funnel_checks`:
the seated part lifted off each target fixel by FUNNEL_LIFTS times L, the other target
contacts kept) only modes that approach the missing fixel may be consistent, for every
model. These are conditions on a part at rest; a part arriving moving is the capture
test's (:mod:`.search`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..classify import ModeClassifier, robust_classification_cones
from ..directions import DirectionInterval, force_basis, force_directions
from ..modes import ModeError, expand_mode
from ..robust import robust_cone
from ..geometry import SceneError
from ..scene import Scene
from ..simulate import Actuator, Simulation, initial_mode
from ..sweeps import common_directions, sweep
from ..tolerances import SIM_CONTACT_BAND
from ..uncertainty import NOMINAL, Uncertainty, as_uncertainty
from ..wrenchset import margins_of
from .execution import SEGMENT_TIMEOUT
from .poses import lifted_scene, project_pose
from .results import FunnelCheck, Segment, fixels_text

#: Most simulations of one segment while its direction settles (:func:`plan_segment`).
PLAN_REFINEMENTS: int = 3

#: Angle (rad) under which a segment's direction counts as settled: the direction of
#: largest worst-case margin over the simulated path moved by less (0.25 degrees).
DIRECTION_SETTLE: float = math.radians(0.25)

#: Directions evaluated per interval when the worst-case margin over a path is maximised
#: (a grid, then a bounded scalar search around its best point).
MARGIN_GRID: int = 48

#: Poses of a segment's path handed to ``sweep`` (the end pose included).
PATH_POSES: int = 12

#: Dimensionless (times L): how far the seated part is lifted off each target fixel, the
#: other target contacts kept, to make the near-seated poses of the funnel check
#: (:func:`funnel_checks`). For the pawl (L = 0.042 m) the part then turns by 0.3 to 6
#: mrad about the stop and one pin, or slides 10 to 170 micrometres back along both pins.
FUNNEL_LIFTS: tuple[float, ...] = (2.5e-4, 1e-3, 4e-3)


# --- directions and margins -------------------------------------------------------------
def margin_function(scenes: Sequence[Scene], mode: str, point, uncertainty
                    ) -> Callable[[float], float]:
    """phi -> the smallest margin over ``scenes`` of the force along phi in ``mode``'s
    robust "all" cone (the worst case over the models; ``uncertainty`` None: the
    nominal model, the zero-width uncertainty, whose "all" cone is the mode's cone)."""
    frame = "com" if point is None else "nominal"
    u = as_uncertainty(uncertainty)
    cones = [(robust_cone(s, mode, u, "all", frame=frame), force_basis(s, point))
             for s in scenes]

    def margin(phi: float) -> float:
        f = np.array([math.cos(phi), math.sin(phi)])
        return min(c.margin(B @ f) for c, B in cones)
    return margin


def best_direction(margin: Callable[[float], float], intervals: Sequence[DirectionInterval]
                   ) -> float:
    """The direction of largest ``margin`` in the intervals: a grid of MARGIN_GRID
    directions per interval, then a bounded scalar search (scipy) between the grid
    neighbours of its best point."""
    from scipy.optimize import minimize_scalar

    best, arg = -math.inf, None
    for iv in intervals:
        grid = np.linspace(iv.lo, iv.hi, MARGIN_GRID)
        vals = [margin(float(p)) for p in grid]
        k = int(np.argmax(vals))
        a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
        phi, val = float(grid[k]), vals[k]
        if b > a:
            r = minimize_scalar(lambda p: -margin(p), bounds=(a, b), method="bounded",
                                options={"xatol": 1e-6})
            if -r.fun > val:
                phi, val = float(r.x), float(-r.fun)
        if val > best:
            best, arg = val, phi
    return arg


def robust_directions(scene: Scene, mode: str, point, uncertainty
                      ) -> list[DirectionInterval]:
    """Directions giving only ``mode`` at the scene's pose (for every model of
    ``uncertainty``, and no other mode for any model: ``force_directions(...,
    exclusive=True, uncertainty=...)``).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The mode.
    point : tuple of 2 float or None
        Where the force acts (m, workpiece frame); None: the com.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model).

    Returns
    -------
    list of DirectionInterval
        The intervals; empty when the mode is not valid at the pose.
    """
    try:
        return force_directions(scene, mode, point, exclusive=True,
                                classifier=ModeClassifier(scene), uncertainty=uncertainty)
    except ModeError:
        return []


def candidate_modes(in_contact: Sequence[bool], target0: set[int]) -> list[str]:
    """Modes that keep the needed contacts and approach a target fixel (module
    docstring); ``target0``: target fixels, 0-based.

    Parameters
    ----------
    in_contact : sequence of bool
        Which fixels touch the part.
    target0 : set of int
        The target fixels (0-based).

    Returns
    -------
    list of str
        The candidate modes.
    """
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


def hold_mode(in_contact: Sequence[bool]) -> str:
    return "".join("n" if c else "s" for c in in_contact)


# --- a moving segment -------------------------------------------------------------------
@dataclass
class Motion:
    """A simulated segment: the stop reason, the fixels reached and lost (0-based), the
    poses, the last pose before the contact, and its duration (s)."""

    reason: str
    reached: tuple[int, ...]
    lost: tuple[int, ...]
    poses: list
    before: tuple[float, float, float] | None
    duration: float


def simulate_segment(scene: Scene, actuator: Actuator, phi: float, kept: Sequence[int],
                     friction=None) -> Motion:
    """Simulate from rest at the scene's pose under phi until a contact event."""
    sim = Simulation(scene, actuator, phi, friction)
    band = SIM_CONTACT_BAND * sim.sp.length_scale
    free = [i for i in range(scene.n_fixels) if not scene.in_contact[i]]
    T = sim.sp.time_scale
    state: dict = {"before": None, "last": tuple(scene.pose)}

    def stop(s: Simulation) -> str | None:
        g = s.gaps()
        reached = tuple(i for i in free if g[i] <= band)
        lost = tuple(i for i in kept if g[i] > band)
        if reached:
            state["reached"] = reached
            state["before"] = state["last"]
            return "reached"
        state["last"] = s.pose
        if lost:
            state["lost"] = lost
            return "lost"
        if s.t > T and s.speed() <= s.velocity_tolerance():
            return "stopped"
        return None

    poses, reason = sim.run_poses(SEGMENT_TIMEOUT * T, stop, record_every=5)
    return Motion(reason, state.get("reached", ()), state.get("lost", ()), poses,
                  state["before"], sim.t)


def segment_path(scene: Scene, motion: Motion, kept: Sequence[int]) -> list | None:
    """PATH_POSES poses of the motion put back onto the kept contacts, then the last
    pose before the contact (the same), then the end pose onto the kept contacts and the
    contacts made; None when a pose cannot be put back."""
    poses = motion.poses
    idx = sorted(set(np.linspace(0, len(poses) - 1, PATH_POSES).round().astype(int)))
    raw = [poses[k] for k in idx[:-1]]
    if motion.before is not None:
        raw.append(motion.before)
    out = [project_pose(scene, p, kept) for p in raw]
    out.append(project_pose(scene, poses[-1], list(kept) + list(motion.reached)))
    return None if any(p is None for p in out) else out


def plan_segment(scene: Scene, mode: str, interval: DirectionInterval, actuator: Actuator,
                 uncertainty: Uncertainty | None, kept: Sequence[int], target0: set[int],
                 direction: float | None = None) -> tuple[Segment | None, str]:
    """One segment in ``mode`` from the scene's pose (module docstring), or None and why
    it was rejected. ``direction``: the one to apply (None: the one of largest
    worst-case margin over its own path).

    Parameters
    ----------
    scene : Scene
        The part at the segment's start pose.
    mode : str
        The segment's mode.
    interval : DirectionInterval
        The directions that give only ``mode`` at the start pose.
    actuator : Actuator
        What pulls the part.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model).
    kept : sequence of int
        The fixels that must stay in contact (0-based).
    target0 : set of int
        The target fixels (0-based).
    direction : float or None, optional
        The direction to apply (rad).

    Returns
    -------
    segment : Segment or None
        The segment.
    reason : str
        Why it was rejected (empty for a segment).
    """
    point = actuator.directions_point
    phi = interval.best if direction is None else float(direction)
    tag = f"{mode} at {math.degrees(phi):.2f} deg"
    nominal = [scene.mu(i) for i in range(scene.n_fixels)]
    for attempt in range(PLAN_REFINEMENTS):
        motion = simulate_segment(scene, actuator, phi, kept, nominal)
        tag = f"{mode} at {math.degrees(phi):.2f} deg"
        if motion.reason != "reached":
            what = {"lost": f"{fixels_text(motion.lost)} lost" if motion.lost else "",
                    "stopped": "the part stopped", "time": "no contact within the time limit"}
            return None, f"{tag}: {what.get(motion.reason, motion.reason)} (simulated)"
        if not set(motion.reached) & target0:
            return None, f"{tag}: reaches {fixels_text(motion.reached)}, not a target (simulated)"
        path = segment_path(scene, motion, kept)
        if path is None:
            return None, f"{tag}: a simulated pose does not fit the kept contacts"
        try:
            sw = sweep(scene, path, mode, point=point, exclusive=True,
                       uncertainty=uncertainty)
            margin = margin_function([scene.with_pose(*p) for p in path[:-1]], mode, point,
                                     uncertainty)
        except SceneError as exc:
            return None, f"{tag}: the simulated path is not valid in the scene ({exc})"
        if sw.stop != len(path) - 1:
            return None, (f"{tag}: not valid along the simulated path (stops at pose "
                          f"{sw.stop} of {len(path)})")
        common = sw.common
        if not common and motion.before is not None:
            # no one direction gives the mode at rest all the way to the contact: the
            # part gets there by its momentum. The interval of the path without the last
            # pose before the contact; the margin (over the whole path) is then not
            # positive, and the segment is not guaranteed quasi-statically.
            common = sweep(scene, path[:-2] + path[-1:], mode, point=point,
                           exclusive=True, uncertainty=uncertainty).common
            select = margin_function([scene.with_pose(*p) for p in path[:-2]], mode, point,
                                     uncertainty)
        else:
            select = margin
        if not common:
            return None, f"{tag}: no direction valid along the whole simulated path"
        inside = [v for v in common if v.contains(phi)]
        if direction is not None:
            if not inside:
                return None, f"{tag}: the direction leaves its interval along its own path"
            break
        best = best_direction(select, common)
        if inside and (abs(best - phi) <= DIRECTION_SETTLE or attempt == PLAN_REFINEMENTS - 1):
            break
        phi = best
    else:
        return None, f"{tag}: the direction leaves its interval along its own path"
    iv = inside[0]
    end_scene = scene.with_pose(*path[-1])
    predicted = tuple(i for i in range(scene.n_fixels)
                      if end_scene.in_contact[i] and not scene.in_contact[i])
    return Segment(mode=mode, interval=iv, direction=phi, margin=margin(phi),
                   start_pose=tuple(scene.pose), end_pose=tuple(path[-1]),
                   event=f"{fixels_text(motion.reached)} reached",
                   predicted_event=(f"{fixels_text(predicted)} reached" if predicted
                                    else "no new contact"),
                   reached=tuple(i + 1 for i in motion.reached),
                   duration=motion.duration), ""


# --- the seated pose: hold, and the funnel around it ------------------------------------
def exclusive_margin(scene: Scene, allowed: Callable[[str], bool], point,
                     uncertainty: Uncertainty | None) -> tuple[Callable[[float], float], list[str]]:
    """phi -> the largest exclusive margin of the force along phi over the valid
    concrete modes of ``scene`` that ``allowed`` admits, and those modes (the ones whose
    robust "all" cone is feasible).

    A mode's exclusive margin is the smallest of its margin in its robust "all" cone and
    minus the margin in every other mode's robust "any" set: > 0 when the force gives
    that mode alone, for every model of ``uncertainty`` (the condition of
    ``force_directions(..., exclusive=True, uncertainty=...)``).

    Parameters
    ----------
    scene : Scene
        The scene (the part at rest at its pose).
    allowed : callable
        mode string -> whether the mode may be the one.
    point : tuple of 2 float or None
        Where the force acts (m, workpiece frame); None: the com.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model).

    Returns
    -------
    margin : callable
        phi (rad, fixture frame) -> the margin (dimensionless; -1 when no mode is
        admitted).
    modes : list of str
        The admitted modes with a feasible "all" cone.
    """
    modes = expand_mode("*" * scene.n_fixels, scene.in_contact)
    alls, anys = robust_classification_cones(
        scene, as_uncertainty(uncertainty), frame="com" if point is None else "nominal")
    admitted = [k for k, m in enumerate(modes) if allowed(m) and alls[k].feasible]
    B = force_basis(scene, point)
    feasible_any = [k for k, c in enumerate(anys) if c.feasible]
    any_sets, all_sets = [anys[k] for k in feasible_any], [alls[k] for k in admitted]

    def margin(phi: float) -> float:
        g = B @ np.array([math.cos(phi), math.sin(phi)])
        y = dict(zip(feasible_any, margins_of(any_sets, g)))  # each set's margin(g)
        inside = dict(zip(admitted, margins_of(all_sets, g)))
        return max((min([inside[k]] + [-v for j, v in y.items() if j != k])
                    for k in admitted), default=-1.0)
    return margin, [modes[k] for k in admitted]


def _approach_margin(scene: Scene, missing: int, point, uncertainty: Uncertainty | None
                     ) -> tuple[Callable[[float], float], list[str], list]:
    """The modes of ``scene`` that approach fixel ``missing`` (0-based), the
    intervals of directions under which each is the only consistent mode for every model
    (``force_directions(..., exclusive=True, uncertainty=...)``), and phi -> the largest
    of their exclusive margins (:func:`exclusive_margin`: > 0 inside the intervals)."""
    margin, approach = exclusive_margin(scene, lambda m: m[missing] == "a", point,
                                        uncertainty)
    found: list[tuple[str, DirectionInterval]] = []
    for mode in approach:
        found += [(mode, iv) for iv in robust_directions(scene, mode, point, uncertainty)]
    return margin, [m for m, _ in found], [iv for _, iv in found]


def funnel_checks(seated: Scene, target0: set[int], point, uncertainty: Uncertainty | None
                  ) -> list[tuple[FunnelCheck, Callable[[float], float], list]]:
    """The near-seated poses of the seated scene and what a direction must do there.

    For every target fixel m and lift in FUNNEL_LIFTS (times L): the part lifted off m by
    the lift, the other target contacts kept (:func:`~.poses.lifted_scene`), when that
    pose exists. There the direction must give only modes that approach m, for every
    model. Each check comes with its margin function and its intervals.

    Parameters
    ----------
    seated : Scene
        The seated scene.
    target0 : set of int
        The target fixels (0-based).
    point : tuple of 2 float or None
        Where the force acts (m, workpiece frame); None: the com.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model).

    Returns
    -------
    list of tuple
        (FunnelCheck, its margin as a function of the direction (rad), its intervals).
    """
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


#: Two hold intervals whose worst-case margins (dimensionless, in [-1, 1]) differ by
#: at most this are tied (a part symmetric in its seat has two of the same margin; the
#: bounded search for an interval's best direction, to 1e-6 rad, leaves margins that
#: should be equal some 1e-9 apart, more in a turned frame).
HOLD_TIE_MARGIN: float = 1e-6


def _hold_order(pool: list[DirectionInterval], previous: float | None
                ) -> list[DirectionInterval]:
    """The order the seat's hold intervals are tried in: largest margin first; ties
    (margins within HOLD_TIE_MARGIN of the largest of their group) nearest the previous
    segment's direction first, a physical order that a turned or mirrored fixture frame
    keeps (the order of the directions' circle, cut at -pi, does not)."""
    def near(iv: DirectionInterval) -> float:
        return 0.0 if previous is None else abs(math.remainder(iv.best - previous,
                                                               2 * math.pi))
    ranked = sorted(pool, key=lambda v: -v.margin)
    out: list[DirectionInterval] = []
    while ranked:
        top = ranked[0].margin
        tied = [v for v in ranked if top - v.margin <= HOLD_TIE_MARGIN]
        out += sorted(tied, key=near)
        ranked = ranked[len(tied):]
    return out


#: Interior points (fractions of the interval, from its low end) of the seat's hold
#: interval that the search tries after the kept and the best directions.
HOLD_FRACTIONS: tuple[float, ...] = (0.5, 0.25, 0.75)


def hold_segments(scene: Scene, previous: float | None, actuator: Actuator,
                  uncertainty: Uncertainty | None, target0: set[int],
                  only: float | None = None) -> tuple[list[Segment], str]:
    """The hold segments to try, best first: the seated pose holds (n at every contact,
    s at free fixels) and every near-seated pose funnels into it (:func:`funnel_checks`).

    Directions: the previous one when it does both (no tilt change), the one of largest
    margin, then interior points of the intervals (HOLD_FRACTIONS), and last the previous
    one when it only holds (its margin, funnel included, is then not positive). Each segment's
    ``margin`` is the smallest of its hold margin and its funnel margins. When no
    direction does both, one segment holds under the previous direction (or the best
    holding one), its margin not positive, and the second value says why; when the
    seated pose holds under no direction, no segment. ``only``: the one direction to hold
    under (a constant tilt's), whatever its margin: one segment, its interval the hold's
    interval that contains it (a single direction when none does).

    Parameters
    ----------
    scene : Scene
        The seated scene.
    previous : float or None
        The direction of the last moving segment (rad).
    actuator : Actuator
        What pulls the part.
    uncertainty : Uncertainty or None
        The model set (None: the nominal model).
    target0 : set of int
        The target fixels (0-based).
    only : float or None, optional
        The one direction to hold under (rad), or None.

    Returns
    -------
    segments : list of Segment
        The hold segments, best first.
    reason : str
        Why no direction both holds and funnels (empty when one does).
    """
    mode = hold_mode(scene.in_contact)
    point = actuator.directions_point
    ivs = robust_directions(scene, mode, point, uncertainty)
    if not ivs and only is None:
        return [], f"the seated pose holds under no direction (mode {mode})"
    hold_margin = margin_function([scene], mode, point, uncertainty)
    checks = funnel_checks(scene, target0, point, uncertainty)

    def margin(phi: float) -> float:
        return min([hold_margin(phi)] + [f(phi) for _c, f, _iv in checks])

    both = common_directions([ivs] + [iv for _c, _f, iv in checks], margin) if ivs else []
    pool = both or ivs
    options: list[tuple[DirectionInterval, float]] = []
    if previous is not None:
        options += [(iv, previous) for iv in pool if iv.contains(previous)][:1]
    for iv in _hold_order(pool, previous):
        options.append((iv, iv.best))
    if both:
        iv = max(both, key=lambda v: v.hi - v.lo)
        options += [(iv, iv.lo + f * (iv.hi - iv.lo)) for f in HOLD_FRACTIONS]
        # last, holds without the funnel (margin not positive: never guaranteed, but a
        # plan the engine may seat when nothing better passes): the previous direction
        options += [(iv, previous) for iv in ivs
                    if previous is not None and iv.contains(previous)][:1]
    else:
        options = options[:1]
    if only is not None:
        inside = [iv for iv in both + ivs if iv.contains(only)]
        options = [(inside[0] if inside else DirectionInterval(only, only, only, 0.0), only)]
    why = ""
    if not both:
        empty = sorted({c.missing for c, _f, v in checks if not v})
        why = ("seating not guaranteed: no direction holds the seated pose and drives every "
               "near-seated pose into it"
               + (" for every model" if uncertainty != NOMINAL else "")
               + (f" (lifted off {fixels_text([m - 1 for m in empty])}, no direction gives "
                  f"only modes that approach it)" if empty else ""))
    out, seen = [], []
    for iv, phi in options:
        if any(abs(phi - q) <= DIRECTION_SETTLE for q in seen):
            continue
        seen.append(phi)
        keep = previous is not None and (phi == previous or only is not None)
        event = "seated: holds" + ("" if keep else " (direction changed)")
        out.append(Segment(mode=mode, interval=iv, direction=phi,
                           margin=margin(phi), start_pose=tuple(scene.pose),
                           end_pose=tuple(scene.pose), event=event, predicted_event=event,
                           hold=True, hold_margin=hold_margin(phi),
                           funnel=tuple(c for c, _f, _iv in checks)))
    return out, why


# --- one constant tilt ------------------------------------------------------------------
#: Angle step (rad) of the constant directions the search tries when no candidate seats
#: the part (6 degrees): the multiples of it inside the seat's hold intervals
#: (:func:`constant_directions`).
CONSTANT_STEP: float = math.radians(6.0)


def constant_directions(seat: Scene, point, anchor: float = 0.0) -> list[float]:
    """The constant directions worth trying from the start to the seat: a direction that
    seats the part and keeps it there must hold the seated pose (mode n at every contact,
    s at the free fixels) in the nominal model, so the directions anchor + k CONSTANT_STEP
    inside the seated pose's nominal hold intervals, in increasing order of their angle
    from anchor + pi (wrapped). The search anchors them at the part's start orientation
    (its pose's theta), so that the same part in a turned fixture frame gets the same
    directions, turned (for a start at theta = 0: the multiples of CONSTANT_STEP from
    -pi)."""
    ivs = robust_directions(seat, hold_mode(seat.in_contact), point, None)
    n = round(2 * math.pi / CONSTANT_STEP)
    ks: set[int] = set()
    for iv in ivs:
        lo = math.remainder(iv.lo - anchor, 2 * math.pi)  # the interval relative to anchor
        hi = lo + (iv.hi - iv.lo)
        for k in range(math.ceil(lo / CONSTANT_STEP - 1e-9),
                       math.floor(hi / CONSTANT_STEP + 1e-9) + 1):
            ks.add(k % n)
    rel = sorted(math.remainder(k * CONSTANT_STEP, 2 * math.pi) for k in ks)
    return [math.remainder(anchor + r, 2 * math.pi) if anchor else r for r in rel]


def constant_segment(scene: Scene, phi: float, actuator: Actuator,
                     uncertainty: Uncertainty | None, target0: set[int],
                     end_pose: tuple[float, float, float]) -> Segment:
    """The moving segment of a constant direction phi that takes the part from the
    scene's pose to every target fixel (``end_pose``: where the engine seated it).

    The mode is the one the engine shows at the start (:func:`~..simulate.initial_mode`);
    when it is a candidate mode and one segment in it under phi reaches every target
    fixel not yet touched (:func:`plan_segment`, the direction imposed), that segment,
    with its interval and worst-case margin. Otherwise the part changes mode on the way
    (an impact, a bounce): the segment is not certified by the cones, its interval is
    phi alone and its margin 0 (not positive: a plan with it is never guaranteed)."""
    contact = {i for i, c in enumerate(scene.in_contact) if c}
    todo = tuple(sorted(target0 - contact))
    nominal = [scene.mu(i) for i in range(scene.n_fixels)]
    mode = initial_mode(scene, phi, actuator, nominal)
    if mode in candidate_modes(scene.in_contact, target0):
        seg, _why = plan_segment(scene, mode, DirectionInterval(phi, phi, phi, 0.0),
                                 actuator, uncertainty, sorted(contact), target0, phi)
        if seg is not None and set(seg.reached) == {i + 1 for i in todo}:
            return seg
    return Segment(mode=mode, interval=DirectionInterval(phi, phi, phi, 0.0), direction=phi,
                   margin=0.0, start_pose=tuple(scene.pose), end_pose=tuple(end_pose),
                   event=f"{fixels_text(todo)} reached",
                   predicted_event="not predicted (the cones certify no one mode on the way)",
                   reached=tuple(i + 1 for i in todo))
