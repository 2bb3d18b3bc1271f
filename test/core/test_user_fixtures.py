# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The user family (test/helpers/user_fixtures.py): its transforms keep the physics, the
cones and the planner are equivariant under them, and the engine agrees.

Independent references: the contact geometry the core's Scene computes for each scene
(gaps, contact points, normals), hand-computed positions (a pin under a flat edge), the
rotation and reflection of the plane applied to wrenches and directions, and the
physics engine run on both scenes."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from helpers.user_fixtures import (
    GAP_TOLERANCE_M,
    KINDS,
    PIN_RADII,
    map_direction,
    map_mode,
    map_pose,
    map_wrench,
    mirror,
    rectangle_scene,
    resize_pins,
    turn,
    user_family,
)
from wrenchcone_ros.core import enumerate_modes, wrench_cone
from wrenchcone_ros.core.scene_yaml import scene_from_dict

FAMILY = user_family(14, seed=0)

#: rad: how far a transformed plan's direction may lie from the original's mapped. The
#: search's largest-margin direction ends in a bounded scalar search with an x tolerance
#: of 1e-6 rad (core/plan/segments.py, best_direction); the two runs see the same margin
#: function up to rounding, so their optima agree to about that tolerance.
DIRECTION_TOLERANCE = 1e-5

#: Dimensionless: a wrench this close to a cone's boundary (its margin) is left out of
#: the membership comparison (rounding may put it on either side).
BOUNDARY = 1e-7


def _normals(scene):
    return np.array([c.n for c in scene.contacts], dtype=float)


def _points(scene):
    return np.array([c.p for c in scene.contacts], dtype=float)


def test_the_family_is_what_it_says():
    """Every kind, unequal radii in PIN_RADII, turned, half of them mirrored, valid
    scenes, each task's friction interval its mu +- 0.1."""
    assert {t.kind for t in FAMILY} == set(KINDS)
    assert sum(t.mirrored for t in FAMILY) not in (0, len(FAMILY))
    for t in FAMILY:
        assert all(PIN_RADII[0] <= r <= PIN_RADII[1] for r in t.radii)
        assert len(set(t.radii)) == len(t.radii)
        assert -math.pi <= t.alpha < math.pi
        s = scene_from_dict(t.scene)
        assert [f.radius for f in s.fixels] == list(t.radii)
        mu = s.friction
        assert t.friction == pytest.approx((max(0.0, mu - 0.1), mu + 0.1), abs=1e-12)
        assert set(t.target) <= set(range(1, s.n_fixels + 1))
    again = user_family(14, seed=0)
    assert [t.scene for t in again] == [t.scene for t in FAMILY]
    assert [t.scene for t in user_family(14, seed=1)] != [t.scene for t in FAMILY]


@pytest.mark.parametrize("kind", ["plate", "tall"])
def test_rectangles_touch_as_intended(kind):
    """The family's own shapes, checked by hand: the rectangle lies on pins 2 and 3
    (their tops at y = 0.2 m, under the bottom edge) and not on the stop at the start;
    slid right by the offset it touches all three, the com between the pins all along."""
    tasks = [t for t in user_family(28, seed=3) if t.kind == kind]
    assert tasks
    for t in tasks:
        p = t.params
        d = rectangle_scene(p["width"], p["height"], p["pin2_x"], p["pin3_x"],
                            p["stop_y"], p["offset"], p["mu"])
        assert d == t.base
        start = scene_from_dict(d)
        assert start.in_contact == (False, True, True)
        assert start.gaps[0] == pytest.approx(p["offset"], abs=1e-12)
        seat = start.with_pose(0.1, 0.2, 0.0)
        assert seat.in_contact == (True, True, True)
        for x0 in (0.1 - p["offset"], 0.1):  # start and seat: com between the pins
            assert p["pin2_x"] < x0 + p["width"] / 2 < p["pin3_x"]
            assert x0 < p["pin2_x"] and p["pin3_x"] < x0 + p["width"]


