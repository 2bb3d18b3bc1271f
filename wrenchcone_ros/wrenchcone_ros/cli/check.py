# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone check``: is a wrench consistent with a mode (or a union of modes)?"""

from __future__ import annotations

from .options import add_common, scene_value, wrench_to_compute, wrench_value
from .render import check_answer
from .uncertain import add_uncertainty, uncertainty_value



def add_arguments(sp) -> None:
    add_common(sp, wrench=True, method=True)
    sp.add_argument("--exit-code", action="store_true",
                    help="exit 0 if the wrench is consistent, 1 if not (2: bad input); "
                         "with uncertainty: consistent for every model")
    add_uncertainty(sp)


def run(args) -> str:
    """Consistent for every model (the "all" set) and for some model (the "any" set): for
    the nominal model both are the mode's cone (the core's zero-width uncertainty)."""
    from ..core import robust_cones

    scene = scene_value(args.scene)  # read first: its errors are worded by the loader
    U = uncertainty_value(args)
    g = wrench_value(args.wrench)
    g_hat = wrench_to_compute(g)
    every, some = (robust_cones(scene, [args.mode], U, q, exact=args.exact, frame=args.frame,
                                method=args.method)[0] for q in ("all", "any"))
    if args.exit_code:
        args.exit_status = 0 if every.contains(g_hat) else 1
    return check_answer(args, g, g_hat, every, some, U)
