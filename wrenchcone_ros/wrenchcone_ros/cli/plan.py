# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone plan``: the tilts (or spring pulls) that seat the part, checked in pymunk.

    wrenchcone plan SCENE.yaml --target 1 2 3 [--actuator tilt|spring --point X Y]
        [--friction LO HI | --friction LO1 HI1 LO2 HI2 ...] [--runs N] [--seed S]
        [--workers W] [--animate out.gif] [--json]

A progress bar on stderr counts the Monte Carlo runs (only on a terminal).
"""

from __future__ import annotations

import json
import math

from ..core.plan import DEFAULT_RUNS, DEFAULT_SEED, DEFAULT_WORKERS, plan_seating
from ..core.simulate import DEFAULT_TILT, Actuator, SimulationUnavailable
from .options import add_point, add_scene, point_value, scene_value

NAME = "plan"
HELP = "a plan of tilts or spring pulls that seats the part, checked in simulation"


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
    sp.add_argument("--runs", type=int, default=DEFAULT_RUNS,
                    help="Monte Carlo runs over the friction interval (default %(default)s)")
    sp.add_argument("--seed", type=int, default=DEFAULT_SEED, help="seed of the runs")
    sp.add_argument("--workers", type=int, default=DEFAULT_WORKERS,
                    help="processes for the runs (default %(default)s)")
    sp.add_argument("--animate", default=None, metavar="FILE",
                    help="write an animation of the nominal run (.gif or .mp4)")


def _friction(values, n: int):
    if values is None:
        return None
    if len(values) == 2:
        return tuple(values)
    if len(values) == 2 * n:
        return [tuple(values[2 * i:2 * i + 2]) for i in range(n)]
    raise ValueError(f"--friction takes LO HI (every fixel) or LO HI per fixel "
                     f"({2 * n} numbers), got {len(values)} number(s)")


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


def text(plan) -> str:
    """The plan as the CLI prints it."""
    act = plan.actuator
    what = ("tray tilt" if act.kind == "tilt" else
            f"spring at ({act.point[0]:g}, {act.point[1]:g}) m (workpiece frame)")
    fr = ("nominal friction" if plan.friction is None else
          "friction " + ", ".join(sorted({f"[{lo:g}, {hi:g}]" for lo, hi in plan.friction})))
    out = [f"plan to seat the part on fixel(s) {' '.join(map(str, plan.target))} "
           f"({what}; {fr}; directions in degrees, fixture frame):",
           "   #  mode      interval lo .. hi    direction   margin  end pose (x m, y m, "
           "theta rad)  event"]
    for k, s in enumerate(plan.segments):
        lo, hi = (math.degrees(v) for v in s.interval)
        x, y, th = s.end_pose
        out.append(f"{k + 1:>4}  {s.mode:<8} {lo:>9.2f} .. {hi:>7.2f}  {math.degrees(s.direction):>10.2f}"
                   f"  {s.margin:>7.4f}  ({x:.5f}, {y:.5f}, {th:.5f})  {s.event}")
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
    elif plan.friction is None:
        out.append("no friction interval given: only the nominal model was simulated")
    if plan.reason:
        out.append(plan.reason)
    return "\n".join(out)


def run(args) -> str:
    scene = scene_value(args.scene)
    act = _actuator(args)
    friction = _friction(args.friction, scene.n_fixels)
    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    update, bar = _progress() if not args.json else (None, None)
    try:
        plan = plan_seating(scene, args.target, act, friction, runs=args.runs,
                            seed=args.seed, workers=args.workers, progress=update)
        if args.animate and plan.feasible:
            from ..core.animate import animate_plan

            animate_plan(scene, plan, args.animate)
    except SimulationUnavailable as exc:
        raise ValueError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    args.exit_status = 0 if plan.feasible else 1  # no plan: 1, bad input: 2
    if args.json:
        return json.dumps(plan.to_dict())
    out = text(plan)
    if args.animate and plan.feasible:
        out += f"\nanimation: {args.animate}"
    return out
