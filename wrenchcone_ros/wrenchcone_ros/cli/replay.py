# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone replay RUN.mcap --mode MODE`` or ``--plan [PLAN.json]``: a recorded run
through the core, offline.

``--plan`` replays each command in the mode of the plan's segment in force: the segments
the recorded controller states name, or those of a plan file (``wrenchcone plan ...
--json``), followed offline (wrenchcone_ros.replay.analysis.segment_modes). ``--friction
LO HI``: each command's robust margin too (every fixel's mu anywhere in [LO, HI]).

No ROS is imported: the bag is read with ``rosbags`` (``pip install rosbags``), the cones
are the core's (wrenchcone_ros.replay).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import yaml

from .options import MODE_HELP, scene_value



def add_arguments(sp) -> None:
    sp.add_argument("bag", metavar="RUN",
                    help="a rosbag2 bag: one .mcap file or a bag directory (metadata.yaml)")
    which = sp.add_mutually_exclusive_group(required=True)
    which.add_argument("--mode", help=MODE_HELP + ": every command in this mode")
    which.add_argument("--plan", nargs="?", const="", metavar="PLAN",
                       help="every command in its plan segment's mode: the segments the "
                       "recorded controller states name, or those of PLAN (the JSON of "
                       "`wrenchcone plan ... --json`)")
    sp.add_argument("--friction", nargs=2, type=float, metavar=("LO", "HI"),
                    help="also the robust margin: every fixel's mu anywhere in [LO, HI]")
    sp.add_argument("--scene", metavar="SCENE",
                    help="the scene YAML (default: the one the bag recorded on /scene_yaml)")
    sp.add_argument("--contact-tolerance", type=float, metavar="M",
                    help="the scene's contact tolerance (m) instead of the recorded one")
    sp.add_argument("--table", action="store_true", help="one line per command")
    sp.add_argument("--json", action="store_true", help="the rows as JSON")
    sp.add_argument("-o", "--plot", metavar="PNG", help="plot the margin and the letters over "
                    "time into this file (matplotlib)")


def _scene(args, run):
    from ..core.scene_yaml import scene_from_dict

    if args.scene:
        scene = scene_value(args.scene)
    elif run.scene_yaml is None:
        raise ValueError(f"{args.bag}: the bag has no scene (/scene_yaml): give --scene FILE")
    else:
        scene = scene_from_dict(yaml.safe_load(run.scene_yaml))
    if args.contact_tolerance is not None:
        scene = replace(scene, contact_tolerance=args.contact_tolerance)
    return scene


def _check_mode(mode: str | None, scene) -> None:
    """A mode no pose of the run could allow (a letter not in 'aslrn' or a wildcard, the
    wrong length) is an error; whether a letter is allowed at a pose is the replay's."""
    from ..core.modes import WILDCARDS, ModeError, ModeSyntaxError, parse_mode, shown_mode

    if mode is None:
        return
    probe = "".join("n" if ch in WILDCARDS else ch for ch in mode)
    try:
        # each fixel in the contact state its letter needs: only the syntax can fail
        contact = [ch != "a" for ch in probe][:scene.n_fixels]
        parse_mode(probe, contact + [True] * (scene.n_fixels - len(contact)))
    except ModeSyntaxError as exc:
        raise ValueError("--mode " + str(exc).replace(shown_mode(probe), shown_mode(mode), 1)
                         ) from None
    except ModeError:  # a letter the contact state decides: per pose, in the replay
        pass


def _plan(args):
    """None (no --plan), RECORDED, or the segment modes of the plan file."""
    from ..replay.analysis import RECORDED

    if args.plan is None:
        return None
    if args.plan == "":
        return RECORDED
    try:
        with open(args.plan, encoding="utf-8") as f:
            data = yaml.safe_load(f)
    except OSError as exc:
        raise ValueError(f"{args.plan}: cannot read the plan ({exc.strerror})") from None
    except yaml.YAMLError:
        raise ValueError(f"{args.plan}: not JSON or YAML (a plan: the output of "
                         "`wrenchcone plan ... --json`)") from None
    segments = data.get("segments") if isinstance(data, dict) else None
    if not segments or not all(isinstance(x, dict) and isinstance(x.get("mode"), str)
                               for x in segments):
        raise ValueError(f"{args.plan}: no segments with a mode (a plan: the output of "
                         "`wrenchcone plan ... --json`)")
    return [x["mode"] for x in segments]


def _uncertainty(args):
    from ..core.uncertainty import Uncertainty

    if args.friction is None:
        return None
    lo, hi = args.friction
    if not (0.0 <= lo <= hi):
        raise ValueError(f"--friction LO HI needs 0 <= LO <= HI, got {lo} {hi}")
    return Uncertainty(friction=(lo, hi))


def run(args) -> str:
    try:
        import rosbags  # noqa: F401
    except ImportError:
        raise ValueError("replay reads bags with rosbags: pip install rosbags") from None
    from ..replay import read_run, replay
    from ..replay.analysis import plot

    rec = read_run(args.bag)
    scene = _scene(args, rec)
    _check_mode(args.mode, scene)
    rep = replay(rec, scene, args.mode, plan=_plan(args),
                 uncertainty=_uncertainty(args))
    if args.plot:
        plot(rep, args.plot)
    if args.json:
        return json.dumps({"mode": rep.mode, "left": list(rep.left),
                           "entered": list(rep.entered),
                           "rows": [{"t": r.t, "stamp": r.stamp, "direction": r.direction,
                                     "magnitude": r.magnitude, "pose": r.pose,
                                     "consistent": r.consistent,
                                     "margin": None if math.isnan(r.margin) else r.margin,
                                     "letters": r.letters, "classified": list(r.classified),
                                     "note": r.note, "segment_mode": r.mode,
                                     "robust_margin": None if math.isnan(r.robust_margin)
                                     else r.robust_margin,
                                     "robust_consistent": r.robust_consistent}
                                    for r in rep.rows]})
    out = [f"{args.bag}: " + rep.summary()]
    if args.table:
        robust = bool(rep.uncertainty)
        out.append("   t s   direction deg  accel m/s^2  mode     margin  in"
                   + ("   robust  in" if robust else "") + "  letters  classified")
        for r in rep.rows:
            m = "     n/a" if math.isnan(r.margin) else f"{r.margin:8.4f}"
            rm = ("" if not robust else "       n/a   " if math.isnan(r.robust_margin)
                  else f"  {r.robust_margin:7.4f}  {'y' if r.robust_consistent else 'n'} ")
            out.append(f"{r.t:7.3f}  {math.degrees(r.direction):13.2f}  {r.magnitude:11.3f}  "
                       f"{r.mode:7s} {m}  {'y' if r.consistent else 'n'} {rm}  {r.letters:7s}  "
                       f"{' '.join(r.classified[:3])}{'  ' + r.note if r.note else ''}")
    if args.plot:
        out.append(f"wrote {args.plot}")
    return "\n".join(out)
