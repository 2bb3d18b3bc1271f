"""``wrenchcone cone``: F, equalities and generators of a mode's cone (or of a union)."""

from __future__ import annotations

import json

from ..core import ConeUnion, wrench_cone
from .options import add_common, scene_value
from .render import CONE_KEYS, cone_lines

NAME = "cone"
HELP = "print F, equalities and generators of a mode's cone"


def add_arguments(sp) -> None:
    add_common(sp, method=True)


def run(args) -> str:
    cone = wrench_cone(scene_value(args.scene), args.mode, exact=args.exact,
                       method=args.method)
    if isinstance(cone, ConeUnion):  # a wildcard mode: the union of its modes' cones
        if args.json:
            return json.dumps({"mode": cone.mode, "feasible": cone.feasible,
                               "impossible": list(cone.impossible), "pieces": [
                                   {k: c.to_dict()[k] for k in CONE_KEYS}
                                   for c in cone.pieces]})
        lines = [f"mode {cone.mode!r} is the union of {len(cone.pieces)} feasible mode "
                 f"cone(s) {list(cone.modes)}; g is consistent iff it is in one of them"]
        if cone.impossible:
            lines.append(f"infeasible (no wrench realises them): {list(cone.impossible)}")
        for piece in cone.pieces:
            lines += [""] + cone_lines(piece)
        return "\n".join(lines)
    if args.json:
        d = cone.to_dict()
        return json.dumps({k: d[k] for k in CONE_KEYS})
    return "\n".join(cone_lines(cone))
