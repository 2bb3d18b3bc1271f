# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone plan``: the tilts (or spring pulls) that seat the part, checked in pymunk.

    wrenchcone plan SCENE.yaml --target 1 2 3 [--actuator tilt|spring --point X Y]
        [--friction LO HI | --friction LO1 HI1 LO2 HI2 ...] [--mass LO HI]
        [--inertia LO HI] [--com-radius R | --com-box HX HY] [--normal-error DELTA]
        [--uncertainty FILE] [--runs N] [--seed S] [--workers W]
        [--max-candidates N] [--max-trials N] [--budget SECONDS]
        [--animate out.gif] [--json] [--exit-code]

A progress bar on stderr counts the Monte Carlo runs (only on a terminal). Exit status:
0 when a plan is found (1: none; 2: bad input); with ``--exit-code``, 0 only when the
plan is guaranteed, 1 for a plan that is not, 2 for no plan or bad input.
"""

from __future__ import annotations

import json
import math

from ..core.plan import (
    DEFAULT_MAX_CANDIDATES,
    DEFAULT_MAX_TRIALS,
    DEFAULT_RUNS,
    DEFAULT_SEED,
    DEFAULT_WORKERS,
    plan_seating,
)
from ..core.simulate import DEFAULT_TILT, Actuator, SimulationUnavailable
from ..core.uncertainty import NOMINAL, Uncertainty, load_uncertainty
from .options import add_point, add_scene, point_value, scene_value
from .render import fixed
from .uncertain import add_model_options



def add_arguments(sp) -> None:
    add_scene(sp)
    sp.add_argument("--target", nargs="+", type=int, required=True, metavar="FIXEL",
                    help="fixels (1-based) that must touch the seated part")
    sp.add_argument("--actuator", choices=("tilt", "spring"), default="tilt",
                    help="tray tilt (force at the com) or a spring at --point")
    add_point(sp, help="the spring's hook, workpiece frame, m (--actuator spring)")
    sp.add_argument("--tilt", type=float, default=math.degrees(DEFAULT_TILT),
                    help="tray tilt angle, degrees (0, 90] (default %(default)g)")
    sp.add_argument("--friction", nargs="+", type=float, default=None, metavar="MU",
                    help="friction interval LO HI for every fixel, or LO HI per fixel")
    g = sp.add_argument_group("other uncertain parameters (robust plans, sampled runs)")
    add_model_options(g, " (robust cones only: not simulated)")
    g.add_argument("--uncertainty", metavar="FILE",
                   help="YAML uncertainty (or a scene file with an uncertainty: block); "
                   "the options above override its fields")
    sp.add_argument("--runs", type=int, default=DEFAULT_RUNS,
                    help="Monte Carlo runs over the uncertain models (default %(default)s)")
    sp.add_argument("--seed", type=int, default=DEFAULT_SEED, help="seed of the runs")
    sp.add_argument("--workers", type=int, default=DEFAULT_WORKERS,
                    help="processes for the runs (default %(default)s)")
    sp.add_argument("--max-candidates", type=int, default=DEFAULT_MAX_CANDIDATES,
                    metavar="N", help="most complete candidate plans the search simulates "
                    "(default %(default)s; the same plan on every machine)")
    sp.add_argument("--max-trials", type=int, default=DEFAULT_MAX_TRIALS, metavar="N",
                    help="most segments the search plans and simulates (default "
                    "%(default)s)")
    sp.add_argument("--budget", type=float, default=None, metavar="SECONDS",
                    help="opt-in cap on the search's time after its first descent, in CPU "
                    "seconds of the planning thread (default: none; a plan it cuts says so "
                    "and may differ from machine to machine)")
    sp.add_argument("--animate", default=None, metavar="FILE",
                    help="write an animation of the nominal run (.gif or .mp4)")
    sp.add_argument("--exit-code", action="store_true",
                    help="exit 0 if the plan is guaranteed, 1 if it is not, 2 if there is "
                    "no plan (or bad input)")


def _friction(values, n: int):
    if values is None:
        return None
    if len(values) == 2:
        return tuple(values)
    if len(values) == 2 * n:
        return [tuple(values[2 * i:2 * i + 2]) for i in range(n)]
    raise ValueError(f"--friction takes LO HI (every fixel) or LO HI per fixel "
                     f"({2 * n} numbers), got {len(values)} number(s)")


def _uncertainty(args, n: int):
    """None, friction intervals (the planner's shorthand), or an Uncertainty when another
    parameter is uncertain."""
    friction = _friction(args.friction, n)
    fields = {"mass": args.mass, "inertia": args.inertia, "com_radius": args.com_radius,
              "com_box": args.com_box, "normal_error": args.normal_error}
    base = load_uncertainty(args.uncertainty) if args.uncertainty else None
    if base is None and all(v is None for v in fields.values()):
        return friction
    d = {} if base is None else base.to_dict()
    d.update({k: v for k, v in fields.items() if v is not None})
    if friction is not None:
        d["friction"] = friction if isinstance(friction, tuple) else list(friction)
    d.pop("seed", None)
    return Uncertainty(**d)


def _actuator(args) -> Actuator:
    point = point_value(args.point)
    if not (0 < args.tilt <= 90):
        raise ValueError(f"--tilt must be in (0, 90] degrees, got {args.tilt}")
    if args.actuator == "spring":
        if point is None:
            raise ValueError("--actuator spring needs --point X Y (the hook, workpiece "
                             "frame, m)")
        return Actuator("spring", tilt=math.radians(args.tilt), point=tuple(point))
    if point is not None:
        raise ValueError("--point is the spring's hook: use it with --actuator spring")
    return Actuator("tilt", tilt=math.radians(args.tilt))


def _progress():
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency of the dev set
        return None, None
    bar = tqdm(total=0, unit="run", desc="simulated models", leave=False, disable=None)

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.update(done - bar.n)
    return update, bar


def _uncertainty_text(plan) -> str:
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


def text(plan) -> str:
    """The plan as the CLI prints it."""
    act = plan.actuator
    what = ("tray tilt" if act.kind == "tilt" else
            f"spring at ({act.point[0]:g}, {act.point[1]:g}) m (workpiece frame)")
    force = "tilt" if act.kind == "tilt" else "force"
    out = [f"plan to seat the part on fixel(s) {' '.join(map(str, plan.target))} "
           f"({what}; {_uncertainty_text(plan)}; directions in degrees, fixture frame):",
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
        out.append(f"sampled models: {ok} of {len(plan.runs)} seated (success rate "
                   f"{100.0 * plan.success_rate:.1f} %, seed {plan.seed}); events as "
                   f"planned in {len(plan.runs) - plan.contradicted} of {len(plan.runs)}")
        fails = [r for r in plan.runs if not r.success]
        for r in fails[:5]:
            out.append(f"  failed: mu {[round(m, 4) for m in r.friction]}: {r.reason}")
    elif plan.uncertainty == NOMINAL:  # none given
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


def run(args) -> str:
    scene = scene_value(args.scene)
    act = _actuator(args)
    uncertainty = _uncertainty(args, scene.n_fixels)
    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    for flag, value in (("--max-candidates", args.max_candidates),
                        ("--max-trials", args.max_trials)):
        if value < 1:
            raise ValueError(f"{flag} must be a whole number >= 1, got {value}")
    if args.budget is not None and not (math.isfinite(args.budget) and args.budget > 0):
        raise ValueError(f"--budget must be a positive number of seconds, got {args.budget:g}")
    update, bar = _progress() if not args.json else (None, None)
    try:
        plan = plan_seating(scene, args.target, act, uncertainty, runs=args.runs,
                            seed=args.seed, workers=args.workers, progress=update,
                            budget=args.budget, max_candidates=args.max_candidates,
                            max_trials=args.max_trials)
        if args.animate and plan.feasible:
            from ..core.animate import animate_plan

            animate_plan(scene, plan, args.animate)
    except SimulationUnavailable as exc:
        raise ValueError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    if args.exit_code:
        args.exit_status = 0 if plan.guaranteed else 1 if plan.feasible else 2
    else:
        args.exit_status = 0 if plan.feasible else 1  # no plan: 1, bad input: 2
    if args.json:
        return json.dumps(plan.to_dict())
    out = text(plan)
    if args.animate and plan.feasible:
        out += f"\nanimation: {args.animate}"
    return out
