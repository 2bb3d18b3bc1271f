# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone design``: where three pins go on a modular plate, ranked.

    wrenchcone design PART.yaml --plate PLATE.yaml [--friction LO HI] [--top K]
        [--plans N] [--runs N] [--seed S] [--start-offset M]
        [--start-region DX DY DTHETA | --no-start-region] [--rank KEYS]
        [--actuator tilt|spring --point X Y] [--scheduler ADDR | --workers N]
        [--batch N] [--plan-candidates N] --out designs.parquet [--plot FILE]
        [--keep-parts]

Runs :func:`wrenchcone_ros.design.design_fixtures` (docs/fixture_design.md): every
design in the Parquet file, the top ones as a table on stdout, then a line per file
written, a progress bar on stderr (on a terminal). Every option is checked before the
work starts (one line on stderr, exit code 2); the heavy parts (Dask, pyarrow, the
planner) are imported only then. Each finished batch is stored under ``OUT.parts/``: an
interrupted run resumes when the same command is run again; after a complete run the
folder is removed unless ``--keep-parts``. Needs dask.distributed and pyarrow (``pip
install .[design]``).
"""

from __future__ import annotations

import math
import os
import shutil
import sys
from pathlib import Path

from ..design.problem import (
    DEFAULT_BATCH_TRIPLES,
    DEFAULT_PLAN_CANDIDATES,
    DEFAULT_PLANS,
    DEFAULT_RUNS,
    DEFAULT_SEED,
    DEFAULT_START_OFFSET_M,
    DEFAULT_START_REGION,
    DEFAULT_TOP,
    DesignError,
    DesignProblem,
    load_plate,
)
from ..design.plot import SHEET_DESIGNS
from ..design.rank import DEFAULT_RANKING, RANK_KEYS, REGION_RANKING, parse_ranking


#: The formats of the ``--plot`` sheet (matplotlib's writers for them).
PLOT_FORMATS: tuple[str, ...] = (".png", ".svg", ".pdf")


def add_arguments(sp) -> None:
    sp.add_argument("part", help="scene YAML whose workpiece is the part (a polygon)")
    sp.add_argument("--plate", required=True, help="plate YAML (pitch, extent, pin_radius "
                    "or pin_radii, keep_out, fixed_pins)")
    sp.add_argument("--friction", nargs=2, type=float, default=None, metavar=("LO", "HI"),
                    help="friction interval of every pin (default: the part's mu)")
    sp.add_argument("--top", type=int, default=DEFAULT_TOP,
                    help="designs run in Monte Carlo and printed (default %(default)s)")
    sp.add_argument("--plans", type=int, default=DEFAULT_PLANS,
                    help="holding designs planned (default %(default)s)")
    sp.add_argument("--runs", type=int, default=DEFAULT_RUNS,
                    help="Monte Carlo models per top design (default %(default)s)")
    sp.add_argument("--seed", type=int, default=DEFAULT_SEED, help="seed of the runs")
    sp.add_argument("--start-offset", type=float, default=DEFAULT_START_OFFSET_M,
                    metavar="M", help="loading task: start this far from the seat, m "
                    "(default %(default)g)")
    dx, dy, dth = DEFAULT_START_REGION
    region = sp.add_mutually_exclusive_group()
    region.add_argument("--start-region", nargs=3, type=float,
                        default=[dx, dy, math.degrees(dth)],
                        metavar=("DX", "DY", "DTHETA"),
                        help="loading task: the box of start poses around the loading "
                        "start, x +- DX m, y +- DY m, theta +- DTHETA degrees (a "
                        "gripper's placement error); each planned design plans the "
                        "region its plan certifies, and the ranking uses its size "
                        f"(default {dx:g} {dy:g} {math.degrees(dth):g})")
    region.add_argument("--no-start-region", action="store_true",
                        help="plan from the loading start only (no region columns; the "
                        "ranking without region_size)")
    sp.add_argument("--rank", default=None, metavar="KEYS",
                    help=f"ranking, comma-separated, from {', '.join(RANK_KEYS)} "
                    f"(default {','.join(REGION_RANKING)}; with --no-start-region "
                    f"{','.join(DEFAULT_RANKING)})")
    sp.add_argument("--actuator", default="tilt",
                    help="'tilt' (tray tilt, default) or 'spring:X,Y' (hook, part frame, m)")
    sp.add_argument("--scheduler", default=None, metavar="ADDR",
                    help="a Dask scheduler's address (default: a LocalCluster)")
    sp.add_argument("--workers", type=int, default=None,
                    help="LocalCluster workers, >= 0 (default: one per core; 0: no Dask, "
                    "this process)")
    sp.add_argument("--batch", type=int, default=DEFAULT_BATCH_TRIPLES,
                    help="pin triples per batch (default %(default)s)")
    sp.add_argument("--plan-candidates", type=int, default=DEFAULT_PLAN_CANDIDATES,
                    metavar="N", help="most candidate plans a design's loading search tries "
                    "(default %(default)s)")
    sp.add_argument("--out", required=True, help="Parquet file of every design; its "
                    "finished batches go to OUT.parts/ as they end: to resume an "
                    "interrupted run, run the same command again")
    sp.add_argument("--keep-parts", action="store_true",
                    help="keep OUT.parts/ after a complete run (default: removed)")
    sp.add_argument("--plot", default=None, metavar="FILE",
                    help="sheet of the top designs and the trade-off scatter "
                    f"({', '.join(PLOT_FORMATS)})")


def _clean(v: float, digits: int) -> float:
    """v rounded to the digits printed, without a negative zero."""
    return round(v, digits) + 0.0


def _deg(v) -> str:
    return "-" if v is None else f"{_clean(math.degrees(v), 2):8.2f}"


def _num(v, fmt: str, digits: int = 3) -> str:
    return "-" if v is None else format(_clean(v, digits), fmt)


def _radii(r) -> str:
    """The pins' radii of a row, mm, comma-separated."""
    return ",".join("-" if r.get(f"pin{k}_r") is None else f"{r[f'pin{k}_r'] * 1000:.6g}"
                    for k in (1, 2, 3))


