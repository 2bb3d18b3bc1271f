# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Animations of a simulated plan (core/animate.py), read back with Pillow (an independent
GIF decoder): one frame per recorded instant of the run (``plan.trace``, at most
MAX_FRAMES plus the changes of segment), FPS frames a second, a picture that changes as
the part moves; bad paths and empty plans refused with a worded error."""

from __future__ import annotations

import math

import pytest

pytest.importorskip("pymunk")
pytest.importorskip("matplotlib")
Image = pytest.importorskip("PIL.Image")

from helpers.docs_examples import ROOT  # noqa: E402
from helpers.tilt_scan import one_tilt_plan  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.animate import FPS, MAX_FRAMES, animate_plan  # noqa: E402
from wrenchcone_ros.core.plan import trace  # noqa: E402

pytestmark = pytest.mark.slow  # a simulated run and a GIF of up to 90 frames: ~10 s


@pytest.fixture(scope="module")
def pawl_plan():
    """The pawl of docs/planning.md under one tilt that seats it (-60 degrees)."""
    scene = load_scene(ROOT / "examples" / "pawl_seating.yaml")
    return scene, one_tilt_plan(scene, math.radians(-60.0), (1, 2, 3))


def test_the_gif_has_one_frame_per_recorded_instant_at_fps(pawl_plan, tmp_path):
    scene, plan = pawl_plan
    record_every = 20
    _, frames = trace(scene, plan, None, record_every=record_every)
    changes = sum(1 for a, b in zip(frames, frames[1:]) if a.segment != b.segment)
    out = animate_plan(scene, plan, tmp_path / "plan.gif", record_every=record_every)
    with Image.open(out) as gif:
        n = gif.n_frames
        durations = []
        first = gif.convert("RGB").tobytes()
        for k in range(n):
            gif.seek(k)
            durations.append(gif.info["duration"])
        last = gif.convert("RGB").tobytes()
    assert min(len(frames), MAX_FRAMES) <= n <= min(len(frames), MAX_FRAMES + changes)
    # GIF stores durations in hundredths of a second: 1/FPS to within 10 ms
    assert all(abs(d - 1000.0 / FPS) <= 10.0 for d in durations), durations
    assert first != last  # the part moved between the first and the last frame


def test_bad_paths_and_empty_plans_are_refused(pawl_plan, tmp_path):
    scene, plan = pawl_plan
    with pytest.raises(ValueError, match=r"\.gif or \.mp4.*plan\.png"):
        animate_plan(scene, plan, tmp_path / "plan.png")
    empty = type(plan)((), plan.feasible, plan.reason, plan.target, plan.actuator, None)
    with pytest.raises(ValueError, match="no segments"):
        animate_plan(scene, empty, tmp_path / "plan.gif")