@pytest.mark.parametrize("task", FAMILY, ids=[t.name for t in FAMILY])
def test_transforms_keep_every_gap_and_turn_the_normals(task):
    """Resized pins: the same gaps, contact set, contact points and normals; turned: the
    same gaps and contacts, points and normals rotated by alpha; mirrored: reflected
    x -> -x (all from the core's Scene of each scene)."""
    base = scene_from_dict(task.base)
    resized_d = resize_pins(task.base, task.radii)
    resized = scene_from_dict(resized_d)
    turned = scene_from_dict(turn(resized_d, task.alpha))
    mirrored = scene_from_dict(mirror(turn(resized_d, task.alpha)))
    for s in (resized, turned, mirrored):
        assert np.abs(np.array(s.gaps) - np.array(base.gaps)).max() <= GAP_TOLERANCE_M
        assert s.in_contact == base.in_contact
    c = list(base.in_contact)
    R = np.array([[math.cos(task.alpha), -math.sin(task.alpha)],
                  [math.sin(task.alpha), math.cos(task.alpha)]])
    M = np.diag([-1.0, 1.0])
    np.testing.assert_allclose(_normals(resized)[c], _normals(base)[c], atol=1e-12)
    np.testing.assert_allclose(_points(resized)[c], _points(base)[c], atol=1e-12)
    np.testing.assert_allclose(_normals(turned), _normals(resized) @ R.T, atol=1e-12)
    np.testing.assert_allclose(_points(turned), _points(resized) @ R.T, atol=1e-12)
    np.testing.assert_allclose(_normals(mirrored), _normals(turned) @ M, atol=1e-12)
    np.testing.assert_allclose(_points(mirrored), _points(turned) @ M, atol=1e-12)
    np.testing.assert_allclose(mirrored.com_world,
                               M @ (R @ scene_from_dict(task.base).com_world), atol=1e-12)
    np.testing.assert_allclose(map_pose(base.pose, task.alpha, task.mirrored),
                               scene_from_dict(task.scene).pose, atol=1e-15)


def test_a_pin_under_a_flat_edge_by_hand():
    """The pawl's pins 2 and 3 under its flat foot (y = 0.2 m): resized to r', each
    centre is at (x, 0.2 - r'), its x unchanged."""
    t = next(t for t in FAMILY if t.kind == "seating")
    d = resize_pins(t.base, t.radii)
    for i in (1, 2):
        assert d["fixels"][i]["position"][0] == t.base["fixels"][i]["position"][0]
        assert d["fixels"][i]["position"][1] == pytest.approx(0.2 - t.radii[i], abs=1e-15)


def test_resize_refuses_a_pin_that_would_touch_elsewhere():
    """A pin near the pawl's concave corner (the inner corner of its L at (0.015,
    0.01) m in the part's frame), 0.5 mm above the foot and 1 mm from the post, grown
    to 5 mm and moved up by 2 mm would cut into the post: resize_pins refuses it."""
    d = {"workpiece": {"mass": 0.05, "inertia": 2e-5, "com": [0.02, 0.012],
                       "shape": {"type": "polygon", "vertices": [
                           [0.0, 0.0], [0.06, 0.0], [0.06, 0.01], [0.015, 0.01],
                           [0.015, 0.035], [0.0, 0.035]]},
                       "pose": [0.0, 0.0, 0.0]},
         "friction": 0.3, "contact_tolerance": 1e-9,
         "fixels": [{"position": [0.019, 0.0135], "radius": 0.003}]}
    with pytest.raises(ValueError, match="resized pins"):
        resize_pins(d, [0.005])


def _random_wrenches(rng, n=300):
    g = rng.normal(size=(n, 3))
    return g / np.linalg.norm(g, axis=1, keepdims=True)


