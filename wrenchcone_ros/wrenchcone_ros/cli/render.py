# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Text rendering shared by several subcommands: cone tables and direction intervals."""

from __future__ import annotations

import math

from ..core import Scene

CONE_KEYS = ("mode", "feasible", "F", "equalities", "G", "lineality", "length_scale",
             "method")


def table(name: str, rows) -> list[str]:
    """A matrix as an indented list of rows under a header with the row count."""
    out = [f"{name} ({rows.shape[0]} row{'s' if rows.shape[0] != 1 else ''}):"]
    out += [f"  [{r[0]: .6g}, {r[1]: .6g}, {r[2]: .6g}]" for r in rows]
    if rows.shape[0] == 0:
        out.append("  (none)")
    return out


def cone_lines(cone) -> list[str]:
    """One mode's cone: verdict, then F, E, G and the lineality space."""
    lines = [f"mode {cone.mode!r} ({cone.method}, {'exact' if cone.exact else 'float'}): "
             + ("feasible" if cone.feasible else
                "INFEASIBLE: no wrench realises this mode (the open mode is impossible)"),
             "g = (fx N, fy N, tz N m) is consistent iff F g <= 0 and E g = 0"]
    lines += table("F", cone.F) + table("E (equalities)", cone.equalities)
    return lines + table("G (generators)", cone.G) + table("lineality", cone.lineality)


def where(scene: Scene, point) -> str:
    """Where the force acts, in words."""
    if point is None:
        cx, cy = scene.workpiece.com
        return f"at the com ({cx:.6g}, {cy:.6g}) m"
    return f"at ({point[0]:.6g}, {point[1]:.6g}) m"


def interval_rows(intervals) -> list[str]:
    """A table of direction intervals, degrees and radians (exact endpoints if known)."""
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