def _region(r) -> str:
    """A row's region column: the certified region's size in percent."""
    v = r.get("region_size")
    return "-" if v is None else f"{100 * v:.0f} %"


def summary(result, top: int, region: bool = False) -> str:
    """The terminal summary: counts per stage, then the top designs (with each pin's
    radius, mm, when the pins of the designs differ in radius; with the certified start
    region's size when ``region``)."""
    rows = result.rows
    mixed = len({r.get(f"pin{k}_r") for r in rows for k in (1, 2, 3)}) > 1
    count = {s: sum(r["stage"] == s for r in rows)
             for s in ("geometry", "location", "hold", "plan", "monte_carlo")}
    located = sum(bool(r["located"]) for r in rows)
    holding = sum(r["hold_margin"] is not None for r in rows)
    planned = count["plan"] + count["monte_carlo"]
    guaranteed = sum(bool(r["plan_guaranteed"]) for r in rows)
    lines = [f"{len(rows)} placements on the plate: {located} located, {holding} hold for "
             f"every model, {planned} planned, {guaranteed} with a guaranteed plan; "
             f"ranking: {', '.join(result.ranking)}",
             "rank  pins (i,j)              " + ("radii mm        " if mixed else "")
             + "pose x m  y m      theta deg  features   "
             "accuracy  hold lo..hi deg      best deg  margin  funnel  plan        "
             + ("region  " if region else "") + "success",
             ]
    for r in rows[:top]:
        pins = " ".join(f"({r[f'pin{k}_i']},{r[f'pin{k}_j']})" for k in (1, 2, 3))
        plan = ("guaranteed" if r["plan_guaranteed"] else "feasible" if r["plan_feasible"]
                else "none" if r["plan_feasible"] is not None else "-")
        rate = "-" if r["success_rate"] is None else f"{100 * r['success_rate']:.0f} %"
        lines.append(
            f"{r['rank']:4d}  {pins:22s}  " + (f"{_radii(r):14s}  " if mixed else "")
            + f"{_num(r['x'], '7.4f', 4)}  {_num(r['y'], '7.4f', 4)}  "
            f"{_deg(r['theta'])}  {r['features']:9s}  "
            f"{_num(r['locating_accuracy'], '8.3f')}  {_deg(r['hold_lo'])}..{_deg(r['hold_hi'])}"
            f"  {_deg(r['best_tilt'])}  {_num(r['hold_margin'], '6.3f')}  "
            f"{_num(r['funnel_margin'], '6.3f')}  {plan:10s}  "
            + (f"{_region(r):6s}  " if region else "") + rate)
        if r["reason"]:
            lines.append(f"      {r['reason']}")
    return "\n".join(lines)


