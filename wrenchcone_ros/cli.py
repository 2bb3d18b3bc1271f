"""Command-line front end: ``wrenchcone`` (also ``python -m wrenchcone_ros.cli``).

    wrenchcone cone SCENE.yaml --mode na [--exact] [--method planar|paper] [--json]
    wrenchcone check SCENE.yaml --mode na --wrench FX FY TZ [--json] [--exit-code]
    wrenchcone classify SCENE.yaml --wrench FX FY TZ [--json]

SCENE may be ``default`` for the built-in paper disc example. A mode may carry wildcards
(c: l, r or n; *: any valid letter): ``cone`` then prints every concrete mode's cone of
the union, ``check`` tests the union. Bad input exits with code 2 and a one-line error on
stderr, never a traceback. ``check --exit-code`` exits 0 when the wrench is consistent
and 1 when it is not (for scripts).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence

from .core import METHODS, ConeUnion, Scene, default_scene, load_scene, wrench_cone


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"wrenchcone: error: {message}\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="wrenchcone", description="Wrench cones of planar augmented contact modes.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    def scene_arg(sp):
        sp.add_argument("scene", help="scene YAML file, or 'default' for the paper's disc")
        sp.add_argument("--json", action="store_true", help="one JSON object on stdout")

    def wrench_arg(sp):
        sp.add_argument("--wrench", nargs=3, type=float, required=True,
                        metavar=("FX", "FY", "TZ"),
                        help="force (N) and torque about the com (N m), world frame")

    def method_args(sp):
        sp.add_argument("--exact", action="store_true", help="rational arithmetic (cddlib GMP)")
        sp.add_argument("--method", choices=sorted(METHODS), default=None,
                        help="algorithm (default: the fastest verified one)")

    c = sub.add_parser("cone", help="print F, equalities and generators of a mode's cone")
    scene_arg(c)
    c.add_argument("--mode", required=True, help="one letter per fixel from 'aslrn'")
    method_args(c)

    k = sub.add_parser("check", help="is a wrench consistent with a mode?")
    scene_arg(k)
    k.add_argument("--mode", required=True)
    wrench_arg(k)
    method_args(k)
    k.add_argument("--exit-code", action="store_true",
                   help="exit 0 if the wrench is consistent, 1 if not (2: bad input)")

    cl = sub.add_parser("classify", help="every mode a wrench is consistent with")
    scene_arg(cl)
    wrench_arg(cl)
    return p


def _scene(arg: str) -> Scene:
    return default_scene() if arg == "default" else load_scene(arg)


def _wrench(values: Sequence[float]) -> list[float]:
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"--wrench must be three finite numbers, got {list(values)}")
    return [float(v) for v in values]


def _table(name: str, rows) -> list[str]:
    out = [f"{name} ({rows.shape[0]} row{'s' if rows.shape[0] != 1 else ''}):"]
    out += [f"  [{r[0]: .6g}, {r[1]: .6g}, {r[2]: .6g}]" for r in rows]
    if rows.shape[0] == 0:
        out.append("  (none)")
    return out


_CONE_KEYS = ("mode", "feasible", "F", "equalities", "G", "lineality", "length_scale",
              "method")


def _cone_lines(cone) -> list[str]:
    lines = [f"mode {cone.mode!r} ({cone.method}, {'exact' if cone.exact else 'float'}): "
             + ("feasible" if cone.feasible else
                "INFEASIBLE: no wrench realises this mode (the open mode is impossible)"),
             "g = (fx N, fy N, tz N m) is consistent iff F g <= 0 and E g = 0"]
    lines += _table("F", cone.F) + _table("E (equalities)", cone.equalities)
    return lines + _table("G (generators)", cone.G) + _table("lineality", cone.lineality)


def _cmd_cone(args) -> str:
    cone = wrench_cone(_scene(args.scene), args.mode, exact=args.exact, method=args.method)
    if isinstance(cone, ConeUnion):  # a wildcard mode: the union of its modes' cones
        if args.json:
            return json.dumps({"mode": cone.mode, "feasible": cone.feasible,
                               "impossible": list(cone.impossible), "pieces": [
                                   {k: c.to_dict()[k] for k in _CONE_KEYS}
                                   for c in cone.pieces]})
        lines = [f"mode {cone.mode!r} is the union of {len(cone.pieces)} feasible mode "
                 f"cone(s) {list(cone.modes)}; g is consistent iff it is in one of them"]
        if cone.impossible:
            lines.append(f"infeasible (no wrench realises them): {list(cone.impossible)}")
        for piece in cone.pieces:
            lines += [""] + _cone_lines(piece)
        return "\n".join(lines)
    if args.json:
        d = cone.to_dict()
        return json.dumps({k: d[k] for k in _CONE_KEYS})
    return "\n".join(_cone_lines(cone))


def _cmd_check(args) -> str:
    cone = wrench_cone(_scene(args.scene), args.mode, exact=args.exact, method=args.method)
    g = _wrench(args.wrench)
    ok, margin = bool(cone.contains(g)), float(cone.margin(g))
    args.consistent = ok  # for --exit-code
    if args.json:
        return json.dumps({"mode": cone.mode, "feasible": cone.feasible, "consistent": ok,
                           "margin": margin})
    verdict = "consistent" if ok else "NOT consistent"
    extra = "" if cone.feasible else " (the mode is infeasible)"
    return f"wrench {g} is {verdict} with mode {cone.mode!r}{extra}; margin {margin:.6g}"


def _cmd_classify(args) -> str:
    from .core.classify import consistent_modes

    scene = _scene(args.scene)
    g = _wrench(args.wrench)
    found = consistent_modes(scene, g)
    if args.json:
        return json.dumps({"wrench": g, "modes": [
            {"mode": m.mode, "margin": m.margin} for m in found]})
    if not found:
        return f"wrench {g} is consistent with no mode"
    return "\n".join([f"wrench {g} is consistent with {len(found)} mode(s):"]
                     + [f"  {m.mode}  margin {m.margin:.6g}" for m in found])


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    handler = {"cone": _cmd_cone, "check": _cmd_check, "classify": _cmd_classify}[args.command]
    try:
        print(handler(args))
    except (ValueError, OSError, ArithmeticError) as exc:  # SceneError, ModeError: ValueError
        msg = " ".join(str(exc).split()) or type(exc).__name__
        print(f"wrenchcone: error: {msg}", file=sys.stderr)
        return 2
    if getattr(args, "exit_code", False):
        return 0 if args.consistent else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
