# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The one printer of the CLI's answers: cone, check, classify, directions and sweep
(:func:`cone_answer`, :func:`check_answer`, :func:`classify_answer`,
:func:`directions_answer`, :func:`sweep_answer`; ``wrenchcone plan`` prints its plan with
:func:`plan_answer`), as text or, with ``--json``, as one JSON object whose keys are the
same whatever the uncertainty (the nominal model's answer is the answer for the
zero-width uncertainty: its "every model" and "some model" verdicts agree).

The subcommands compute an answer (the core decides, from the uncertainty, how) and hand
it here. The text names the model set and the guarantee only when the question named one
(:func:`models_named`); that is wording, not another computation.

Printed numbers are rounded: a cone's rows to PRINT_DIGITS significant digits, with an
entry below PRINT_ZERO (core/tolerances.py) in the nondimensional metric printed as 0;
angles and margins to fixed decimals. No printed number is ``-0``. The ``--json`` outputs
carry the computed values unrounded.
"""

from __future__ import annotations

import json
import math

import numpy as np

from ..core import Scene
from ..core.tolerances import PRINT_ZERO

#: Significant digits of the printed entries of a cone's rows.
PRINT_DIGITS: int = 6

CONE_KEYS = ("mode", "feasible", "F", "equalities", "G", "lineality", "length_scale",
             "method")


def fixed(x: float, decimals: int) -> str:
    """``x`` with ``decimals`` decimals, never ``-0.000``."""
    return f"{round(x, decimals) + 0.0:.{decimals}f}"


def pose_text(pose, length_scale: float) -> str:
    """A pose (x m, y m, theta rad) to PRINT_DIGITS significant digits, a coordinate below
    PRINT_ZERO times the workpiece's length scale (or an angle below PRINT_ZERO rad)
    printed as 0."""
    scales = (length_scale, length_scale, 1.0)
    shown = [0.0 if abs(v) < PRINT_ZERO * s else v + 0.0 for v, s in zip(pose, scales)]
    return "(" + ", ".join(f"{v:.{PRINT_DIGITS}g}" for v in shown) + ")"


def shown_rows(rows, unit_rows):
    """``rows`` as printed: entries whose counterpart in ``unit_rows`` (the same rows in
    the nondimensional metric, unit vectors) is below PRINT_ZERO set to 0, ``-0`` to 0."""
    rows = np.asarray(rows, dtype=float)
    return np.where(np.abs(np.asarray(unit_rows, dtype=float)) < PRINT_ZERO, 0.0, rows) + 0.0


def table(name: str, rows, unit_rows=None) -> list[str]:
    """A matrix as an indented list of rows under a header with the row count; with
    ``unit_rows``, round-off entries print as 0 (:func:`shown_rows`)."""
    rows = shown_rows(rows, rows if unit_rows is None else unit_rows)
    out = [f"{name} ({rows.shape[0]} row{'s' if rows.shape[0] != 1 else ''}):"]
    out += ["  [" + ", ".join(f"{v: .{PRINT_DIGITS}g}" for v in r) + "]" for r in rows]
    if rows.shape[0] == 0:
        out.append("  (none)")
    return out


def cone_lines(cone) -> list[str]:
    """One mode's cone: verdict, then F, E, G and the lineality space."""
    lines = [f"mode {cone.mode!r} ({cone.method}, {'exact' if cone.exact else 'float'}): "
             + ("feasible" if cone.feasible else
                "INFEASIBLE: no wrench realises this mode (the open mode is impossible)"),
             "g = (fx N, fy N, tz N m) is consistent iff F g <= 0 and E g = 0"]
    lines += table("F", cone.F, cone.F_hat)
    lines += table("E (equalities)", cone.equalities, cone.E_hat)
    return lines + table("G (generators)", cone.G, cone.G_hat) + table("lineality",
                                                                      cone.lineality,
                                                                      cone.L_hat)


