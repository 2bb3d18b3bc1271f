# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone sweep``: the force directions that give a mode along a path of poses."""

from __future__ import annotations

import json
import math

from ..core.sweeps import sweep
from ..core.scene import yaml_problem
from .directions import add_direction_arguments
from .options import point_value, scene_value
from .uncertain import given, uncertainty_value
from .render import fixed, interval_rows, pose_text, where



def add_arguments(sp) -> None:
    add_direction_arguments(sp)
    sp.add_argument("--poses", required=True,
                    help="YAML file: a list of [x m, y m, theta rad] (or {poses: [...]})")


def load_poses(path: str) -> list:
    """The list of poses in a YAML file (a list, or a mapping with the key 'poses')."""
    import yaml

    try:
        with open(path) as fh:
            data = yaml.safe_load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read poses file {path!r}: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"poses file {path!r} is not valid YAML: "
                         f"{yaml_problem(exc)}") from None
    if isinstance(data, dict):
        if set(data) != {"poses"}:
            raise ValueError(f"poses file {path!r}: a mapping must have exactly the key "
                             f"'poses', got {sorted(map(str, data))}")
        data = data["poses"]
    if not isinstance(data, list) or not data:
        raise ValueError(f"poses file {path!r} must hold a non-empty list of "
                         f"[x m, y m, theta rad], got {type(data).__name__}")
    return data


def run(args) -> str:
    scene = scene_value(args.scene)
    point = point_value(args.point)
    U = uncertainty_value(args)
    res = sweep(scene, load_poses(args.poses), args.mode, point=point,
                exclusive=args.exclusive, uncertainty=U)
    if args.json:
        return json.dumps({
            "mode": res.mode, "point": point, "exclusive": args.exclusive,
            "poses": [list(p) for p in res.poses],
            "intervals": [None if ivs is None else [iv.to_dict() for iv in ivs]
                          for ivs in res.intervals],
            "common": [iv.to_dict() for iv in res.common], "stop": res.stop,
            "stop_reason": res.stop_reason,
            "after": [m.to_dict() if given(U) else {"mode": m.mode, "margin": m.margin}
                      for m in res.after],
            **({"uncertainty": U.to_dict()} if given(U) else {})})
    what = f"only mode {res.mode!r}" if args.exclusive else f"mode {res.mode!r}"
    if given(U):
        what += f" for every model of {U.describe()}"
    out = [f"force directions {where(scene, point)} giving {what} along "
           f"{len(res.poses)} poses (degrees):"]
    for k, (pose, ivs) in enumerate(zip(res.poses, res.intervals)):
        p = pose_text(pose, scene.length_scale)
        if ivs is None:
            out.append(f"  pose {k:>3} {p}: " + ("STOP" if k == res.stop else "-"))
        else:
            spans = ", ".join(f"[{fixed(math.degrees(iv.lo), 4)}, {fixed(math.degrees(iv.hi), 4)}]"
                              for iv in ivs)
            out.append(f"  pose {k:>3} {p}: {spans}")
    if res.stop is not None:
        out.append(f"stops at pose {res.stop}: {' '.join(res.stop_reason.split())}")
    else:
        out.append("holds at every pose")
    n = res.stop if res.stop is not None else len(res.poses)
    out.append(f"valid at every pose before that ({n}):" if res.stop is not None else
               f"valid at all {n} poses:")
    out += interval_rows(res.common) if res.common else ["  none"]
    if res.after and given(U):
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
                   f"{math.degrees(res.common[0].best):.4f} deg is consistent with no mode")
    return "\n".join(out)
