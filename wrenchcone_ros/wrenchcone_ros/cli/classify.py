# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone classify``: every mode a wrench is consistent with."""

from __future__ import annotations

from .options import add_common, scene_value, wrench_to_compute, wrench_value
from .render import classify_answer
from .uncertain import add_uncertainty, uncertainty_value



def add_arguments(sp) -> None:
    add_common(sp, mode=False, wrench=True)
    add_uncertainty(sp)


def run(args) -> str:
    """Every mode the wrench may produce: certain (every model) or possible (some model);
    for the nominal model every match is certain."""
    from ..core.classify import consistent_modes

    scene = scene_value(args.scene)
    g = wrench_value(args.wrench)
    U = uncertainty_value(args)
    found = consistent_modes(scene, wrench_to_compute(g), uncertainty=U, frame=args.frame)
    return classify_answer(args, g, found, U)
