# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone plot``: a picture of the scene and of a mode's cone (matplotlib)."""

from __future__ import annotations

from ..core import force_directions, robust_cone
from .options import (
    MODE_HELP,
    add_mode,
    add_point,
    add_scene,
    add_wrench,
    point_value,
    scene_value,
    wrench_to_compute,
    wrench_value,
)
from .render import models_named
from .uncertain import add_uncertainty, uncertainty_value



def add_arguments(sp) -> None:
    add_scene(sp, json=False)
    add_mode(sp, help=MODE_HELP)
    add_wrench(sp, required=False,
               help="draw this wrench (N, N m about the com) with its verdict")
    add_point(sp, help="a point of the workpiece (workpiece frame, m) where the force "
                       "directions are drawn (default: the centre of mass)")
    sp.add_argument("-o", "--output", required=True,
                    help="output file; the format from its extension: .png, .svg or .pdf")
    add_uncertainty(sp)


def run(args) -> str:
    from ..core import plot

    plot.output_format(args.output)  # bad input fails before matplotlib is imported
    scene = scene_value(args.scene)
    wrench = (wrench_to_compute(wrench_value(args.wrench)) if args.wrench is not None
              else None)
    point = point_value(args.point)
    cone = plot.plotted_cone(scene, args.mode)
    # the consistent force directions at the point (workpiece frame, None = the com),
    # drawn as fans there
    U = uncertainty_value(args)
    directions = force_directions(scene, args.mode, point, uncertainty=U)
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise ValueError("plot needs matplotlib: pip install matplotlib "
                         "(or pip install .[plot])") from None
    if models_named(U):  # the nominal and the robust cone side by side, robust fans
        rc = robust_cone(scene, args.mode, U, "all", frame=args.frame)
        fig = plot.robust_figure(scene, args.mode, cone, rc.cone,
                                 f"{U.describe()}\n{rc.guarantee}", wrench, point=point,
                                 directions=directions)
        return f"wrote {plot.save(fig, args.output)}"
    fig = plot.figure(scene, args.mode, wrench, point=point, directions=directions,
                      cone=cone)
    path = plot.save(fig, args.output)
    return f"wrote {path}"
