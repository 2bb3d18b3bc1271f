# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Stages 2 to 4 of a design: hold, funnel and plan, Monte Carlo; each on the scene of
one placement, with the core's robust cones and the seating planner.

The scene of a design (:func:`design_scene`): the part at its seated pose, the three
pins as fixels (the plate's pin radius), the part's nominal friction, contact tolerance
DESIGN_CONTACT_TOLERANCE_M; the core checks again that all three pins touch and none
penetrates (a SceneError otherwise).

* **Hold** (:func:`hold`): the directions of the actuator's pull under which the seated
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
* **Monte Carlo** (:func:`monte_carlo`): the plan run in pymunk for ``runs`` models
  sampled from the uncertainty (seeded); the success rate.
"""

from __future__ import annotations

import math

from ..core.plan import (
    GOAL_GUARANTEED,
    GOAL_SEATED,
    hold_segments,
    plan_seating,
    robust_directions,
)
from ..core.scene import Fixel, Scene, SceneError, Workpiece
from .problem import DEFAULT_PLAN_CANDIDATES, DESIGN_CONTACT_TOLERANCE_M, DesignProblem


ENCLOSED = ("no translation frees the part from its seat: the pins enclose it (it can "
            "only be loaded from above)")


def design_scene(problem: DesignProblem, positions, pose) -> Scene:
    """The scene of a design (module docstring).

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part, the pin radius, the nominal friction).
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).

    Returns
    -------
    Scene
        The part at ``pose`` with the three pins as fixels.

    Raises
    ------
    SceneError
        A pin penetrates the part at that pose.
    """
    wp = problem.part.workpiece
    r = problem.plate.pin_radius
    return Scene(workpiece=Workpiece(wp.mass, wp.inertia, wp.shape, wp.com),
                 fixels=tuple(Fixel(tuple(p), r) for p in positions),
                 friction=problem.part.friction, pose=tuple(pose),
                 contact_tolerance=DESIGN_CONTACT_TOLERANCE_M)


def hold(problem: DesignProblem, positions, pose) -> dict:
    """The hold columns of one design: hold_lo, hold_hi, best_tilt (rad), hold_margin,
    and ``enclosed`` (no translation frees the part: :func:`loading_direction`);
    ``reason`` when it does not hold.

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    positions : sequence of (x, y)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        The part's seated pose (x m, y m, theta rad).

    Returns
    -------
    dict
        The hold columns, or ``reason`` alone.
    """
    try:
        scene = design_scene(problem, positions, pose)
    except SceneError as exc:
        return {"reason": f"the core refuses the seated scene: {exc}"}
    if not all(scene.in_contact):
        return {"reason": "the core does not see all three pins in contact"}
    ivs = robust_directions(scene, "nnn", problem.actuator.directions_point,
                            problem.uncertainty)
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


def plan(problem: DesignProblem, positions, pose, runs: int = 0, seed: int = 0,
         max_candidates: int = DEFAULT_PLAN_CANDIDATES) -> dict:
    """The funnel and plan columns of one design (module docstring); with ``runs`` > 0
    also the Monte Carlo success rate of those runs.

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

    Returns
    -------
    dict
        The funnel and plan columns (and ``reason`` when the design fails a stage).
    """
    scene = design_scene(problem, positions, pose)
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
    p = plan_seating(start, [1, 2, 3], act, unc, runs=runs, seed=seed, workers=1,
                     simulate_runs=runs > 0, max_candidates=max_candidates,
                     goal=GOAL_GUARANTEED if out["funnel_ok"] else GOAL_SEATED)
    out.update(plan_feasible=p.feasible, plan_guaranteed=p.guaranteed,
               plan_segments=len(p.segments),
               plan_nominal_seated=bool(p.nominal is not None and p.nominal.success),
               plan_directions=";".join(f"{s.direction:.6f}" for s in p.segments),
               plan_modes=";".join(s.mode for s in p.segments))
    if runs > 0 and p.runs:
        out["success_rate"] = p.success_rate
        out["mc_runs"] = len(p.runs)
    if not p.feasible:
        out["reason"] = f"no loading plan: {p.reason}"
    elif not out["funnel_ok"]:
        out["reason"] = why
    return out


__all__ = ["ENCLOSED", "design_scene", "hold", "loading_direction", "plan"]
