# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The design sheet: in every design panel the hold fan and the best-tilt arrow lie
inside the panel's axes, and the legend names every marker drawn (the pins given and
chosen, the part, the hold interval, the best tilt)."""

import math

import pytest

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.design import design_fixtures
from wrenchcone_ros.design.problem import DesignProblem, load_plate

pytest.importorskip("matplotlib")

PLATE = {"pitch": 0.01, "extent": [9, 6], "pin_radius": 0.003,
         "fixed_pins": [[2, 2], [5, 2]]}


def test_the_fan_and_the_arrow_lie_inside_each_panel_and_the_legend_names_the_markers():
    import matplotlib.pyplot as plt
    from matplotlib.patches import Wedge

    from wrenchcone_ros.design.plot import design_sheet

    res = design_fixtures("examples/pawl_seating.yaml", PLATE, (0.2, 0.4), workers=0,
                          plans=0, runs=0)
    rows = [r for r in res.rows if r["hold_margin"] is not None][:6]
    assert len(rows) >= 3
    problem = DesignProblem(load_scene("examples/pawl_seating.yaml"), load_plate(PLATE))
    fig = design_sheet(problem, rows, top=len(rows))
    try:
        panels = fig.axes[:len(rows)]
        for ax, r in zip(panels, rows):
            (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()

            def inside(p, x0=x0, x1=x1, y0=y0, y1=y1):
                return x0 <= p[0] <= x1 and y0 <= p[1] <= y1

            (w,) = [p for p in ax.patches if isinstance(p, Wedge)]
            cx, cy = w.center
            for a in range(0, 360, 5):  # the fan's circle, sampled
                pt = (cx + w.r * math.cos(math.radians(a)),
                      cy + w.r * math.sin(math.radians(a)))
                assert inside(pt), (r["design_id"], pt, (x0, x1, y0, y1))
            arrows = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
            assert arrows
            for t in arrows:
                assert inside(t.xy) and inside(t.xyann), (r["design_id"], t.xy)
            names = {t.get_text() for t in ax.get_legend().get_texts()}
            kinds = {"given" if (r[f"pin{k}_i"], r[f"pin{k}_j"]) in {(2, 2), (5, 2)}
                     else "chosen" for k in (1, 2, 3)}
            assert {f"pin ({k})" for k in kinds} | {"part at its seat", "hold interval",
                                                     "best tilt"} <= names, names
    finally:
        plt.close(fig)
