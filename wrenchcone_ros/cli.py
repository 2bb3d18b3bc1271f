"""Command-line front end: ``wrenchcone`` (also ``python -m wrenchcone_ros.cli``).

    wrenchcone cone SCENE.yaml --mode na [--exact] [--method planar|paper] [--json]
    wrenchcone check SCENE.yaml --mode na --wrench FX FY TZ [--json]
    wrenchcone classify SCENE.yaml --wrench FX FY TZ [--json]
    wrenchcone plot SCENE.yaml --mode M [--wrench FX FY TZ] [--point X Y] -o FILE.png|svg|pdf
    wrenchcone --version

SCENE may be ``default`` for the built-in paper disc example. Bad input exits with code
2 and a one-line error on stderr, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence

from ._version import __version__
from .core import METHODS, Scene, default_scene, load_scene, wrench_cone


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"wrenchcone: error: {message}\n")


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="wrenchcone", description="Wrench cones of planar augmented contact modes.")
    p.add_argument("--version", action="version", version=f"wrenchcone {__version__}")
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

    cl = sub.add_parser("classify", help="every mode a wrench is consistent with")
    scene_arg(cl)
    wrench_arg(cl)
    _add_plot_parser(sub)
    return p


def _add_plot_parser(sub) -> None:
    pl = sub.add_parser("plot", help="picture of the scene and of a mode's cone (matplotlib)")
    pl.add_argument("scene", help="scene YAML file, or 'default' for the paper's disc")
    pl.add_argument("--mode", required=True, help="one letter per fixel from 'aslrn'")
    pl.add_argument("--wrench", nargs=3, type=float, metavar=("FX", "FY", "TZ"),
                    help="draw this wrench (N, N m about the com) with its verdict")
    pl.add_argument("--point", nargs=2, type=float, metavar=("X", "Y"),
                    help="a point of the workpiece (workpiece frame, m) where the force "
                         "directions are drawn (default: the centre of mass)")
    pl.add_argument("-o", "--output", required=True,
                    help="output file; the format from its extension: .png, .svg or .pdf")


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


def _cmd_cone(args) -> str:
    cone = wrench_cone(_scene(args.scene), args.mode, exact=args.exact, method=args.method)
    if args.json:
        d = cone.to_dict()
        return json.dumps({k: d[k] for k in ("mode", "feasible", "F", "equalities", "G",
                                              "lineality", "length_scale", "method")})
    lines = [f"mode {cone.mode!r} ({cone.method}, {'exact' if cone.exact else 'float'}): "
             + ("feasible" if cone.feasible else
                "INFEASIBLE: no wrench realises this mode (the open mode is impossible)"),
             "g = (fx N, fy N, tz N m) is consistent iff F g <= 0 and E g = 0"]
    lines += _table("F", cone.F) + _table("E (equalities)", cone.equalities)
    lines += _table("G (generators)", cone.G) + _table("lineality", cone.lineality)
    return "\n".join(lines)


def _cmd_check(args) -> str:
    cone = wrench_cone(_scene(args.scene), args.mode, exact=args.exact, method=args.method)
    g = _wrench(args.wrench)
    ok, margin = cone.contains(g), cone.margin(g)
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


def _cmd_plot(args) -> str:
    from .core import plot

    plot.output_format(args.output)  # bad input fails before matplotlib is imported
    scene = _scene(args.scene)
    wrench = _wrench(args.wrench) if args.wrench is not None else None
    point = None
    if args.point is not None:
        if not all(math.isfinite(v) for v in args.point):
            raise ValueError(f"--point must be two finite numbers (m), got {args.point}")
        point = [float(v) for v in args.point]
    cone = plot.plotted_cone(scene, args.mode)
    directions = None
    # TODO(merge, issue 9): directions = force_directions(scene, args.mode, point)
    # (wrenchcone_ros.core.directions; point in the workpiece frame, None = the com);
    # plot.figure draws them as fans at that point.
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise ValueError("plot needs matplotlib: pip install matplotlib "
                         "(or pip install .[plot])") from None
    fig = plot.figure(scene, args.mode, wrench, point=point, directions=directions,
                      cone=cone)
    path = plot.save(fig, args.output)
    return f"wrote {path}"


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    handler = {"cone": _cmd_cone, "check": _cmd_check, "classify": _cmd_classify,
               "plot": _cmd_plot}[args.command]
    try:
        print(handler(args))
    except (ValueError, OSError) as exc:  # SceneError and ModeError are ValueErrors
        msg = " ".join(str(exc).split())
        print(f"wrenchcone: error: {msg}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
