# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone directions``: the force directions at a point that give a mode."""

from __future__ import annotations

import json

from ..core.directions import force_directions
from .options import add_common, point_value, scene_value
from .uncertain import add_uncertainty, given, uncertainty_value
from .render import interval_rows, where



def add_direction_arguments(sp) -> None:
    """The options ``directions`` and ``sweep`` share."""
    add_common(sp, point=True)
    sp.add_argument("--exclusive", action="store_true",
                    help="only directions consistent with this mode and no other")
    add_uncertainty(sp, frame=False)


def add_arguments(sp) -> None:
    add_direction_arguments(sp)
    sp.add_argument("--exact", action="store_true",
                    help="endpoints in rational arithmetic (cddlib GMP)")


def run(args) -> str:
    scene = scene_value(args.scene)
    point = point_value(args.point)
    U = uncertainty_value(args)
    ivs = force_directions(scene, args.mode, point=point, exclusive=args.exclusive,
                           exact=args.exact, uncertainty=U)
    if args.json:
        out = {"mode": args.mode, "point": point, "exclusive": args.exclusive,
               "exact": args.exact, "intervals": [iv.to_dict() for iv in ivs]}
        if given(U):
            out["uncertainty"] = U.to_dict()
        return json.dumps(out)
    what = f"only mode {args.mode!r}" if args.exclusive else f"mode {args.mode!r}"
    if given(U):
        what += f" for every model of {U.describe()}"
    head = (f"force directions {where(scene, point)} (workpiece frame) giving {what} "
            f"(fixture frame, counter-clockwise from +x; {'exact' if args.exact else 'float'}):")
    if not ivs:
        return head + "\n  none"
    tail = [f"guarantee: {ivs[0].guarantee}; margin and best: the worst case over the "
            "models"] if given(U) else []
    return "\n".join([head] + interval_rows(ivs) + tail)