def _writable_file(path: str, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """``path`` as a file the run can write at its end, checked now: its folder exists and
    is writable, it is not a folder, and (``suffixes``) its format is one of them."""
    p = Path(path)
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise DesignError(f"{option} {path}: the format must be one of "
                          f"{', '.join(suffixes)}, got {p.suffix or 'no suffix'!r}")
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise DesignError(f"{option} {path}: the folder {folder} does not exist")
    if p.is_dir():
        raise DesignError(f"{option} {path} is a folder; give a file name")
    if not os.access(folder, os.W_OK):
        raise DesignError(f"{option} {path}: the folder {folder} is not writable")
    return p


def check_options(args) -> tuple:
    """Every option of a design run checked before the work (one error, what is allowed):
    the counts, the workers, the ranking, the output and plot files, the part, the plate
    and the problem. Imports nothing heavy.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options.

    Returns
    -------
    tuple
        (part Scene, Plate, uncertainty, DesignProblem).

    Raises
    ------
    DesignError
        An option out of range, a file that cannot be written, or a bad part or plate.
    """
    from ..core.scene_yaml import load_scene
    from ..core.uncertainty import Uncertainty

    for option, value, least in (("--top", args.top, 0), ("--plans", args.plans, 0),
                                 ("--runs", args.runs, 0), ("--seed", args.seed, 0),
                                 ("--batch", args.batch, 1),
                                 ("--plan-candidates", args.plan_candidates, 1)):
        if value < least:
            raise DesignError(f"{option} must be a whole number >= {least}, got {value}")
    if args.workers is not None and args.workers < 0:
        raise DesignError(f"--workers must be >= 0 (0: no Dask, this process), got "
                          f"{args.workers}")
    if args.workers is not None and args.scheduler:
        raise DesignError("--workers sizes the LocalCluster; with --scheduler the "
                          "scheduler's workers run the batches: give one of them")
    parse_ranking(args.rank)
    region = None
    if not args.no_start_region:
        dx, dy, dth = args.start_region
        if not all(math.isfinite(v) and v >= 0 for v in (dx, dy, dth)) or dth > 180:
            raise DesignError("--start-region takes DX DY (m) and DTHETA (degrees, at most "
                              f"180), each finite and >= 0, got {dx:g} {dy:g} {dth:g}")
        region = (dx, dy, math.radians(dth))
    _writable_file(args.out, "--out")
    if args.plot:
        _writable_file(args.plot, "--plot", PLOT_FORMATS)
    part = load_scene(args.part)
    plate = load_plate(args.plate)
    unc = None if args.friction is None else Uncertainty(friction=tuple(args.friction))
    problem = DesignProblem(part, plate, unc, args.actuator, args.start_offset, region)
    return part, plate, unc, problem


def run(args) -> str:
    part, plate, unc, problem = check_options(args)
    try:  # pyarrow, dask, the planner: only now, and optional (setup.py's design extra)
        from ..design.pipeline import design_fixtures
    except ImportError as exc:
        raise DesignError(f"design needs dask[distributed] and pyarrow ({exc}): pip install "
                          "'wrenchcone_ros[design]' (or pip install 'dask[distributed]' "
                          "pyarrow pymunk)") from None

    result = design_fixtures(part, plate, unc, actuator=args.actuator,
                             start_offset=args.start_offset, plans=args.plans, top=args.top,
                             runs=args.runs, seed=args.seed, ranking=args.rank,
                             out=args.out, scheduler=args.scheduler, workers=args.workers,
                             batch_triples=args.batch, progress=sys.stderr.isatty(),
                             plan_candidates=args.plan_candidates,
                             start_region=problem.start_region)
    print(summary(result, args.top, problem.start_region is not None), flush=True)  # the table first, whatever follows
    lines = [f"wrote {args.out} ({len(result.rows)} designs)"]
    parts = Path(str(args.out) + ".parts")
    if args.keep_parts:
        lines.append(f"kept {parts}/ (the finished batches)")
    else:
        shutil.rmtree(parts, ignore_errors=True)
    if args.plot:
        from ..design.plot import plot_designs

        try:
            plot_designs(problem, result.rows, args.plot, args.top)
        except (ValueError, OSError) as exc:
            raise DesignError(f"--plot {args.plot}: {exc} (the designs are in "
                              f"{args.out})") from None
        lines.append(f"wrote {args.plot} (the sheet of the top "
                     f"{min(args.top, len(result.rows), SHEET_DESIGNS)} designs)")
    return "\n".join(lines)
