# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Where the part rests on a segment's contacts, the cones decide
(core/plan/region_cones.py).

Checked against what shares no code with the cones:

* the geometry: every cover pose touches exactly the slice's fixels (the scene's own
  gaps), the pawl's foot on pins 2 and 3 slides flat (y and theta of the start);
* the engine (pymunk): from rest at a cover pose, under each corner model of the
  friction box (one mu per pin), the part slides in the planned mode (the engine's own
  mode letters) exactly where the cones' margin for that model is positive, and stays
  put where it is negative;
* not vacuous: a box long enough to reach the poses where the part sticks fails there,
  and a hold direction turned off its interval fails the lifted slices.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.plan import (
    ConeSlice,
    PlanError,
    RegionCertificate,
    StartRegion,
    check_region_cones,
    exclusive_margin,
    plan_seating,
    slice_cover,
    trace,
)
from wrenchcone_ros.core.plan.region_cones import segment_slices
from wrenchcone_ros.core.uncertainty import as_uncertainty

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PAWL_BOX = (0.002, 0.002, math.radians(5.0))
#: the margin (dimensionless) within which the engine may go either way: a pose that
#: near a mode boundary is the engine's step and slop, not the cones'
BAND = 0.01


@pytest.fixture(scope="module")
def pawl():
    scene = load_scene(EXAMPLES / "pawl_seating.yaml")
    return scene, plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4),
                               simulate_runs=False)


def _box(centre, half):
    c, h = np.asarray(centre, dtype=float), np.asarray(half, dtype=float)
    return c - h, c + h


def _touching(scene, pose) -> set[int]:
    return {i + 1 for i, c in enumerate(scene.with_pose(*pose).in_contact) if c}


def _slides(scene, plan, pose, model) -> bool:
    """The engine's answer: from rest at ``pose`` under ``model``, does the part move in
    segment 1's mode (the engine's mode letters in the first recorded frames)?"""
    _, frames = trace(scene.with_pose(*pose), plan, model, record_every=5)
    return any(f.readout.letters == plan.segments[0].mode for f in frames[:5])


def _corner_models():
    # pin 1 is not touched in segment 1; pins 2 and 3 at the ends of [0.2, 0.4]
    return [(0.3, a, b) for a, b in itertools.product((0.2, 0.4), repeat=2)]