def where(scene: Scene, point) -> str:
    """Where the force acts, in words."""
    if point is None:
        cx, cy = scene.workpiece.com
        return f"at the com ({cx:.6g}, {cy:.6g}) m"
    return f"at ({point[0]:.6g}, {point[1]:.6g}) m"


def interval_rows(intervals) -> list[str]:
    """A table of direction intervals, degrees and radians (exact endpoints if known)."""
    head = (f"  {'#':>2}  {'lo deg':>10}  {'hi deg':>10}  {'width deg':>9}  {'best deg':>10}"
            f"  {'margin':>9}  {'lo rad':>10}  {'hi rad':>10}  {'best rad':>10}")
    out = [head]
    for k, iv in enumerate(intervals, 1):
        out.append(f"  {k:>2}  {fixed(math.degrees(iv.lo), 4):>10}  "
                   f"{fixed(math.degrees(iv.hi), 4):>10}  {fixed(math.degrees(iv.width), 4):>9}  "
                   f"{fixed(math.degrees(iv.best), 4):>10}  {fixed(iv.margin, 6):>9}  "
                   f"{fixed(iv.lo, 6):>10}  {fixed(iv.hi, 6):>10}  {fixed(iv.best, 6):>10}")
        if iv.lo_direction is not None:
            out.append(f"      exact directions: lo ({iv.lo_direction[0]}, {iv.lo_direction[1]})"
                       f", hi ({iv.hi_direction[0]}, {iv.hi_direction[1]})")
    return out


# --- the answers ------------------------------------------------------------------------
def models_named(U) -> bool:
    """Whether the question named a model set (an uncertainty option or a scene file's
    ``uncertainty:`` block with a parameter): its text then says which set and what
    guarantee the answer carries; otherwise the answer is worded as the nominal model's.
    The CLI's one test of the uncertainty, for words only."""
    return U.describe() != "none"


def emit(args, data: dict, text) -> str:
    """``data`` as one line of JSON with ``--json``, else ``text()`` (a callable returning
    the lines, or a string)."""
    if args.json:
        return json.dumps(data)
    out = text()
    return out if isinstance(out, str) else "\n".join(out)


def guarantee_line(guarantee) -> str:
    """``guarantee: ...`` (:class:`~wrenchcone_ros.core.Guarantee`)."""
    return f"guarantee: {guarantee}"


def cone_dict(cone) -> dict:
    """A convex cone's JSON keys (:data:`CONE_KEYS`)."""
    d = cone.to_dict()
    return {k: d[k] for k in CONE_KEYS}


def cone_answer(args, ws, U) -> str:
    """A mode's set of wrenches (:class:`~wrenchcone_ros.core.WrenchSet`): a concrete
    mode's cone, a wildcard's union, a robust "all" or "any" set.

    JSON: ``mode``, ``feasible``, ``quantifier``, ``frame``, ``guarantee`` (text),
    ``uncertainty``, ``impossible`` (a wildcard's infeasible modes), ``pieces`` (the
    convex cones of the union, :data:`CONE_KEYS` each) and ``cone`` (the one piece, or
    null for a union of several)."""
    data = {"mode": ws.mode, "feasible": ws.feasible, "quantifier": ws.quantifier,
            "frame": ws.frame, "guarantee": str(ws.guarantee), "uncertainty": U.to_dict(),
            "impossible": list(ws.impossible), "pieces": [cone_dict(c) for c in ws.pieces],
            "cone": cone_dict(ws.pieces[0]) if len(ws.pieces) == 1 else None}

    def text() -> list[str]:
        lines = []
        if models_named(U):
            who = "every model" if ws.quantifier == "all" else "some model"
            lines.append(f"wrenches consistent with {ws.mode!r} for {who} of: "
                         f"{U.describe()} (frame {ws.frame}; {guarantee_line(ws.guarantee)})")
            if len(ws.pieces) != 1:
                return lines + [f"the union of {len(ws.pieces)} cones, one per sampled "
                                "model (--json lists them)"]
        if len(ws.pieces) == 1 and not ws.impossible and ws.pieces[0].mode == ws.mode:
            return lines + cone_lines(ws.pieces[0])
        lines.append(f"mode {ws.mode!r} is the union of {len(ws.pieces)} feasible mode "
                     f"cone(s) {[c.mode for c in ws.pieces]}; g is consistent iff it is in "
                     "one of them")
        if ws.impossible:
            lines.append(f"infeasible (no wrench realises them): {list(ws.impossible)}")
        for piece in ws.pieces:
            lines += [""] + cone_lines(piece)
        return lines

    return emit(args, data, text)


