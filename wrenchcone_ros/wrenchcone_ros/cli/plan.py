# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone plan``: the tilts (or spring pulls) that seat the part, checked in pymunk.

    wrenchcone plan SCENE.yaml --target 1 2 3 [--actuator tilt|spring --point X Y]
        [--friction LO HI | --friction LO1 HI1 LO2 HI2 ...] [--mass LO HI]
        [--inertia LO HI] [--com-radius R | --com-box HX HY] [--normal-error DELTA]
        [--uncertainty FILE] [--runs N] [--seed S] [--workers W]
        [--max-candidates N] [--max-trials N] [--budget SECONDS]
        [--start-region DX DY DTHETA [--region-candidates N] [--draw out.png]]
        [--animate out.gif] [--json]
        [--exit-code]

A progress bar on stderr counts the Monte Carlo runs (only on a terminal). Exit status:
0 when a plan is found (1: none; 2: bad input); with ``--exit-code``, 0 only when the
plan is guaranteed, 1 for a plan that is not, 2 for no plan or bad input.
"""

from __future__ import annotations

import math

from ..core.plan import (
    DEFAULT_MAX_CANDIDATES,
    DEFAULT_MAX_TRIALS,
    DEFAULT_RUNS,
    DEFAULT_SEED,
    DEFAULT_WORKERS,
    REGION_CANDIDATES,
    plan_seating,
)
from ..core.simulate import DEFAULT_TILT, Actuator, SimulationUnavailable
from ..core.uncertainty import Uncertainty, as_uncertainty, load_uncertainty
from .options import add_point, add_scene, point_value, scene_value
from .render import plan_answer
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
    sp.add_argument("--start-region", nargs=3, type=float, default=None,
                    metavar=("DX", "DY", "DTHETA"),
                    help="plan for every start in the box x +- DX m, y +- DY m, theta +- "
                    "DTHETA degrees around the scene's pose: the plan is run from a grid "
                    "of starts of the box under every model of the capture test, and the "
                    "box is shrunk per axis until it holds (the output says which box "
                    "holds and what is claimed)")
    sp.add_argument("--region-candidates", type=int, default=REGION_CANDIDATES, metavar="N",
                    help="with --start-region: most plans the search certifies over the "
                    "box (its first, then, while none holds from the whole box, the next "
                    "ones in its order); the one with the largest certified box is chosen "
                    "(default %(default)s; 1: the first plan only)")
    sp.add_argument("--animate", default=None, metavar="FILE",
                    help="write an animation of the nominal run (.gif or .mp4); with "
                    "--start-region, of starts drawn in the certified box seating together")
    sp.add_argument("--draw", default=None, metavar="FILE",
                    help="with --start-region: a picture (.png, .svg or .pdf) of the "
                    "certified box, each segment's entry region (the poses at which runs "
                    "from the box enter it) and the paths of starts drawn in the box")
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


def _uncertainty(args, n: int) -> Uncertainty:
    """The Uncertainty the options describe (friction intervals, the planner's
    shorthand, with the other parameters; :data:`~wrenchcone_ros.core.NOMINAL` for
    none)."""
    friction = _friction(args.friction, n)
    fields = {"mass": args.mass, "inertia": args.inertia, "com_radius": args.com_radius,
              "com_box": args.com_box, "normal_error": args.normal_error}
    base = load_uncertainty(args.uncertainty) if args.uncertainty else None
    if base is None and all(v is None for v in fields.values()):
        return as_uncertainty(friction)
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


def run(args) -> str:
    scene = scene_value(args.scene)
    act = _actuator(args)
    uncertainty = _uncertainty(args, scene.n_fixels)
    if args.workers < 1:
        raise ValueError(f"--workers must be >= 1, got {args.workers}")
    for flag, value in (("--max-candidates", args.max_candidates),
                        ("--max-trials", args.max_trials),
                        ("--region-candidates", args.region_candidates)):
        if value < 1:
            raise ValueError(f"{flag} must be a whole number >= 1, got {value}")
    if args.budget is not None and not (math.isfinite(args.budget) and args.budget > 0):
        raise ValueError(f"--budget must be a positive number of seconds, got {args.budget:g}")
    region = None
    if args.start_region is not None:
        dx, dy, dth = args.start_region
        if not all(math.isfinite(v) and v >= 0 for v in args.start_region) or dth > 180:
            raise ValueError("--start-region takes DX DY (m) and DTHETA (degrees, at most "
                             f"180), each a finite number >= 0, got {dx:g} {dy:g} {dth:g}")
        region = (dx, dy, math.radians(dth))
    if args.draw is not None:
        if region is None:
            raise ValueError("--draw needs --start-region DX DY DTHETA (it draws the "
                             "region of starts)")
        if not args.draw.lower().endswith((".png", ".svg", ".pdf")):
            raise ValueError(f"--draw {args.draw}: the format must be .png, .svg or .pdf")
    if args.animate and not args.animate.lower().endswith((".gif", ".mp4")):
        raise ValueError(f"--animate {args.animate}: the format must be .gif or .mp4")
    pictures: list[str] = []
    update, bar = _progress() if not args.json else (None, None)
    try:
        plan = plan_seating(scene, args.target, act, uncertainty, runs=args.runs,
                            seed=args.seed, workers=args.workers, progress=update,
                            budget=args.budget, max_candidates=args.max_candidates,
                            max_trials=args.max_trials, start_region=region,
                            region_candidates=args.region_candidates)
        if region is not None and (args.draw or args.animate) and plan.feasible:
            pictures = _region_pictures(scene, plan, args)
        elif args.animate and plan.feasible:
            from ..core.animate import animate_plan

            animate_plan(scene, plan, args.animate)
            pictures = [f"animation: {args.animate}"]
    except SimulationUnavailable as exc:
        raise ValueError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    if args.exit_code:
        args.exit_status = 0 if plan.guaranteed else 1 if plan.feasible else 2
    else:
        args.exit_status = 0 if plan.feasible else 1  # no plan: 1, bad input: 2
    out = plan_answer(args, plan)
    if pictures and not args.json:
        out += "\n" + "\n".join(pictures)
    return out


def _region_pictures(scene, plan, args) -> list[str]:
    """The region's picture (``--draw``) and animation (``--animate``), from one set of
    runs; a line per file written, or why none was."""
    from ..core.animate import animate_region, draw_region, region_runs

    if plan.start_region is None:
        return ["picture: none (no start region certified)"]
    runs = region_runs(scene, plan, seed=args.seed)
    out = []
    if args.draw:
        d = draw_region(scene, plan, args.draw, runs=runs)
        drawn = len(d.paths)
        out.append(f"picture: {args.draw} (the certified box, {len(d.entries)} segments' "
                   f"entry regions from {len(runs)} nominal runs, {drawn} drawn starts' "
                   "paths)")
    if args.animate:
        animate_region(scene, plan, args.animate, runs=runs)
        out.append(f"animation: {args.animate} (the drawn starts seating together)")
    return out
