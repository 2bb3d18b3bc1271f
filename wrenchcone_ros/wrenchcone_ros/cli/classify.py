# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone classify``: every mode a wrench is consistent with."""

from __future__ import annotations

import json

from ..core.classify import consistent_modes
from .options import add_common, scene_value, wrench_to_compute, wrench_value
from .uncertain import add_uncertainty, given, guarantee_line, uncertainty_value



def add_arguments(sp) -> None:
    add_common(sp, mode=False, wrench=True)
    add_uncertainty(sp)


def run_robust(args, scene, g, U) -> str:
    """Every mode g may produce: certain (every model) or possible (some model)."""
    found = consistent_modes(scene, wrench_to_compute(g), uncertainty=U, frame=args.frame)
    guarantee = found[0].guarantee if found else None
    if args.json:
        return json.dumps({"wrench": g, "uncertainty": U.to_dict(),
                           "modes": [m.to_dict() for m in found]})
    if not found:
        return f"wrench {g} is consistent with no mode for any model ({U.describe()})"
    return "\n".join(
        [f"wrench {g} may produce {len(found)} mode(s) ({U.describe()}; "
         f"{guarantee_line(guarantee)}):"]
        + [f"  {m.mode}  {'certain ' if m.certain else 'possible'}  worst-case margin "
           f"{m.margin_all:.6g}  best-case margin {m.margin_any:.6g}" for m in found])


def run(args) -> str:
    scene = scene_value(args.scene)
    g = wrench_value(args.wrench)
    U = uncertainty_value(args)
    if given(U):
        return run_robust(args, scene, g, U)
    found = consistent_modes(scene, wrench_to_compute(g), uncertainty=U)
    if args.json:
        return json.dumps({"wrench": g, "modes": [
            {"mode": m.mode, "margin": m.margin} for m in found]})
    if not found:
        return f"wrench {g} is consistent with no mode"
    return "\n".join([f"wrench {g} is consistent with {len(found)} mode(s):"]
                     + [f"  {m.mode}  margin {m.margin:.6g}" for m in found])
