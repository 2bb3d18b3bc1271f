# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone check``: is a wrench consistent with a mode (or a union of modes)?"""

from __future__ import annotations

import json

from .options import add_common, wrench_to_compute, wrench_value
from .uncertain import add_uncertainty, guarantee_line, robust_or_nominal



def add_arguments(sp) -> None:
    add_common(sp, wrench=True, method=True)
    sp.add_argument("--exit-code", action="store_true",
                    help="exit 0 if the wrench is consistent, 1 if not (2: bad input); "
                         "with uncertainty: consistent for every model")
    add_uncertainty(sp)


def run_robust(args, scene, U) -> str:
    """Consistent for every model (the "all" cone) and for some model (the "any" set)."""
    from ..core import robust_cones

    g = wrench_value(args.wrench)
    g_hat = wrench_to_compute(g)
    a, y = (robust_cones(scene, [args.mode], U, q, exact=args.exact, frame=args.frame)[0]
            for q in ("all", "any"))
    every, some = bool(a.contains(g_hat)), bool(y.contains(g_hat))
    m_all, m_any = float(a.margin(g_hat)), float(y.margin(g_hat))
    if args.exit_code:
        args.exit_status = 0 if every else 1
    if args.json:
        return json.dumps({"mode": args.mode, "feasible": a.feasible or y.feasible,
                           "consistent_every_model": every, "consistent_some_model": some,
                           "margin_all": m_all, "margin_any": m_any,
                           "guarantee": str(a.guarantee), "uncertainty": U.to_dict()})
    verdict = ("consistent for every model" if every else
               "consistent for some model only" if some else "consistent for no model")
    return (f"wrench {g} with mode {args.mode!r}: {verdict} ({U.describe()}); worst-case "
            f"margin {m_all:.6g}, best-case margin {m_any:.6g}; {guarantee_line(a.guarantee)}")


def run(args) -> str:
    return robust_or_nominal(args, run_robust, run_nominal)


def run_nominal(args, scene, cone) -> str:
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