def test_the_pawls_start_box_rests_on_its_pins(pawl):
    """+-2 mm x +-2 mm x +-5 deg: the poses at rest on pins 2 and 3 are the foot slid
    flat along them, x +-2 mm; at every cover pose the tilt gives mode arr alone for
    every model, and the engine slides the part in arr under every corner model at the
    slice's ends and middle."""
    scene, plan = pawl
    lo, hi = _box(scene.pose, PAWL_BOX)
    (piece,) = segment_slices(scene, plan, 0, lo, hi, "the start box")
    assert piece.contacts == (2, 3) and piece.lifted == 0 and piece.dimension == 1
    assert piece.holds and piece.points >= 17 and piece.worst > 0.1
    poses, step = slice_cover(scene, scene.pose, (1, 2), lo, hi)
    assert len(poses) == piece.points and step == pytest.approx(0.004 / 16)
    xs = sorted(p[0] for p in poses)
    assert xs[0] == pytest.approx(lo[0], abs=1e-9) and xs[-1] == pytest.approx(hi[0], abs=1e-9)
    for p in poses:
        assert _touching(scene, p) == {2, 3}
        assert p[1] == pytest.approx(scene.pose[1], abs=1e-9)
        assert p[2] == pytest.approx(scene.pose[2], abs=1e-9)
    for p in (min(poses), poses[len(poses) // 2], max(poses)):
        for model in _corner_models():
            assert _slides(scene, plan, p, model), (p, model)
    text = piece.verdict()
    assert text.startswith("segment 1 at rest on fixel(s) 2 3, in the start box (a curve; ")
    assert "the direction gives mode arr alone for every model at every cover pose" in text
    assert "between cover poses nothing is proved" in text


def test_the_cones_and_the_engine_agree_where_the_part_sticks(pawl):
    """A box 30 mm long in x reaches the poses where the foot has left its flat
    (the part turned on a pin): there the tilt does not make the part slide for every
    friction. The slice fails there; model by model, the engine slides the part exactly
    where the cones' margin for that model is positive (outside BAND)."""
    scene, plan = pawl
    lo, hi = _box(scene.pose, (0.03, 0.002, math.radians(5.0)))
    (piece,) = segment_slices(scene, plan, 0, lo, hi, "the start box")
    assert not piece.holds and 0 < piece.failed < piece.points and piece.worst < 0
    assert "does not give mode arr alone for every model at" in piece.verdict()
    poses, _ = slice_cover(scene, scene.pose, (1, 2), lo, hi)
    seg = plan.segments[0]
    compared = {True: 0, False: 0}
    for p in sorted(poses)[::3]:
        assert _touching(scene, p) == {2, 3}
        for model in _corner_models():
            u = as_uncertainty([(m, m) for m in model])
            m = exclusive_margin(scene.with_pose(*p), lambda mode: mode == seg.mode, None,
                                 u)[0](seg.direction)
            if abs(m) < BAND:
                continue
            assert _slides(scene, plan, p, model) == (m > 0), (p, model, m)
            compared[m > 0] += 1
    assert compared[True] >= 4 and compared[False] >= 2  # both sides were compared


def test_the_hold_slices_lifted_off_each_target(pawl):
    """Around the seat (+-0.1 mm, +-0.1 mm, +-0.1 deg): for each target fixel, the poses at
    rest on the other two, lifted off it; the hold direction gives only modes
    approaching it there for every model. Turned by 30 degrees, it does not."""
    scene, plan = pawl
    hold = plan.segments[1]
    lo, hi = _box(hold.start_pose, (1e-4, 1e-4, math.radians(0.1)))
    pieces = segment_slices(scene, plan, 1, lo, hi, "segment 2's entry region")
    assert [p.lifted for p in pieces] == [1, 2, 3]
    for piece in pieces:
        assert piece.holds and piece.points >= 10, piece.verdict()
        kept = set(range(1, 4)) - {piece.lifted}
        assert set(piece.contacts) == kept
        poses, _ = slice_cover(scene, hold.start_pose, [i - 1 for i in kept], lo, hi)
        for p in poses:
            s = scene.with_pose(*p)
            assert _touching(scene, p) == kept
            assert s.gaps[piece.lifted - 1] > 0.0
        assert "only modes approaching fixel" in piece.verdict()
    turned = replace(plan, segments=(plan.segments[0],
                                     replace(hold, direction=hold.direction + math.radians(30))))
    bad = segment_slices(scene, turned, 1, lo, hi, "segment 2's entry region")
    assert any(not p.holds for p in bad)


def test_a_region_certificate_gains_its_slices(pawl):
    """check_region_cones: segment 1's slice in the certified box, then each entry
    region's; nothing without a certified box; a bad grid is an error."""
    scene, plan = pawl
    box = StartRegion(*PAWL_BOX)
    cert = RegionCertificate(box, box, 1.0, 5, 50, 75, ("nominal",), 1, 50)
    out = check_region_cones(scene, plan, cert)
    assert [(c.segment, c.lifted) for c in out.cone_slices] == [(1, 0)]
    assert isinstance(out.cone_slices[0], ConeSlice)
    d = out.to_dict()["cone_slices"][0]
    assert d["holds"] and d["contacts"] == [2, 3] and d["verdict"].startswith("segment 1")
    none = replace(cert, certified=None)
    assert check_region_cones(scene, plan, none) is none
    with pytest.raises(PlanError, match="grid must be a whole number >= 1"):
        check_region_cones(scene, plan, cert, grid=0)


@pytest.mark.parametrize("alpha, mirrored", [(0.7, False), (-2.3, True)])
def test_the_slice_in_a_turned_mirrored_frame_with_unequal_pins(pawl, alpha, mirrored):
    """The pawl with pins of radii 2, 4.5 and 1.5 mm, its frame turned by alpha and
    mirrored (test/helpers/user_fixtures.py, which keep every gap and contact): the
    slice of the box holding the turned start box rests on the mapped pins; each of its
    cover poses, mapped back, rests on pins 2 and 3 of the original scene, and its
    margin for the mapped mode and direction is the original's there, computed on the
    original scene."""
    import yaml
    from helpers.user_fixtures import map_direction, map_mode, map_pose, transform

    from wrenchcone_ros.core.scene_yaml import scene_from_dict

    scene, plan = pawl
    seg = plan.segments[0]
    base = yaml.safe_load((EXAMPLES / "pawl_seating.yaml").read_text())
    radii = (0.002, 0.0045, 0.0015)
    original = scene_from_dict(transform(base, radii, 0.0, False))
    moved = scene_from_dict(transform(base, radii, alpha, mirrored))
    assert original.in_contact == moved.in_contact == scene.in_contact
    lo, hi = _box(scene.pose, PAWL_BOX)
    corners = np.array([map_pose([a if b == 0 else c for b, a, c in zip(bits, lo, hi)],
                                 alpha, mirrored) for bits in np.ndindex(2, 2, 2)])
    poses, _ = slice_cover(moved, moved.pose, (1, 2), corners.min(axis=0),
                           corners.max(axis=0))
    assert len(poses) >= 17
    u, mode = plan.uncertainty, map_mode(seg.mode, mirrored)
    phi = map_direction(seg.direction, alpha, mirrored)

    def back(p):
        x, y, th = p
        if mirrored:
            x, th = -x, -th
        c, s = math.cos(-alpha), math.sin(-alpha)
        return (c * x - s * y, s * x + c * y, th - alpha)

    for p in poses[::4]:
        q = back(p)
        assert _touching(original, q) == {2, 3} and _touching(moved, p) == {2, 3}
        here = exclusive_margin(moved.with_pose(*p), lambda m: m == mode, None, u)[0](phi)
        there = exclusive_margin(original.with_pose(*q), lambda m: m == seg.mode, None,
                                 u)[0](seg.direction)
        assert here == pytest.approx(there, abs=1e-9) and there > 0.0
