# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone directions``: the force directions at a point that give a mode."""

from __future__ import annotations

from ..core.directions import force_directions
from .options import add_common, point_value, scene_value
from .render import directions_answer
from .uncertain import add_uncertainty, uncertainty_value



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
    return directions_answer(args, scene, point, ivs, U)
