# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone cone``: F, equalities and generators of a mode's cone (or of a union)."""

from __future__ import annotations

from .options import add_common, scene_value
from .render import cone_answer
from .uncertain import add_uncertainty, uncertainty_value



def add_arguments(sp) -> None:
    add_common(sp, method=True)
    add_uncertainty(sp)
    sp.add_argument("--quantifier", choices=("all", "any"), default="all",
                    help="with uncertainty: wrenches consistent for every model (all) or "
                         "for some model (any)")


def run(args) -> str:
    """The mode's set of wrenches under the options' uncertainty
    (:func:`~wrenchcone_ros.core.robust_cone`: the mode's cone, or a wildcard's union, for
    the nominal model)."""
    from ..core import robust_cone

    scene = scene_value(args.scene)  # read first: its errors are worded by the loader
    U = uncertainty_value(args)
    ws = robust_cone(scene, args.mode, U, args.quantifier, exact=args.exact,
                     frame=args.frame, method=args.method)
    return cone_answer(args, ws, U)
