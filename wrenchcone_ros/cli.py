"""Command-line front end: ``wrenchcone`` (also ``python -m wrenchcone_ros.cli``).

    wrenchcone cone SCENE.yaml --mode na [--exact] [--method planar|paper] [--json]
    wrenchcone check SCENE.yaml --mode na --wrench FX FY TZ [--json] [--exit-code]
    wrenchcone classify SCENE.yaml --wrench FX FY TZ [--json]
    wrenchcone directions SCENE.yaml --mode arr [--point X Y] [--exclusive] [--exact] [--json]
    wrenchcone sweep SCENE.yaml --mode arr --poses POSES.yaml [--point X Y] [--exclusive] [--json]
    wrenchcone plot SCENE.yaml --mode M [--wrench FX FY TZ] [--point X Y] -o FILE.png|svg|pdf
    wrenchcone --version

SCENE may be ``default`` for the built-in paper disc example. A mode may carry wildcards
(c: l, r or n; *: any valid letter): ``cone`` then prints every concrete mode's cone of
the union, ``check`` tests the union. Bad input exits with code 2 and a one-line error on
stderr, never a traceback. ``check --exit-code`` exits 0 when the wrench is consistent
and 1 when it is not (for scripts).

The CLI computes float cones with the numpy reference engine unless $WRENCHCONE_ENGINE
says otherwise: a one-shot command computes a handful of cones, and loading the numba
kernel from its cache costs more than that (measured: 1.1 s per `wrenchcone check` with
numpy against 2.3 s with the kernel, docs/performance.md). Both engines give the same
cones (test/core/test_kernel.py).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from ._version import __version__
from .core import (
    METHODS,
    ConeUnion,
    Scene,
    default_scene,
    force_directions,
    load_scene,
    wrench_cone,
)
from .core.batch import ENGINE_ENV


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
    k.add_argument("--exit-code", action="store_true",
                   help="exit 0 if the wrench is consistent, 1 if not (2: bad input)")

    cl = sub.add_parser("classify", help="every mode a wrench is consistent with")
    scene_arg(cl)
    wrench_arg(cl)
    _direction_parsers(sub, scene_arg)
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


# --- force directions and sweeps (issue 9) ------------------------------------------------
def _direction_parsers(sub, scene_arg) -> None:
    """The ``directions`` and ``sweep`` subcommands (wrenchcone_ros.core.directions)."""

    def common(sp):
        scene_arg(sp)
        sp.add_argument("--mode", required=True,
                        help="mode string, one letter per fixel (wildcards c, * allowed)")
        sp.add_argument("--point", nargs=2, type=float, metavar=("X", "Y"), default=None,
                        help="where the force acts, workpiece frame, m (default: the com)")
        sp.add_argument("--exclusive", action="store_true",
                        help="only directions consistent with this mode and no other")

    d = sub.add_parser("directions", help="force directions at a point that give a mode")
    common(d)
    d.add_argument("--exact", action="store_true",
                   help="endpoints in rational arithmetic (cddlib GMP)")
    sw = sub.add_parser("sweep", help="force directions along a path of poses")
    common(sw)
    sw.add_argument("--poses", required=True,
                    help="YAML file: a list of [x m, y m, theta rad] (or {poses: [...]})")


def _point(scene: Scene, args) -> list[float] | None:
    if args.point is None:
        return None
    if not all(math.isfinite(v) for v in args.point):
        raise ValueError(f"--point must be two finite numbers (m), got {list(args.point)}")
    return [float(v) for v in args.point]


def _where(scene: Scene, point) -> str:
    if point is None:
        cx, cy = scene.workpiece.com
        return f"at the com ({cx:.6g}, {cy:.6g}) m"
    return f"at ({point[0]:.6g}, {point[1]:.6g}) m"


def _interval_rows(intervals) -> list[str]:
    head = (f"  {'#':>2}  {'lo deg':>10}  {'hi deg':>10}  {'width deg':>9}  {'best deg':>10}"
            f"  {'margin':>9}  {'lo rad':>10}  {'hi rad':>10}  {'best rad':>10}")
    out = [head]
    for k, iv in enumerate(intervals, 1):
        out.append(f"  {k:>2}  {math.degrees(iv.lo):>10.4f}  {math.degrees(iv.hi):>10.4f}  "
                   f"{math.degrees(iv.width):>9.4f}  {math.degrees(iv.best):>10.4f}  "
                   f"{iv.margin:>9.6f}  {iv.lo:>10.6f}  {iv.hi:>10.6f}  {iv.best:>10.6f}")
        if iv.lo_direction is not None:
            out.append(f"      exact directions: lo ({iv.lo_direction[0]}, {iv.lo_direction[1]})"
                       f", hi ({iv.hi_direction[0]}, {iv.hi_direction[1]})")
    return out


def _cmd_directions(args) -> str:
    from .core.directions import force_directions

    scene = _scene(args.scene)
    point = _point(scene, args)
    ivs = force_directions(scene, args.mode, point=point, exclusive=args.exclusive,
                           exact=args.exact)
    if args.json:
        return json.dumps({"mode": args.mode, "point": point, "exclusive": args.exclusive,
                           "exact": args.exact, "intervals": [iv.to_dict() for iv in ivs]})
    what = f"only mode {args.mode!r}" if args.exclusive else f"mode {args.mode!r}"
    head = (f"force directions {_where(scene, point)} (workpiece frame) giving {what} "
            f"(fixture frame, counter-clockwise from +x; {'exact' if args.exact else 'float'}):")
    if not ivs:
        return head + "\n  none"
    return "\n".join([head] + _interval_rows(ivs))


def _load_poses(path: str) -> list:
    import yaml

    try:
        with open(path) as fh:
            data = yaml.safe_load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read poses file {path!r}: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"poses file {path!r} is not valid YAML: "
                         f"{str(exc).splitlines()[0]}") from None
    if isinstance(data, dict):
        if set(data) != {"poses"}:
            raise ValueError(f"poses file {path!r}: a mapping must have exactly the key "
                             f"'poses', got {sorted(map(str, data))}")
        data = data["poses"]
    if not isinstance(data, list) or not data:
        raise ValueError(f"poses file {path!r} must hold a non-empty list of "
                         f"[x m, y m, theta rad], got {type(data).__name__}")
    return data


def _cmd_sweep(args) -> str:
    from .core.directions import sweep

    scene = _scene(args.scene)
    point = _point(scene, args)
    res = sweep(scene, _load_poses(args.poses), args.mode, point=point,
                exclusive=args.exclusive)
    if args.json:
        return json.dumps({
            "mode": res.mode, "point": point, "exclusive": args.exclusive,
            "poses": [list(p) for p in res.poses],
            "intervals": [None if ivs is None else [iv.to_dict() for iv in ivs]
                          for ivs in res.intervals],
            "common": [iv.to_dict() for iv in res.common], "stop": res.stop,
            "stop_reason": res.stop_reason,
            "after": [{"mode": m.mode, "margin": m.margin} for m in res.after]})
    what = f"only mode {res.mode!r}" if args.exclusive else f"mode {res.mode!r}"
    out = [f"force directions {_where(scene, point)} giving {what} along "
           f"{len(res.poses)} poses (degrees):"]
    for k, (pose, ivs) in enumerate(zip(res.poses, res.intervals)):
        p = f"({pose[0]:.6g}, {pose[1]:.6g}, {pose[2]:.6g})"
        if ivs is None:
            out.append(f"  pose {k:>3} {p}: " + ("STOP" if k == res.stop else "-"))
        else:
            spans = ", ".join(f"[{math.degrees(iv.lo):.4f}, {math.degrees(iv.hi):.4f}]"
                              for iv in ivs)
            out.append(f"  pose {k:>3} {p}: {spans}")
    if res.stop is not None:
        out.append(f"stops at pose {res.stop}: {' '.join(res.stop_reason.split())}")
    else:
        out.append("holds at every pose")
    n = res.stop if res.stop is not None else len(res.poses)
    out.append(f"valid at every pose before that ({n}):" if res.stop is not None else
               f"valid at all {n} poses:")
    out += _interval_rows(res.common) if res.common else ["  none"]
    if res.after:
        best = math.degrees(res.common[0].best)
        out.append(f"at pose {res.stop} the force along {best:.4f} deg gives: "
                   + ", ".join(f"{m.mode} (margin {m.margin:.6g})" for m in res.after))
    elif res.stop is not None and res.common:
        out.append(f"at pose {res.stop} the force along "
                   f"{math.degrees(res.common[0].best):.4f} deg is consistent with no mode")
    return "\n".join(out)
def _cmd_plot(args) -> str:
    from .core import plot

    plot.output_format(args.output)  # bad input fails before matplotlib is imported
    scene = _scene(args.scene)
    wrench = _wrench(args.wrench) if args.wrench is not None else None
    point = _point(scene, args)
    cone = plot.plotted_cone(scene, args.mode)
    # the consistent force directions at the point (workpiece frame, None = the com),
    # drawn as fans there
    directions = force_directions(scene, args.mode, point)
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise ValueError("plot needs matplotlib: pip install matplotlib "
                         "(or pip install .[plot])") from None
    fig = plot.figure(scene, args.mode, wrench, point=point, directions=directions,
                      cone=cone)
    path = plot.save(fig, args.output)
    return f"wrote {path}"


@contextmanager
def _one_shot_engine() -> Iterator[None]:
    """The numpy engine for this one command unless $WRENCHCONE_ENGINE names one (see
    the module docstring); the variable is removed again afterwards, because main() is
    also called in-process (tests, scripts) and must not choose the engine of the rest
    of the process."""
    if ENGINE_ENV in os.environ:
        yield
        return
    os.environ[ENGINE_ENV] = "numpy"
    try:
        yield
    finally:
        os.environ.pop(ENGINE_ENV, None)


def main(argv: Sequence[str] | None = None) -> int:
    with _one_shot_engine():
        return _main(argv)


def _main(argv: Sequence[str] | None) -> int:
    args = _parser().parse_args(argv)
    handler = {"cone": _cmd_cone, "check": _cmd_check, "classify": _cmd_classify,
               "directions": _cmd_directions, "sweep": _cmd_sweep,
               "plot": _cmd_plot}[args.command]
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
