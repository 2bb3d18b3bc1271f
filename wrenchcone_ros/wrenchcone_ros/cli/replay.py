# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone replay RUN.mcap --mode MODE``: a recorded run through the core, offline.

No ROS is imported: the bag is read with ``rosbags`` (``pip install rosbags``), the cones
are the core's (wrenchcone_ros.replay).
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import yaml

from .options import add_mode, scene_value

NAME = "replay"
HELP = "a recorded run (rosbag2 MCAP): the cone at every recorded pose, the commands' margins"


def add_arguments(sp) -> None:
    sp.add_argument("bag", metavar="RUN",
                    help="a rosbag2 bag: one .mcap file or a bag directory (metadata.yaml)")
    add_mode(sp)
    sp.add_argument("--scene", metavar="SCENE",
                    help="the scene YAML (default: the one the bag recorded on /scene_yaml)")
    sp.add_argument("--contact-tolerance", type=float, metavar="M",
                    help="the scene's contact tolerance (m) instead of the recorded one")
    sp.add_argument("--table", action="store_true", help="one line per command")
    sp.add_argument("--json", action="store_true", help="the rows as JSON")
    sp.add_argument("-o", "--plot", metavar="PNG", help="plot the margin and the letters over "
                    "time into this file (matplotlib)")


def _scene(args, run):
    from ..core.scene import scene_from_dict

    if args.scene:
        scene = scene_value(args.scene)
    elif run.scene_yaml is None:
        raise ValueError(f"{args.bag}: the bag has no scene (/scene_yaml): give --scene FILE")
    else:
        scene = scene_from_dict(yaml.safe_load(run.scene_yaml))
    if args.contact_tolerance is not None:
        scene = replace(scene, contact_tolerance=args.contact_tolerance)
    return scene


def run(args) -> str:
    try:
        import rosbags  # noqa: F401
    except ImportError:
        raise ValueError("replay reads bags with rosbags: pip install rosbags") from None
    from ..replay import read_run, replay
    from ..replay.analysis import plot

    rec = read_run(args.bag)
    rep = replay(rec, _scene(args, rec), args.mode)
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
                                     "note": r.note} for r in rep.rows]})
    out = [f"{args.bag}: " + rep.summary()]
    if args.table:
        out.append("   t s   direction deg  accel m/s^2   margin  in  letters  classified")
        for r in rep.rows:
            m = "     n/a" if math.isnan(r.margin) else f"{r.margin:8.4f}"
            out.append(f"{r.t:7.3f}  {math.degrees(r.direction):13.2f}  {r.magnitude:11.3f}  {m}  "
                       f"{'y' if r.consistent else 'n'}   {r.letters:7s}  "
                       f"{' '.join(r.classified[:3])}{'  ' + r.note if r.note else ''}")
    if args.plot:
        out.append(f"wrote {args.plot}")
    return "\n".join(out)