def check_answer(args, g, g_hat, every_set, some_set, U) -> str:
    """Is the wrench ``g`` consistent with the mode: for every model (``every_set``, the
    "all" set) and for some model (``some_set``, the "any" set); for the nominal model
    the two are one cone and agree.

    JSON: ``mode``, ``feasible``, ``consistent`` and ``margin`` (for every model: the
    worst case), ``consistent_every_model``, ``consistent_some_model``, ``margin_all``,
    ``margin_any``, ``guarantee`` (text), ``uncertainty``."""
    every, some = bool(every_set.contains(g_hat)), bool(some_set.contains(g_hat))
    m_all, m_any = float(every_set.margin(g_hat)), float(some_set.margin(g_hat))
    feasible = bool(every_set.feasible or some_set.feasible)
    data = {"mode": every_set.mode, "feasible": feasible, "consistent": every,
            "margin": m_all, "consistent_every_model": every, "consistent_some_model": some,
            "margin_all": m_all, "margin_any": m_any, "guarantee": str(every_set.guarantee),
            "uncertainty": U.to_dict()}

    def text() -> str:
        if models_named(U):
            verdict = ("consistent for every model" if every else
                       "consistent for some model only" if some else
                       "consistent for no model")
            return (f"wrench {g} with mode {every_set.mode!r}: {verdict} ({U.describe()}); "
                    f"worst-case margin {m_all:.6g}, best-case margin {m_any:.6g}; "
                    f"{guarantee_line(every_set.guarantee)}")
        verdict = "consistent" if every else "NOT consistent"
        extra = "" if feasible else " (the mode is infeasible)"
        return (f"wrench {g} is {verdict} with mode {every_set.mode!r}{extra}; "
                f"margin {m_all:.6g}")

    return emit(args, data, text)


def classify_answer(args, g, found, U) -> str:
    """Every mode the wrench ``g`` is consistent with (:class:`~wrenchcone_ros.core.classify.ModeMatch`).

    JSON: ``wrench``, ``uncertainty``, ``modes`` (each ``mode``, ``certain``,
    ``possible``, ``margin``, ``margin_all``, ``margin_any``, ``guarantee``)."""
    data = {"wrench": g, "uncertainty": U.to_dict(), "modes": [m.to_dict() for m in found]}

    def text() -> list[str]:
        if models_named(U):
            if not found:
                return [f"wrench {g} is consistent with no mode for any model "
                        f"({U.describe()})"]
            return ([f"wrench {g} may produce {len(found)} mode(s) ({U.describe()}; "
                     f"{guarantee_line(found[0].guarantee)}):"]
                    + [f"  {m.mode}  {'certain ' if m.certain else 'possible'}  worst-case "
                       f"margin {m.margin_all:.6g}  best-case margin {m.margin_any:.6g}"
                       for m in found])
        if not found:
            return [f"wrench {g} is consistent with no mode"]
        return ([f"wrench {g} is consistent with {len(found)} mode(s):"]
                + [f"  {m.mode}  margin {m.margin:.6g}" for m in found])

    return emit(args, data, text)


