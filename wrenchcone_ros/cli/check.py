"""``wrenchcone check``: is a wrench consistent with a mode (or a union of modes)?"""

from __future__ import annotations

import json

from ..core import wrench_cone
from .options import add_common, scene_value, wrench_to_compute, wrench_value

NAME = "check"
HELP = "is a wrench consistent with a mode?"


def add_arguments(sp) -> None:
    add_common(sp, wrench=True, method=True)
    sp.add_argument("--exit-code", action="store_true",
                    help="exit 0 if the wrench is consistent, 1 if not (2: bad input)")


def run(args) -> str:
    cone = wrench_cone(scene_value(args.scene), args.mode, exact=args.exact,
                       method=args.method)
    g = wrench_value(args.wrench)
    g_hat = wrench_to_compute(g)
    ok, margin = bool(cone.contains(g_hat)), float(cone.margin(g_hat))
    if args.exit_code:
        args.exit_status = 0 if ok else 1
    if args.json:
        return json.dumps({"mode": cone.mode, "feasible": cone.feasible, "consistent": ok,
                           "margin": margin})
    verdict = "consistent" if ok else "NOT consistent"
    extra = "" if cone.feasible else " (the mode is infeasible)"
    return f"wrench {g} is {verdict} with mode {cone.mode!r}{extra}; margin {margin:.6g}"