@pytest.mark.parametrize("task", FAMILY[:7], ids=[t.name for t in FAMILY[:7]])
def test_cones_are_equivariant(task):
    """For every mode at the start pose: g is in the original's cone iff the mapped
    wrench (R f, tz), mirrored (M f, -tz), is in the transformed scene's cone of the
    mapped mode (l and r swapped when mirrored), with the same margin (the margin is a
    distance in (fx, fy, tz / L), which the rotation and reflection preserve); the
    resized scene's cones are the base's."""
    base = scene_from_dict(task.base)
    resized = scene_from_dict(task.resized)
    moved = scene_from_dict(task.scene)
    L = base.length_scale
    rng = np.random.default_rng(7)
    G = _random_wrenches(rng) * np.array([1.0, 1.0, L])
    compared = 0
    for mode in enumerate_modes(base.in_contact):
        a = wrench_cone(base, mode)
        r = wrench_cone(resized, mode)
        b = wrench_cone(moved, map_mode(mode, task.mirrored))
        assert a.feasible == r.feasible == b.feasible, mode
        if not a.feasible:
            continue
        for g in G:
            m = a.margin(g)
            assert r.margin(g) == pytest.approx(m, abs=1e-9)
            h = map_wrench(g, task.alpha, task.mirrored)
            assert b.margin(h) == pytest.approx(m, abs=1e-9), (mode, g)
            if abs(m) > BOUNDARY:
                assert b.contains(h) == a.contains(g) == (m > 0), (mode, g)
                compared += 1
    assert compared > 100


def test_cones_of_a_mirrored_scene_exactly():
    """Mirroring negates coordinates, which the exact (rational) cones take as written:
    the exact cone of the mirrored pawl of examples/pawl_seating.yaml, mode with l and r
    swapped, contains (-fx, fy, -tz) iff the original's contains (fx, fy, tz), for
    rational wrenches on both sides of every face."""
    from fractions import Fraction

    from helpers.user_fixtures import EXAMPLES, ROOT
    import yaml

    d = yaml.safe_load((ROOT / "examples" / f"{EXAMPLES[0][0]}.yaml").read_text())
    a_scene, b_scene = scene_from_dict(d), scene_from_dict(mirror(d))
    rng = np.random.default_rng(3)
    for mode in enumerate_modes(a_scene.in_contact):
        a = wrench_cone(a_scene, mode, exact=True)
        b = wrench_cone(b_scene, map_mode(mode, True), exact=True)
        assert a.feasible == b.feasible, mode
        if not a.feasible:
            continue
        Fa = [tuple(r) for r in a.exact_rep.F] if a.exact_rep is not None else []
        Fb = [tuple(r) for r in b.exact_rep.F] if b.exact_rep is not None else []
        Ea = [tuple(r) for r in a.exact_rep.E] if a.exact_rep is not None else []
        Eb = [tuple(r) for r in b.exact_rep.E] if b.exact_rep is not None else []
        for _ in range(200):
            g = [Fraction(int(v), 1000) for v in rng.integers(-1000, 1001, size=3)]
            h = [-g[0], g[1], -g[2]]

            def inside(F, E, w):
                return (all(sum(x * y for x, y in zip(row, w)) <= 0 for row in F)
                        and all(sum(x * y for x, y in zip(row, w)) == 0 for row in E))
            assert inside(Fa, Ea, g) == inside(Fb, Eb, h), (mode, g)


# --- the planner and the engine ------------------------------------------------------
_PLANS: dict = {}


def _plan(task, which: str):
    """The plan (friction interval of the task, no sampled runs) of the task's base
    scene ("base"), resized ("resized") or transformed ("moved"), once per process."""
    from wrenchcone_ros.core.plan import plan_seating

    key = (task.name, which)
    if key not in _PLANS:
        d = {"base": task.base, "resized": task.resized, "moved": task.scene}[which]
        _PLANS[key] = plan_seating(scene_from_dict(d), task.target, "tilt",
                                   uncertainty=task.friction, runs=0)
    return _PLANS[key]


def _mapped(plan, alpha: float, mirrored: bool):
    """The plan's segments in the transformed task: modes, directions, poses mapped."""
    segs = tuple(replace(s, mode=map_mode(s.mode, mirrored),
                         direction=map_direction(s.direction, alpha, mirrored),
                         start_pose=tuple(map_pose(s.start_pose, alpha, mirrored)),
                         end_pose=tuple(map_pose(s.end_pose, alpha, mirrored)))
                 for s in plan.segments)
    return replace(plan, segments=segs)


