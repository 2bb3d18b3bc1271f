# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The plot sheet of a design run: the top designs on the plate (holes, keep-outs, the
three pins each drawn at its radius (at least a twentieth of the pitch, to be seen), and
on a plate of several pin radii the radii in the panel's title, the seated part, the hold interval as a wedge at the com with its best tilt,
the loading plan's directions as arrows) and the trade-off scatter (hold margin against
locating accuracy, coloured by the Monte Carlo success rate)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .problem import DesignProblem

#: Design panels on one sheet at most (the eighth panel is the scatter).
SHEET_DESIGNS: int = 7


#: The colours of the sheet: given pins, chosen pins, the part, the hold, the plan.
COLOURS = {"given": "tab:orange", "chosen": "k", "part": "tab:blue", "hold": "tab:green",
           "plan": "tab:red"}


def fan_radius(problem: DesignProblem) -> float:
    """The radius (m) of a panel's hold fan and arrows: 0.6 of the part's length scale,
    at most 0.3 of the plate's shorter side.

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part's size, the plate).

    Returns
    -------
    float
        m.
    """
    x0, y0, x1, y1 = problem.plate.bounds
    return min(0.6 * problem.part.length_scale, 0.3 * min(x1 - x0, y1 - y0))


def _scale_bar(ax, x0, y0, x1, y1) -> None:
    """A bar of a round length (1, 2 or 5 times a power of ten, m) in the lower left."""
    span = x1 - x0
    raw = span / 5
    p = 10 ** math.floor(math.log10(raw))
    length = max(m * p for m in (1, 2, 5) if m * p <= raw)
    bx, by = x0 + 0.04 * span, y0 + 0.04 * (y1 - y0)
    ax.plot([bx, bx + length], [by, by], color="k", lw=2, solid_capstyle="butt")
    ax.text(bx + length / 2, by + 0.015 * (y1 - y0), f"{length * 1000:g} mm",
            ha="center", va="bottom", fontsize=6)


def _design_panel(ax, problem: DesignProblem, row: dict) -> None:
    from matplotlib.patches import Circle, Polygon, Rectangle, Wedge

    plate = problem.plate
    nx, ny = plate.extent
    x0, y0, x1, y1 = plate.bounds
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fc="0.95", ec="0.6"))
    for b in plate.keep_out:
        ax.add_patch(Rectangle((b[0], b[1]), b[2] - b[0], b[3] - b[1], fc="0.8", ec="none",
                               hatch="//", label="keep-out"))
    hi, hj = np.meshgrid(range(nx), range(ny))
    ax.plot(hi.ravel() * plate.pitch, hj.ravel() * plate.pitch, ".", ms=2, color="0.6")
    x, y, th = row["x"], row["y"], row["theta"]
    c, s = math.cos(th), math.sin(th)
    V = np.array(problem.vertices)
    W = np.column_stack([x + c * V[:, 0] - s * V[:, 1], y + s * V[:, 0] + c * V[:, 1]])
    ax.add_patch(Polygon(W, closed=True, fc=COLOURS["part"], alpha=0.35, ec=COLOURS["part"],
                         label="part at its seat"))
    fixed = {tuple(h) for h in plate.fixed_pins}
    shown = set()
    radii = [row.get(f"pin{k}_r") for k in (1, 2, 3)]
    if None in radii:  # a row of a plate of one pin size, written without radii
        radii = [plate.pin_radius] * 3
    for k in (1, 2, 3):
        kind = "given" if (row[f"pin{k}_i"], row[f"pin{k}_j"]) in fixed else "chosen"
        ax.add_patch(Circle((row[f"pin{k}_x"], row[f"pin{k}_y"]),
                            max(radii[k - 1], plate.pitch / 20), fc=COLOURS[kind],
                            ec="k", lw=0.5,
                            label=None if kind in shown else f"pin ({kind})"))
        shown.add(kind)
    cx, cy = problem.part.workpiece.com
    com = (x + c * cx - s * cy, y + s * cx + c * cy)
    size = fan_radius(problem)
    if row.get("hold_lo") is not None:
        ax.add_patch(Wedge(com, size, math.degrees(row["hold_lo"]),
                           math.degrees(row["hold_hi"]), fc=COLOURS["hold"], alpha=0.25,
                           label="hold interval"))
        b = row["best_tilt"]
        ax.annotate("", (com[0] + size * math.cos(b), com[1] + size * math.sin(b)), com,
                    arrowprops={"arrowstyle": "->", "color": COLOURS["hold"], "lw": 1.5})
        ax.plot([], [], color=COLOURS["hold"], lw=1.5, label="best tilt")
    if row.get("plan_directions"):
        for k, d in enumerate(row["plan_directions"].split(";")):
            phi = float(d)
            ax.annotate("", (com[0] + 0.8 * size * math.cos(phi),
                             com[1] + 0.8 * size * math.sin(phi)), com,
                        arrowprops={"arrowstyle": "->", "color": COLOURS["plan"],
                                    "alpha": min(1.0, 0.5 + 0.5 * k / 4)})
        ax.plot([], [], color=COLOURS["plan"], label="plan's directions")
    # the panel: the plate, and the fan wherever the com is
    lx0, ly0 = min(x0, com[0] - 1.05 * size), min(y0, com[1] - 1.05 * size)
    lx1, ly1 = max(x1, com[0] + 1.05 * size), max(y1, com[1] + 1.05 * size)
    ax.set_xlim(lx0, lx1)
    ax.set_ylim(ly0, ly1)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    _scale_bar(ax, lx0, ly0, lx1, ly1)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=3, fontsize=5,
              frameon=False)
    rate = row.get("success_rate")
    acc, hm = row.get("locating_accuracy"), row.get("hold_margin")
    plan = ("guaranteed plan" if row.get("plan_guaranteed") else "plan" if
            row.get("plan_feasible") else "no plan" if row.get("plan_feasible") is not None
            else "not planned")
    sizes = ("  r " + "/".join(f"{1000 * r:.6g}" for r in radii) + " mm"
             if plate.mixed else "")
    ax.set_title(f"#{row['rank']}  {row['features']}{sizes}\n"
                 f"accuracy {'-' if acc is None else f'{acc:.2f}'}  "
                 f"hold {'-' if hm is None else f'{hm:.3f}'}  {plan}"
                 + (f"  {100 * rate:.0f} %" if rate is not None else ""), fontsize=7)


