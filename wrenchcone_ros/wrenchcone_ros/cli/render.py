# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Text rendering shared by several subcommands: cone tables and direction intervals.

Printed numbers are rounded: a cone's rows to PRINT_DIGITS significant digits, with an
entry below PRINT_ZERO (core/tolerances.py) in the nondimensional metric printed as 0;
angles and margins to fixed decimals. No printed number is ``-0``. The ``--json`` outputs
carry the computed values unrounded.
"""

from __future__ import annotations

import math

import numpy as np

from ..core import Scene
from ..core.tolerances import PRINT_ZERO

#: Significant digits of the printed entries of a cone's rows.
PRINT_DIGITS: int = 6

CONE_KEYS = ("mode", "feasible", "F", "equalities", "G", "lineality", "length_scale",
             "method")


def fixed(x: float, decimals: int) -> str:
    """``x`` with ``decimals`` decimals, never ``-0.000``."""
    return f"{round(x, decimals) + 0.0:.{decimals}f}"


def pose_text(pose, length_scale: float) -> str:
    """A pose (x m, y m, theta rad) to PRINT_DIGITS significant digits, a coordinate below
    PRINT_ZERO times the workpiece's length scale (or an angle below PRINT_ZERO rad)
    printed as 0."""
    scales = (length_scale, length_scale, 1.0)
    shown = [0.0 if abs(v) < PRINT_ZERO * s else v + 0.0 for v, s in zip(pose, scales)]
    return "(" + ", ".join(f"{v:.{PRINT_DIGITS}g}" for v in shown) + ")"


def shown_rows(rows, unit_rows):
    """``rows`` as printed: entries whose counterpart in ``unit_rows`` (the same rows in
    the nondimensional metric, unit vectors) is below PRINT_ZERO set to 0, ``-0`` to 0."""
    rows = np.asarray(rows, dtype=float)
    return np.where(np.abs(np.asarray(unit_rows, dtype=float)) < PRINT_ZERO, 0.0, rows) + 0.0


def table(name: str, rows, unit_rows=None) -> list[str]:
    """A matrix as an indented list of rows under a header with the row count; with
    ``unit_rows``, round-off entries print as 0 (:func:`shown_rows`)."""
    rows = shown_rows(rows, rows if unit_rows is None else unit_rows)
    out = [f"{name} ({rows.shape[0]} row{'s' if rows.shape[0] != 1 else ''}):"]
    out += ["  [" + ", ".join(f"{v: .{PRINT_DIGITS}g}" for v in r) + "]" for r in rows]
    if rows.shape[0] == 0:
        out.append("  (none)")
    return out


def cone_lines(cone) -> list[str]:
    """One mode's cone: verdict, then F, E, G and the lineality space."""
    lines = [f"mode {cone.mode!r} ({cone.method}, {'exact' if cone.exact else 'float'}): "
             + ("feasible" if cone.feasible else
                "INFEASIBLE: no wrench realises this mode (the open mode is impossible)"),
             "g = (fx N, fy N, tz N m) is consistent iff F g <= 0 and E g = 0"]
    lines += table("F", cone.F, cone.F_hat)
    lines += table("E (equalities)", cone.equalities, cone.E_hat)
    return lines + table("G (generators)", cone.G, cone.G_hat) + table("lineality",
                                                                      cone.lineality,
                                                                      cone.L_hat)


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
        out.append(f"  {k:>2}  {fixed(math.degrees(iv.lo), 4):>10}  "
                   f"{fixed(math.degrees(iv.hi), 4):>10}  {fixed(math.degrees(iv.width), 4):>9}  "
                   f"{fixed(math.degrees(iv.best), 4):>10}  {fixed(iv.margin, 6):>9}  "
                   f"{fixed(iv.lo, 6):>10}  {fixed(iv.hi, 6):>10}  {fixed(iv.best, 6):>10}")
        if iv.lo_direction is not None:
            out.append(f"      exact directions: lo ({iv.lo_direction[0]}, {iv.lo_direction[1]})"
                       f", hi ({iv.hi_direction[0]}, {iv.hi_direction[1]})")
    return out
