# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Pictures of a plan for a region of starts (core/animate.py ``draw_region``,
``animate_region``): the PNG is written and is a real picture; the paths it draws end
where the engine leaves the part from those starts (each start run again here with
``execute``, the planner's open-loop run, not through the drawing's runs); the first
segment's entry region is the starts themselves; the animation has the frames asked,
read back with Pillow, and the part moves in it. The pawl of docs/planning.md under one
tilt that seats it (-60 degrees), in the nominal model, a small box, a 2-point cover and
no drawn starts in the certification."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("pymunk")
pytest.importorskip("matplotlib")
Image = pytest.importorskip("PIL.Image")

from helpers.docs_examples import ROOT  # noqa: E402
from helpers.tilt_scan import one_tilt_plan  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.animate import animate_region, draw_region, region_runs  # noqa: E402
from wrenchcone_ros.core.plan import certify_region, execute  # noqa: E402
from wrenchcone_ros.core.uncertainty import NOMINAL  # noqa: E402

pytestmark = pytest.mark.slow  # a plan, a small region, a dozen traced runs, a PNG, a GIF

STARTS = 4


@pytest.fixture(scope="module")
def region_plan():
    scene = load_scene(ROOT / "examples" / "pawl_seating.yaml")
    plan = one_tilt_plan(scene, math.radians(-60.0), (1, 2, 3))
    cert = certify_region(scene, plan, (0.001, 0.001, math.radians(2.0)), NOMINAL,
                          grid=2, bisections=1, sampled=0, draws=0, workers=1)
    assert cert.certified is not None
    plan = replace(plan, region=cert)
    return scene, plan, region_runs(scene, plan, STARTS, seed=5)


def com(scene, pose):
    cx, cy = scene.workpiece.com
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.array([pose[0] + c * cx - s * cy, pose[1] + s * cx + c * cy])


def test_the_drawn_paths_end_where_the_engine_leaves_the_part(region_plan, tmp_path):
    scene, plan, runs = region_plan
    d = draw_region(scene, plan, tmp_path / "region.png", runs=runs)
    with Image.open(d.path) as png:
        assert png.size[0] > 300 and sum(n > 0 for n in png.convert("L").histogram()) > 20
    lines = [ln for ln in d.figure.axes[0].lines if ln.get_gid() == "path"]
    drawn = [r for r in runs if not r.cover]
    assert len(lines) == len(drawn) == STARTS
    box = plan.start_region
    for line, r in zip(lines, drawn):
        offset = np.subtract(r.start, scene.pose)
        assert all(abs(o) <= h + 1e-12 for o, h in zip(offset, box.half_widths))
        again = execute(scene.with_pose(*r.start), plan)
        xy = np.column_stack(line.get_data())
        assert np.allclose(xy[-1], com(scene, again.final_pose), atol=1e-9)
        assert np.allclose(xy[0], com(scene, r.start), atol=1e-9)
        assert np.hypot(*(xy[-1] - xy[0])) > 1e-3  # it moved: the path is not a point
    # every run enters the first segment at its start
    starts = np.array(sorted(r.start for r in runs))
    assert np.allclose(np.array(sorted(map(tuple, d.entries[0]))), starts, atol=1e-6)
    assert len(d.entries) == len(plan.segments)


def test_the_animation_shows_the_drawn_starts_moving(region_plan, tmp_path):
    scene, plan, runs = region_plan
    out = animate_region(scene, plan, tmp_path / "region.gif", runs=runs, frames=12)
    with Image.open(out) as gif:
        assert gif.n_frames == 12
        first = gif.convert("RGB").tobytes()
        gif.seek(11)
        last = gif.convert("RGB").tobytes()
    assert first != last
    with pytest.raises(ValueError, match=r"\.gif or \.mp4"):
        animate_region(scene, plan, tmp_path / "region.png", runs=runs)
    with pytest.raises(ValueError, match="no certified start region"):
        draw_region(scene, replace(plan, region=None), tmp_path / "x.png")


def test_the_docs_show_the_region_pictures():
    text = (ROOT / "docs" / "planning.md").read_text()
    for name, least in (("plan_region_pawl.png", 20_000), ("plan_region_pawl.gif", 50_000)):
        assert f"figures/{name}" in text
        assert (ROOT / "docs" / "figures" / name).stat().st_size > least
