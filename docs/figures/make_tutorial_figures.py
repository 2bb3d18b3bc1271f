# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Figures of docs/tutorial_tray_tilting.md, from real runs of wrenchcone_ros.core.directions.

    make figures          # or: .venv/bin/python docs/figures/make_tutorial_figures.py

writes docs/figures/tutorial_directions.png and docs/figures/tutorial_sweep.png. The scene's
geometry (outline, fixels, points in the world, the best arrow) comes from
wrenchcone_ros.core.drawing, as in ``wrenchcone plot`` and the node's markers; only the
millimetre axes and the two fans in one picture are drawn here.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib
import numpy as np
import yaml

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, Polygon, Wedge  # noqa: E402

from wrenchcone_ros.core import force_directions, load_scene, sweep, wrench_cone  # noqa: E402
from wrenchcone_ros.core.directions import force_basis  # noqa: E402
from wrenchcone_ros.core.drawing import best_arrow, contact_sketches, outline, to_world  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
OUT = Path(__file__).resolve().parent
PAWL = ROOT / "examples/pawl_polygon.yaml"
POSES = ROOT / "examples/pawl_slide_poses.yaml"
SPRING = (0.0075, 0.035)  # the top of the pawl's upright, workpiece frame (m)
MODE = "arr"


def draw_scene(ax, scene):
    ax.add_patch(Polygon(outline(scene) * 1e3, closed=True, fc="#dddddd", ec="k"))
    for sk in contact_sketches(scene):
        ax.add_patch(Circle(sk.position * 1e3, sk.radius * 1e3, fc="#555555"))
        ax.annotate(f"fixel {sk.index + 1}", sk.position * 1e3, xytext=(4, -12),
                    textcoords="offset points", fontsize=8)


def draw_wedge(ax, centre, iv, radius, color, label):
    c = centre * 1e3
    ax.add_patch(Wedge(c, radius, math.degrees(iv.lo), math.degrees(iv.hi), fc=color,
                       alpha=0.35, ec=color, label=label))
    tail, tip = best_arrow(c, iv.best, radius * 1.15)
    ax.annotate("", tip, tail, arrowprops={"arrowstyle": "->", "color": color, "lw": 2})


def margin_curve(scene, point):
    cone = wrench_cone(scene, MODE)
    B = force_basis(scene, point)
    phis = np.linspace(-math.pi, math.pi, 1441)
    return phis, np.array([cone.margin(B @ [math.cos(p), math.sin(p)]) for p in phis])


def figure_directions(scene):
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    draw_scene(ax, scene)
    (com_iv,) = force_directions(scene, MODE)
    (spr_iv,) = force_directions(scene, MODE, point=SPRING)
    draw_wedge(ax, scene.com_world, com_iv, 22, "tab:blue", "tray tilt (force at the com)")
    draw_wedge(ax, to_world(scene, SPRING), spr_iv, 22, "tab:orange",
               "spring at the upright")
    ax.set_xlim(85, 180)
    ax.set_ylim(170, 245)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm, fixture frame)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"force directions giving mode '{MODE}' (arrows: best)")
    ax.legend(loc="upper right", fontsize=8)
    for point, iv, color, label in ((None, com_iv, "tab:blue", "at the com"),
                                    (SPRING, spr_iv, "tab:orange", "at the spring point")):
        phis, m = margin_curve(scene, point)
        bx.plot(np.degrees(phis), m, color=color, label=label)
        bx.axvspan(math.degrees(iv.lo), math.degrees(iv.hi), color=color, alpha=0.15)
        bx.plot([math.degrees(iv.best)], [iv.margin], "o", color=color)
    bx.axhline(0, color="k", lw=0.5)
    bx.set_xlim(-180, 180)
    bx.set_xticks(range(-180, 181, 45))
    bx.set_xlabel("force direction phi (deg)")
    bx.set_ylabel(f"margin in the '{MODE}' cone")
    bx.set_title("margin of a unit force; shaded: consistent, dot: best")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(OUT / "tutorial_directions.png", dpi=110)
    plt.close(fig)


def figure_sweep(scene, poses):
    fig, ax = plt.subplots(figsize=(7.5, 4))
    xs = [1e3 * (p[0] - poses[0][0]) for p in poses]
    for point, color, label, dx in ((None, "tab:blue", "tray tilt (com)", -0.05),
                                    (SPRING, "tab:orange", "spring at the upright", 0.05)):
        res = sweep(scene, poses, MODE, point=point)
        for x, ivs in zip(xs, res.intervals):
            for iv in ivs or ():
                ax.plot([x + dx, x + dx], [math.degrees(iv.lo), math.degrees(iv.hi)], color=color,
                        lw=6, alpha=0.6, solid_capstyle="butt")
        for iv in res.common:
            ax.axhspan(math.degrees(iv.lo), math.degrees(iv.hi), color=color, alpha=0.12,
                       label=f"{label}: every pose")
            ax.axhline(math.degrees(iv.best), color=color, ls="--", lw=1)
        ax.axvline(xs[res.stop], color="k", ls=":", lw=1)
    ax.annotate("fixel 1 touched:\n'arr' ends", (xs[-1], -20), ha="right", fontsize=8)
    ax.set_xlabel("slide distance (mm)")
    ax.set_ylabel("force direction (deg)")
    ax.set_title("'arr' along the slide: bars per pose, band: valid at every pose")
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(OUT / "tutorial_sweep.png", dpi=110)
    plt.close(fig)


def main() -> None:
    scene = load_scene(PAWL)
    poses = yaml.safe_load(POSES.read_text())["poses"]
    figure_directions(scene)
    figure_sweep(scene, poses)
    print(f"wrote {OUT / 'tutorial_directions.png'} and {OUT / 'tutorial_sweep.png'}")


if __name__ == "__main__":
    main()