def _scatter(ax, rows: Sequence[dict]) -> None:
    pts = [r for r in rows if r.get("hold_margin") is not None
           and r.get("locating_accuracy") is not None]
    acc = np.array([r["locating_accuracy"] for r in pts])
    hm = np.array([r["hold_margin"] for r in pts])
    ax.scatter(acc, hm, s=4, c="0.7", label="holds")
    mc = [r for r in pts if r.get("success_rate") is not None]
    if mc:
        sc = ax.scatter([r["locating_accuracy"] for r in mc], [r["hold_margin"] for r in mc],
                        c=[r["success_rate"] for r in mc], vmin=0, vmax=1, cmap="viridis",
                        s=30, edgecolors="k", label="Monte Carlo")
        ax.figure.colorbar(sc, ax=ax, label="success rate")
    g = [r for r in pts if r.get("plan_guaranteed")]
    if g:
        ax.scatter([r["locating_accuracy"] for r in g], [r["hold_margin"] for r in g],
                   marker="x", c="tab:red", s=20, label="guaranteed plan")
    if len(acc) and acc.max() > 30 * acc.min():  # a log axis, labelled between decades
        from matplotlib.ticker import LogFormatterSciNotation

        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(LogFormatterSciNotation(labelOnlyBase=False,
                                                             minor_thresholds=(2, 0.4)))
        ax.tick_params(axis="x", which="minor", labelsize=6)
    ax.set_xlabel("locating accuracy (m/m, smaller is better)")
    ax.set_ylabel("hold margin")
    ax.legend(fontsize=6)
    ax.set_title("trade-off", fontsize=8)


def plot_designs(problem: DesignProblem, rows: Sequence[dict], path: str | Path,
                 top: int = SHEET_DESIGNS) -> Path:
    """Write the sheet (module docstring) of the ``top`` best rows (at most
    SHEET_DESIGNS) and the scatter of all rows to ``path`` (.png, .svg or .pdf).

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part's outline, the plate).
    rows : sequence of dict
        The ranked rows, best first.
    path : str or Path
        The output file.
    top : int, optional
        How many designs get a panel.

    Returns
    -------
    Path
        ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = design_sheet(problem, rows, top)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def design_sheet(problem: DesignProblem, rows: Sequence[dict], top: int = SHEET_DESIGNS):
    """The sheet of :func:`plot_designs` as a matplotlib figure (Agg), not written.

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part's outline, the plate).
    rows : sequence of dict
        The ranked rows, best first.
    top : int, optional
        How many designs get a panel (at most SHEET_DESIGNS).

    Returns
    -------
    matplotlib.figure.Figure
        The figure: the design panels first, the scatter last.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    best = [r for r in rows[:max(0, min(top, SHEET_DESIGNS))]]
    n = len(best) + 1
    ncols = min(4, n)
    nrows = math.ceil(n / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.6 * ncols, 3.3 * nrows), squeeze=False)
    flat = axes.ravel()
    for ax, row in zip(flat, best):
        _design_panel(ax, problem, row)
    for ax in flat[len(best):-1]:
        ax.axis("off")  # the panels between the last design and the scatter
    _scatter(flat[-1], rows)
    fig.tight_layout()
    return fig


__all__ = ["COLOURS", "SHEET_DESIGNS", "design_sheet", "fan_radius", "plot_designs"]
