# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Stages 2 to 4 of a design: hold, funnel and plan, Monte Carlo; each on the scene of
one placement, with the core's robust cones and the seating planner.

The scene of a design (:func:`design_scene`): the part at its seated pose, the three
pins as fixels, each of its own radius (the plate's one pin radius when it offers one),
the part's nominal friction, contact tolerance
DESIGN_CONTACT_TOLERANCE_M; the core checks again that all three pins touch and none
penetrates (a SceneError otherwise).

* **Hold** (:func:`hold`, on :func:`hold_scene`: every contact of every pin, two for a
  pin in a concave corner): the directions of the actuator's pull under which the seated
  part holds, mode ``nnn`` and no other mode, for every model of the friction
  uncertainty (``force_directions(..., exclusive=True, uncertainty=...)``, the robust
  cones); of the intervals, the one of largest margin: its ``lo`` / ``hi``, its best
  direction and that direction's worst-case margin (the robust ``all`` cone's margin,
  dimensionless). A tray tilt's direction is the downhill direction in the plate.
* **Funnel and plan** (:func:`plan`): the seat's funnel as the planner checks it
  (``core.plan.hold_segments``: the near-seated poses drive into the seat for every
  model; its margin is the smallest of the hold and funnel margins at its direction),
  and the seating plan (``core.plan.plan_seating``) from the loading start
  (:func:`loading_direction`): the seat moved back by the problem's ``start_offset``
  against the loading direction; feasible, guaranteed (every segment's worst-case margin
  positive) and whether its nominal simulation seats the part. A design whose seat has
  no funnel cannot have a guaranteed plan (its three pins fix the seated pose, so every
  plan ends there): its search stops at the first candidate whose nominal run seats the
  part (the planner's GOAL_SEATED), where a search for a guarantee would run to its
  bound for nothing. A search ends after DEFAULT_PLAN_CANDIDATES candidates (or the
  planner's DEFAULT_MAX_TRIALS segments), bounds of work, never of time, so that the row
  is the same on every machine.
* **Start region** (in :func:`plan`, when the problem has a ``start_region`` and the
  plan is feasible): the plan run from a cover of the box of start poses around the
  loading start under every model of the planner's capture test, the box shrunk per
  axis until it holds (``core.plan.certify_region`` with the problem's
  :class:`~.problem.RegionWork`); the row gets the certified half-widths, their size
  (:func:`region_size`), the volume fraction, the engine runs and the last failure.
  Only designs that reach the loading stage plan a region, and only once: the Monte
  Carlo stage keeps the plan stage's region.
* **Monte Carlo** (:func:`plan` with ``runs``): the plan run in pymunk for ``runs``
  models sampled from the uncertainty (seeded); the success rate. With the plan stage's
  certified start region (``mc_region``), each run starts at a pose drawn uniformly in
  that box (``core.plan.run_region_samples``), as ``plan_seating`` does for a region;
  without one, at the loading start.
"""

from __future__ import annotations

import math
from dataclasses import replace

from ..core.plan import (
    GOAL_GUARANTEED,
    GOAL_SEATED,
    RegionCertificate,
    StartRegion,
    certify_region,
    hold_segments,
    plan_seating,
    robust_directions,
    run_region_samples,
)
from ..core.geometry import Fixel, SceneError, Workpiece
from ..core.scene import Scene
from .geometry import Features, pin_contacts
from .problem import (
    DEFAULT_PLAN_CANDIDATES,
    DESIGN_CONTACT_TOLERANCE_M,
    DesignError,
    DesignProblem,
)


ENCLOSED = ("no translation frees the part from its seat: the pins enclose it (it can "
            "only be loaded from above)")


def pin_radii(problem: DesignProblem, radii=None) -> tuple[float, ...]:
    """Each pin's radius (m): ``radii`` as given, or the plate's one pin radius for all
    three.

    Parameters
    ----------
    problem : DesignProblem
        The problem (its plate).
    radii : sequence of 3 float or None, optional
        Each pin's radius (m).

    Returns
    -------
    tuple of 3 float
        m.

    Raises
    ------
    DesignError
        No radii given on a plate that offers several.
    """
    if radii is not None:
        if len(radii) != 3:
            raise DesignError(f"give the radius of each of the 3 pins (m), got {radii!r}")
        return tuple(float(r) for r in radii)
    r = problem.plate.pin_radius
    if r is None or problem.plate.mixed:
        raise DesignError(f"the plate's pins differ in radius ({list(problem.plate.pin_radii)}"
                          f" m, fixed {list(problem.plate.fixed_radii)} m): give each pin's "
                          "radius")
    return (r, r, r)


def design_scene(problem: DesignProblem, positions, pose, radii=None) -> Scene:
    """The scene of a design (module docstring).

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part, the pin radius, the nominal friction).
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).
    radii : sequence of 3 float or None, optional
        Each pin's radius (m); None: the plate's one pin radius (:func:`pin_radii`).

    Returns
    -------
    Scene
        The part at ``pose`` with the three pins as fixels, each of its radius.

    Raises
    ------
    SceneError
        A pin penetrates the part at that pose.
    DesignError
        No radii on a plate of several.
    """
    wp = problem.part.workpiece
    rs = pin_radii(problem, radii)
    return Scene(workpiece=Workpiece(wp.mass, wp.inertia, wp.shape, wp.com),
                 fixels=tuple(Fixel(tuple(p), r) for p, r in zip(positions, rs)),
                 friction=problem.part.friction, pose=tuple(pose),
                 contact_tolerance=DESIGN_CONTACT_TOLERANCE_M)


def hold_scene(problem: DesignProblem, positions, pose, contacts=None, radii=None) -> Scene:
    """The scene whose contacts are every contact of the design (module docstring): a
    pin with one contact is itself; a pin touching the part at several points (a concave
    corner) becomes one fixel per contact, of half the pin's radius, centred halfway
    between the pin's centre and the contact point: inside the pin, tangent to the part
    at that point only, with the same contact point and normal.

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).
    contacts : sequence of 3 sequences of PinContact or None, optional
        Every contact of each pin (:func:`.geometry.pin_contacts`); None: computed here.
    radii : sequence of 3 float or None, optional
        Each pin's radius (m); None: the plate's one pin radius (:func:`pin_radii`).

    Returns
    -------
    Scene
        The scene; the pins' scene (:func:`design_scene`) when no pin has two contacts.

    Raises
    ------
    SceneError
        A pin penetrates the part at that pose.
    DesignError
        No radii on a plate of several.
    """
    rs = pin_radii(problem, radii)
    if contacts is None:
        contacts = [pin_contacts(Features.of(problem.vertices, r), pose, c,
                                 DESIGN_CONTACT_TOLERANCE_M) for c, r in zip(positions, rs)]
    if all(len(cs) <= 1 for cs in contacts):
        return design_scene(problem, positions, pose, rs)
    fixels = []
    for c, cs, r in zip(positions, contacts, rs):
        if len(cs) <= 1:
            fixels.append(Fixel(tuple(c), r))
        else:
            fixels += [Fixel(((c[0] + ct.point[0]) / 2, (c[1] + ct.point[1]) / 2), r / 2)
                       for ct in cs]
    wp = problem.part.workpiece
    return Scene(workpiece=Workpiece(wp.mass, wp.inertia, wp.shape, wp.com),
                 fixels=tuple(fixels), friction=problem.part.friction, pose=tuple(pose),
                 contact_tolerance=DESIGN_CONTACT_TOLERANCE_M)


def merge_wrapped(intervals) -> list:
    """Direction intervals with pieces that meet across +-pi joined into one (``lo`` the
    first piece's, ``hi`` past pi; the best direction and margin of the better piece).

    Parameters
    ----------
    intervals : sequence of DirectionInterval
        The intervals.

    Returns
    -------
    list of DirectionInterval
        The same intervals, those that meet across +-pi joined.
    """
    out = list(intervals)
    joined = True
    while joined:
        joined = False
        for a in out:
            for b in out:
                if a is b or a.hi - a.lo >= 2 * math.pi:
                    continue
                if abs(math.remainder(a.hi - b.lo, 2 * math.pi)) <= 1e-12 and \
                        abs(a.hi - b.lo) > math.pi:
                    hi = b.hi + (a.hi - b.lo)  # b moved by the 2 pi between them
                    best = a if a.margin >= b.margin else b
                    shift = 0.0 if best is a else a.hi - b.lo
                    merged = replace(a, hi=min(hi, a.lo + 2 * math.pi),
                                     best=best.best + shift, margin=best.margin)
                    out = [v for v in out if v is not a and v is not b] + [merged]
                    joined = True
                    break
            if joined:
                break
    return out


def hold(problem: DesignProblem, positions, pose, contacts=None, radii=None) -> dict:
    """The hold columns of one design: hold_lo, hold_hi, best_tilt (rad), hold_margin,
    and ``enclosed`` (no translation frees the part: :func:`loading_direction`);
    ``reason`` when it does not hold. Every contact of the pins counts (:func:`hold_scene`:
    a pin in a concave corner holds the part at both of its edges); an interval that
    crosses +-180 degrees is one interval (``hold_hi`` may exceed pi).

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).
    contacts : sequence of 3 sequences of PinContact or None, optional
        Every contact of each pin (None: computed from the geometry).
    radii : sequence of 3 float or None, optional
        Each pin's radius (m); None: the plate's one pin radius.

    Returns
    -------
    dict
        The hold columns, or ``reason`` alone.
    """
    try:
        scene = hold_scene(problem, positions, pose, contacts, radii)
    except SceneError as exc:
        return {"reason": f"the core refuses the seated scene: {exc}"}
    if not all(scene.in_contact):
        return {"reason": "the core does not see every pin's contacts"}
    ivs = merge_wrapped(robust_directions(scene, "n" * scene.n_fixels,
                                          problem.actuator.directions_point,
                                          problem.uncertainty))
    if not ivs:
        return {"reason": "holds under no direction for every model"}
    iv = max(ivs, key=lambda v: v.margin)
    return {"hold_lo": iv.lo, "hold_hi": iv.hi, "best_tilt": iv.best,
            "hold_margin": iv.margin, "hold_intervals": len(ivs),
            "enclosed": loading_direction(scene, iv.best) is None}


def loading_direction(scene: Scene, phi: float) -> float | None:
    """The direction (rad) along which the part arrives at its seat: the pull's own
    direction phi when moving the seated part back against it frees it from all three
    pins (every n_k . u <= 0, n_k the unit normal from pin k into the part), else the
    translation that frees it fastest (the largest smallest -n_k . d over unit d: among
    the -n_k and the directions where two of the n_k . d are equal); None when no
    translation frees it (the pins enclose the part: it can only be loaded from above).

    Parameters
    ----------
    scene : Scene
        The seated scene.
    phi : float
        The pull's direction (rad).

    Returns
    -------
    float or None
        The loading direction (rad), or None for an enclosed part.
    """
    n = scene.contact_arrays.n
    u = (math.cos(phi), math.sin(phi))
    if all(nk[0] * u[0] + nk[1] * u[1] <= 0 for nk in n):
        return phi
    cands = [math.atan2(-nk[1], -nk[0]) for nk in n]
    for i in range(3):
        for j in range(i + 1, 3):
            dx, dy = n[i][0] - n[j][0], n[i][1] - n[j][1]
            if dx or dy:  # (n_i - n_j) . d = 0
                base = math.atan2(dy, dx)
                cands += [base + math.pi / 2, base - math.pi / 2]

    def worst(a: float) -> float:
        return min(nk[0] * math.cos(a) + nk[1] * math.sin(a) for nk in n)
    best = max(cands, key=worst)  # d with the largest min n_k . d: moving by d frees it
    return math.atan2(-math.sin(best), -math.cos(best)) if worst(best) > 0 else None


def region_size(cert: RegionCertificate) -> float:
    """The size of a certified start region, the ranking's measure: the mean, over the
    axes the asked box spans (half-width > 0), of the certified half-width over the
    asked one; in [0, 1], 1 for the whole asked box, 0 when not even the loading start
    is certified. Unlike the volume fraction (their product), it does not drop to 0 as
    soon as one axis certifies nothing (a pawl's designs seldom hold a turn of a
    degree, and would all tie at 0).

    Parameters
    ----------
    cert : RegionCertificate
        The planner's region result.

    Returns
    -------
    float
        The size, dimensionless.
    """
    if cert.certified is None:
        return 0.0
    pairs = [(c, a) for c, a in zip(cert.certified.half_widths, cert.asked.half_widths)
             if a > 0]
    return sum(c / a for c, a in pairs) / len(pairs) if pairs else 1.0


def region_columns(cert: RegionCertificate) -> dict:
    """A design's start-region columns from the planner's region result: region_size
    (:func:`region_size`), region_fraction (the certified volume over the asked one),
    region_dx, region_dy (m), region_dtheta (rad) (None when nothing is certified),
    region_runs (engine runs made), region_failure (the last box that failed and why).

    Parameters
    ----------
    cert : RegionCertificate
        The planner's region result.

    Returns
    -------
    dict
        The columns.
    """
    box = cert.certified
    dx, dy, dth = (None, None, None) if box is None else box.half_widths
    return {"region_size": region_size(cert), "region_fraction": cert.fraction,
            "region_dx": dx, "region_dy": dy, "region_dtheta": dth,
            "region_runs": cert.runs, "region_failure": cert.failure}


def plan(problem: DesignProblem, positions, pose, runs: int = 0, seed: int = 0,
         max_candidates: int = DEFAULT_PLAN_CANDIDATES, radii=None,
         region: bool = True, mc_region=None) -> dict:
    """The funnel and plan columns of one design (module docstring); with ``runs`` > 0
    also the Monte Carlo success rate of those runs; with the problem's start region
    (and ``region``) the region columns (:func:`region_columns`).

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).
    runs : int, optional
        Monte Carlo runs of the plan (0: none).
    seed : int, optional
        The seed of the sampled models.
    max_candidates : int, optional
        The most candidate plans the search tries (DEFAULT_PLAN_CANDIDATES).
    radii : sequence of 3 float or None, optional
        Each pin's radius (m); None: the plate's one pin radius.
    region : bool, optional
        False: no start region even when the problem has one (the Monte Carlo stage,
        which keeps the plan stage's region).
    mc_region : StartRegion, sequence of 3 float or None, optional
        The box (half-widths around the loading start) the Monte Carlo's starts are
        drawn in: the plan stage's certified region. None, or a box of zero size: every
        run starts at the loading start.

    Returns
    -------
    dict
        The funnel and plan columns (and ``reason`` when the design fails a stage).
    """
    scene = design_scene(problem, positions, pose, radii)
    act, unc = problem.actuator, problem.uncertainty
    segs, why = hold_segments(scene, None, act, unc, {0, 1, 2})
    seg = segs[0] if segs else None  # the best first
    out: dict = {}
    if seg is None:
        return {"reason": why, "funnel_ok": False}
    out["funnel_ok"] = not why
    out["funnel_margin"] = seg.margin
    out["funnel_tilt"] = seg.direction
    phi = loading_direction(scene, seg.direction)
    if phi is None:
        out.update(plan_feasible=False, plan_guaranteed=False, reason=ENCLOSED)
        return out
    out["load_direction"] = phi
    x, y, th = pose
    off = problem.start_offset
    try:
        start = scene.with_pose(x - off * math.cos(phi), y - off * math.sin(phi), th)
    except SceneError as exc:
        out.update(plan_feasible=False, plan_guaranteed=False,
                   reason=f"the loading start is not free ({exc})")
        return out
    box = None if mc_region is None else StartRegion.of(mc_region)
    from_region = runs > 0 and box is not None and any(box.half_widths)
    p = plan_seating(start, [1, 2, 3], act, unc, runs=runs, seed=seed, workers=1,
                     simulate_runs=runs > 0 and not from_region,
                     max_candidates=max_candidates,
                     goal=GOAL_GUARANTEED if out["funnel_ok"] else GOAL_SEATED)
    if from_region and p.feasible:
        p = replace(p, runs=tuple(run_region_samples(start, p, box, unc, runs, seed,
                                                     workers=1)))
    out.update(plan_feasible=p.feasible, plan_guaranteed=p.guaranteed,
               plan_segments=len(p.segments),
               plan_nominal_seated=bool(p.nominal is not None and p.nominal.success),
               plan_directions=";".join(f"{s.direction:.6f}" for s in p.segments),
               plan_modes=";".join(s.mode for s in p.segments))
    if region and problem.start_region is not None and p.feasible:
        w = problem.region_work
        out.update(region_columns(certify_region(
            start, p, problem.start_region, unc, grid=w.grid, bisections=w.bisections,
            sampled=w.sampled, draws=w.draws, seed=seed, workers=1)))
    if runs > 0 and p.runs:
        out["success_rate"] = p.success_rate
        out["mc_runs"] = len(p.runs)
        out["mc_start_region"] = from_region
    if not p.feasible:
        out["reason"] = f"no loading plan: {p.reason}"
    elif not out["funnel_ok"]:
        out["reason"] = why
    return out


__all__ = ["ENCLOSED", "design_scene", "hold", "hold_scene", "loading_direction",
           "merge_wrapped", "pin_radii", "plan", "region_columns", "region_size"]