def _giving(mode: str, exclusive: bool, U) -> str:
    what = f"only mode {mode!r}" if exclusive else f"mode {mode!r}"
    return what + (f" for every model of {U.describe()}" if models_named(U) else "")


def directions_answer(args, scene, point, ivs, U) -> str:
    """The force directions at ``point`` that give the mode (intervals).

    JSON: ``mode``, ``point``, ``exclusive``, ``exact``, ``intervals``, ``uncertainty``."""
    data = {"mode": args.mode, "point": point, "exclusive": args.exclusive,
            "exact": args.exact, "intervals": [iv.to_dict() for iv in ivs],
            "uncertainty": U.to_dict()}

    def text() -> list[str]:
        head = (f"force directions {where(scene, point)} (workpiece frame) giving "
                f"{_giving(args.mode, args.exclusive, U)} (fixture frame, "
                f"counter-clockwise from +x; {'exact' if args.exact else 'float'}):")
        if not ivs:
            return [head, "  none"]
        tail = ([f"guarantee: {ivs[0].guarantee}; margin and best: the worst case over the "
                 "models"] if models_named(U) else [])
        return [head] + interval_rows(ivs) + tail

    return emit(args, data, text)


def sweep_answer(args, scene, point, res, U) -> str:
    """A sweep along a path (:class:`~wrenchcone_ros.core.SweepResult`).

    JSON: ``mode``, ``point``, ``exclusive``, ``poses``, ``intervals`` (per pose, null
    from the stop on), ``common``, ``stop``, ``stop_reason``, ``after`` (the modes at the
    stop, as in classify), ``uncertainty``."""
    data = {"mode": res.mode, "point": point, "exclusive": args.exclusive,
            "poses": [list(p) for p in res.poses],
            "intervals": [None if ivs is None else [iv.to_dict() for iv in ivs]
                          for ivs in res.intervals],
            "common": [iv.to_dict() for iv in res.common], "stop": res.stop,
            "stop_reason": res.stop_reason, "after": [m.to_dict() for m in res.after],
            "uncertainty": U.to_dict()}

    def text() -> list[str]:
        out = [f"force directions {where(scene, point)} giving "
               f"{_giving(res.mode, args.exclusive, U)} along {len(res.poses)} poses "
               "(degrees):"]
        for k, (pose, ivs) in enumerate(zip(res.poses, res.intervals)):
            p = pose_text(pose, scene.length_scale)
            if ivs is None:
                out.append(f"  pose {k:>3} {p}: " + ("STOP" if k == res.stop else "-"))
            else:
                spans = ", ".join(f"[{fixed(math.degrees(iv.lo), 4)}, "
                                  f"{fixed(math.degrees(iv.hi), 4)}]" for iv in ivs)
                out.append(f"  pose {k:>3} {p}: {spans}")
        if res.stop is not None:
            out.append(f"stops at pose {res.stop}: {' '.join(res.stop_reason.split())}")
        else:
            out.append("holds at every pose")
        n = res.stop if res.stop is not None else len(res.poses)
        out.append(f"valid at every pose before that ({n}):" if res.stop is not None else
                   f"valid at all {n} poses:")
        out += interval_rows(res.common) if res.common else ["  none"]
        if res.after and models_named(U):
            best = math.degrees(res.common[0].best)
            out.append(f"at pose {res.stop} the force along {best:.4f} deg may give: "
                       + ", ".join(f"{m.mode} ({'certain' if m.certain else 'possible'})"
                                   for m in res.after))
        elif res.after:
            best = math.degrees(res.common[0].best)
            out.append(f"at pose {res.stop} the force along {best:.4f} deg gives: "
                       + ", ".join(f"{m.mode} (margin {m.margin:.6g})" for m in res.after))
        elif res.stop is not None and res.common:
            out.append(f"at pose {res.stop} the force along "
                       f"{math.degrees(res.common[0].best):.4f} deg is consistent with no "
                       "mode")
        return out

    return emit(args, data, text)


