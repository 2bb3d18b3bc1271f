"""``wrenchcone classify``: every mode a wrench is consistent with."""

from __future__ import annotations

import json

from ..core.classify import consistent_modes
from .options import add_common, scene_value, wrench_to_compute, wrench_value

NAME = "classify"
HELP = "every mode a wrench is consistent with"


def add_arguments(sp) -> None:
    add_common(sp, mode=False, wrench=True)


def run(args) -> str:
    scene = scene_value(args.scene)
    g = wrench_value(args.wrench)
    found = consistent_modes(scene, wrench_to_compute(g))
    if args.json:
        return json.dumps({"wrench": g, "modes": [
            {"mode": m.mode, "margin": m.margin} for m in found]})
    if not found:
        return f"wrench {g} is consistent with no mode"
    return "\n".join([f"wrench {g} is consistent with {len(found)} mode(s):"]
                     + [f"  {m.mode}  margin {m.margin:.6g}" for m in found])
