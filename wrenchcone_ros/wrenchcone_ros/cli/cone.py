# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone cone``: F, equalities and generators of a mode's cone (or of a union)."""

from __future__ import annotations

import json

from ..core.modes import is_wildcard
from .options import add_common
from .uncertain import add_uncertainty, guarantee_line, robust_or_nominal
from .render import CONE_KEYS, cone_lines



def add_arguments(sp) -> None:
    add_common(sp, method=True)
    add_uncertainty(sp)
    sp.add_argument("--quantifier", choices=("all", "any"), default="all",
                    help="with uncertainty: wrenches consistent for every model (all) or "
                         "for some model (any)")


def run_robust(args, scene, U) -> str:
    """The robust cone of a concrete mode (core.robust.robust_cone)."""
    from ..core import robust_cone

    rc = robust_cone(scene, args.mode, U, args.quantifier, exact=args.exact, frame=args.frame)
    if args.json:
        return json.dumps({**rc.to_dict(), "uncertainty": U.to_dict()})
    who = "every model" if args.quantifier == "all" else "some model"
    lines = [f"wrenches consistent with {rc.mode!r} for {who} of: {U.describe()} "
             f"(frame {rc.frame}; {guarantee_line(rc.guarantee)})"]
    if len(rc.pieces) == 1:
        return "\n".join(lines + cone_lines(rc.cone))
    return "\n".join(lines + [f"the union of {len(rc.pieces)} cones, one per sampled model "
                              "(--json lists them)"])


def run(args) -> str:
    return robust_or_nominal(args, run_robust, run_nominal)


def run_nominal(args, scene, cone) -> str:
    if is_wildcard(cone.mode):  # a wildcard mode: the union of its modes' cones
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