# --- plans --------------------------------------------------------------------------------
def _plan_models(plan) -> str:
    """The plan's model set in one phrase ("nominal model" when none was given)."""
    u = plan.uncertainty
    parts = []
    if plan.friction is not None and any(lo < hi for lo, hi in plan.friction):
        parts.append("friction " + ", ".join(sorted({f"[{lo:g}, {hi:g}]"
                                                     for lo, hi in plan.friction})))
    for name, unit in (("mass", "kg"), ("inertia", "kg m^2"), ("com_radius", "m"),
                       ("com_box", "m"), ("normal_error", "rad")):
        v = getattr(u, name)
        if v is not None:
            shown = (f"[{v[0]:g}, {v[1]:g}]" if isinstance(v, tuple) and len(v) == 2
                     and name != "com_box" else
                     f"+-({v[0]:g}, {v[1]:g})" if name == "com_box" else f"+-{v:g}"
                     if not isinstance(v, tuple) else str(list(v)))
            parts.append(f"{name.replace('_', ' ')} {shown} {unit}")
    return "; ".join(parts) or "nominal model"


def plan_text(plan) -> str:
    """The plan as the CLI prints it."""
    act = plan.actuator
    what = ("tray tilt" if act.kind == "tilt" else
            f"spring at ({act.point[0]:g}, {act.point[1]:g}) m (workpiece frame)")
    force = "tilt" if act.kind == "tilt" else "force"
    out = [f"plan to seat the part on fixel(s) {' '.join(map(str, plan.target))} "
           f"({what}; {_plan_models(plan)}; directions in degrees, fixture frame):",
           f"   #  mode      interval lo .. hi    direction  accuracy  {force:>6}   margin"
           "  end pose (x m, y m, theta rad)  event"]
    for k, s in enumerate(plan.segments):
        lo, hi = math.degrees(s.interval.lo), math.degrees(s.interval.hi)
        x, y, th = s.end_pose
        mag = (f"{fixed(plan.tilt_deg(s), 2):>6}" if act.kind == "tilt" else f"x{s.scale:<5g}")
        out.append(f"{k + 1:>4}  {s.mode:<8} {fixed(lo, 2):>9} .. {fixed(hi, 2):>7}  "
                   f"{fixed(math.degrees(s.direction), 2):>10}  "
                   f"+-{fixed(math.degrees(s.accuracy), 2):<6}  {mag}  {fixed(s.margin, 4):>7}  "
                   f"({fixed(x, 5)}, {fixed(y, 5)}, {fixed(th, 5)})  {s.event}")
        if s.predicted_event != s.event:
            out.append(f"      predicted from the geometry: {s.predicted_event}")
    if not plan.feasible:
        out.append(f"no plan: {plan.reason}")
        return "\n".join(out)
    n = plan.nominal
    out.append(f"nominal simulation: {'seated' if n.success else 'NOT seated: ' + n.reason}"
               f", fixels reached in order {list(n.events)}"
               + ("" if n.matches else " (the plan predicted otherwise)"))
    if plan.runs:
        ok = sum(r.success for r in plan.runs)
        starts = (", starts drawn uniformly in the certified start region"
                  if plan.runs[0].start is not None else "")
        out.append(f"sampled models: {ok} of {len(plan.runs)} seated (success rate "
                   f"{100.0 * plan.success_rate:.1f} %, seed {plan.seed}{starts}); events as "
                   f"planned in {len(plan.runs) - plan.contradicted} of {len(plan.runs)}")
        fails = [r for r in plan.runs if not r.success]
        for r in fails[:5]:
            at = ("" if r.start is None else
                  " from (" + ", ".join(fixed(v, 5) for v in r.start) + ")")
            out.append(f"  failed: mu {[round(m, 4) for m in r.friction]}{at}: {r.reason}")
    elif not models_named(plan.uncertainty):
        out.append("no uncertainty given: only the nominal model was simulated")
    acc = min(s.accuracy for s in plan.segments)
    if plan.guaranteed:
        engines = len(plan.engine_checks)
        n = len(plan.checks) - engines
        models = ("the nominal model" if n == 1 else
                  f"the nominal and {n - 1} boundary models")
        under = f", and the nominal one under {engines} other engine settings" if engines else ""
        out.append(f"guaranteed ({plan.guarantee}): every segment's worst-case margin is "
                   f"positive, and the part is captured at every contact event ({models} "
                   f"simulated{under}, inelastic impacts); each direction must be held to "
                   f"within +-{math.degrees(acc):.2f} deg")
    else:
        out.append("NOT guaranteed: missing " + "; ".join(plan.missing))
    if plan.region is not None:
        out += region_lines(plan.region)
    if plan.out_of_time:
        out.append("the search was cut by its time budget (--budget): another machine may "
                   "find another plan")
    if plan.reason and not plan.reason.startswith("not guaranteed"):
        out.append(plan.reason)
    elif plan.reason and "; " in plan.reason:
        rest = plan.reason.split("; ", 1)[1]
        extra = [r for r in rest.split("; ") if r not in "; ".join(plan.missing)]
        if extra:
            out.append("; ".join(extra))
    return "\n".join(out)