def _assert_same_plan(a, b, alpha: float, mirrored: bool, hold_margin: bool = True):
    assert a.feasible == b.feasible and a.guaranteed == b.guaranteed, (a.reason, b.reason)
    assert [map_mode(s.mode, mirrored) for s in a.segments] == [s.mode for s in b.segments]
    assert [s.scale for s in a.segments] == [s.scale for s in b.segments]
    for s, t in zip(a.segments, b.segments):
        d = math.remainder(map_direction(s.direction, alpha, mirrored) - t.direction,
                           2 * math.pi)
        assert abs(d) <= DIRECTION_TOLERANCE, (s.mode, s.direction, t.direction, d)
        if hold_margin or not s.hold:
            assert t.margin == pytest.approx(s.margin, abs=1e-6)
        np.testing.assert_allclose(map_pose(s.end_pose, alpha, mirrored), t.end_pose,
                                   atol=1e-7)


#: Tasks of FAMILY planned turned (and mirrored where the task is): a disc turned, a
#: plate turned and mirrored, a pivot turned and mirrored, the example pawl turned; and
#: the first pawl of the seating family, whose plan is the search's last resort of one
#: constant tilt (the tilts are anchored at the part's start orientation:
#: core/plan/segments.py, constant_directions); a disc in its nest, whose two hold
#: intervals have the same margin (tried nearest the previous direction first:
#: segments.py, HOLD_TIE_MARGIN).
EQUIVARIANT = [0, 1, 2, 3, 4, 7, 8, 9]

@pytest.mark.slow
@pytest.mark.parametrize("k", EQUIVARIANT)
def test_the_planner_is_equivariant(k):
    """The transformed task's plan is the original's (its pins resized) mapped: the same
    modes (l and r swapped when mirrored), directions + alpha (pi - phi when mirrored) to
    DIRECTION_TOLERANCE, the same force scales, margins and verdict, the end poses
    mapped."""
    task = FAMILY[k]
    a, b = _plan(task, "resized"), _plan(task, "moved")
    assert a.feasible
    _assert_same_plan(a, b, task.alpha, task.mirrored)


#: Tasks whose path runs on flat edges only (the pawl, a plate): their pins' radii do
#: not change the path, so the resized task must get the same plan. (On a disc or a
#: pivot the part rolls or turns about a pin, a path that depends on its radius: the
#: plans differ there by 0.1 to 0.15 deg, or in a discrete choice.) The hold's margin is
#: not compared: it includes the funnel's, at near-seated poses turned about the stop
#: and a pin, which depend on the pins' radii (it moved by 1e-5 to 3e-5 here).
@pytest.mark.slow
@pytest.mark.parametrize("k", [2, 7])
def test_resized_pins_give_the_same_plan(k):
    task = FAMILY[k]
    assert task.kind in ("seating", "plate")
    a, b = _plan(task, "base"), _plan(task, "resized")
    assert a.feasible
    _assert_same_plan(a, b, 0.0, False, hold_margin=False)


@pytest.mark.slow
@pytest.mark.parametrize("k", [1, 2, 4])
def test_the_engine_agrees_on_the_transformed_task(k):
    """The original's plan run open loop (nominal model) on the original scene, and the
    same plan mapped on the transformed scene: both seat the part (or neither), with the
    same contact events, and end at poses that map onto each other (to 1e-6 m, rad: the
    engine's rounding differs in the turned frame)."""
    from wrenchcone_ros.core.plan import execute

    task = FAMILY[k]
    plan = _plan(task, "resized")
    assert plan.feasible
    a = execute(scene_from_dict(task.resized), plan)
    b = execute(scene_from_dict(task.scene), _mapped(plan, task.alpha, task.mirrored))
    assert a.success == b.success
    assert a.events == b.events
    np.testing.assert_allclose(map_pose(a.final_pose, task.alpha, task.mirrored),
                               b.final_pose, atol=1e-6)