def region_lines(cert) -> list[str]:
    """The start region's lines of :func:`plan_text`: the box asked, the box certified
    (the fraction of the asked one when only part holds), what is claimed, the work;
    each later segment's entry region and its check as a funnel; with a region search (``region_candidates`` > 1), how many plans were certified,
    which was chosen, and each one's region (the chosen one starred)."""
    asked = cert.asked.text()
    if cert.certified is None:
        head = f"start region {asked}: none certified"
    elif cert.whole:
        head = f"start region {asked}: the whole box certified"
    else:
        head = (f"start region {asked}: only {cert.certified.text()} certified "
                f"({100.0 * cert.fraction:.1f} % of the asked box's volume)")
    out = [head + f": {cert.claim} ({cert.boxes} box(es) checked, {cert.runs} runs; "
           "the verdict above is for the scene's pose)"]
    if cert.failure:
        out.append(f"  the last box that failed, {cert.failure}")
    for funnel in cert.segment_funnels:  # each later segment's entry region
        out.append(f"funnel: {funnel.verdict()}")
        out.append(f"  entry region: {funnel.text()}")
    for piece in cert.cone_slices:  # where the part rests on a segment's contacts
        out.append(f"cones: {piece.verdict()}")
    if len(cert.compared) == 1 and cert.compared[0].candidate == 0:
        out.append("region search: no candidate plan met the search's goal: its plan was "
                   f"certified alone (at most {cert.limit} would have been compared)")
    elif len(cert.compared) == 1:
        out.append(f"region search: 1 candidate plan certified (at most {cert.limit}): "
                   + ("it holds from the whole box" if cert.whole else
                      "the search has no other that meets its goal"))
    elif cert.compared:
        out.append(f"region search: {len(cert.compared)} candidate plans certified (at "
                   f"most {cert.limit}), chosen: candidate {cert.chosen} (the largest "
                   "certified fraction of the asked volume, then of each axis on average; "
                   f"{cert.compared_boxes} box(es), {cert.compared_runs} runs in all)")
        out += [f"  {'*' if c.index == cert.chosen else ' '} {c.text()}" for c in cert.compared]
    return out


def plan_answer(args, plan) -> str:
    """A plan (:class:`~wrenchcone_ros.core.plan.Plan`): its ``to_dict()`` as JSON (the
    same keys whatever the uncertainty: ``uncertainty`` is the model set planned for, the
    zero-width one for the nominal model), else :func:`plan_text`."""
    return emit(args, plan.to_dict(), lambda: plan_text(plan))
