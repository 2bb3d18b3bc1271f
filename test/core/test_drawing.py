# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Drawing geometry against hand-worked values and independent formulas (complex numbers
for rigid motions, the cross product for moments, the paper's example for cones)."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from wrenchcone_ros.core import ModeError, default_scene, load_scene, wrench_cone
from wrenchcone_ros.core.drawing import (
    LETTER_COLOURS,
    break_wraps,
    contact_sketches,
    great_circle,
    line_of_force,
    outline,
    sphere_angles,
    sphere_directions,
)
from wrenchcone_ros.core.modes import MODE_TABLE

RNG = np.random.default_rng(20261123)
PAWL = "examples/pawl_polygon.yaml"


def test_polygon_outline_is_the_vertices_moved_by_the_pose():
    base = load_scene(PAWL)
    for x, y, th in [(0.1, 0.2, 0.0), (-3.0, 7.5, 2.1), (1e3, -2e3, -0.7)]:
        scene = base.with_pose(x, y, th)
        got = outline(scene)
        want = [complex(*v) * cmath.exp(1j * th) + complex(x, y)
                for v in scene.workpiece.shape.vertices]
        assert np.allclose(got[:-1, 0], [w.real for w in want], atol=1e-12, rtol=1e-12)
        assert np.allclose(got[:-1, 1], [w.imag for w in want], atol=1e-12, rtol=1e-12)
        assert np.array_equal(got[0], got[-1])  # closed


def test_disc_outline_lies_on_the_circle_round_the_pose():
    scene = default_scene().with_pose(0.3, 3.0, 1.0)
    pts = outline(scene, samples=50)
    assert pts.shape == (51, 2)
    assert np.allclose(np.hypot(pts[:, 0] - 0.3, pts[:, 1] - 3.0), 1.0, atol=1e-12)


def test_paper_disc_contacts_and_force_cones():
    # fixel 1 at (0, -1) under the unit disc: n = (0, 1) into the disc, t = (-1, 0).
    # Rolling (n) allows the whole cone n +- mu t; fixel 2 is free (a): no force.
    scene = default_scene()
    s1, s2 = contact_sketches(scene, "na")
    assert s1.in_contact and not s2.in_contact
    assert s1.letter == "n" and s2.letter == "a"
    assert np.allclose(s1.point, (0.0, -1.0)) and np.allclose(s1.normal, (0.0, 1.0))
    assert np.allclose(s1.tangent, (-1.0, 0.0))
    want = {(0.2 / math.hypot(0.2, 1), 1 / math.hypot(0.2, 1)),
            (-0.2 / math.hypot(0.2, 1), 1 / math.hypot(0.2, 1))}
    got = {tuple(np.round(e, 12)) for e in s1.force_edges}
    assert got == {tuple(np.round(w, 12)) for w in want}
    assert s2.force_edges.shape == (0, 2)
    assert s1.colour == LETTER_COLOURS["n"] and s2.colour == LETTER_COLOURS["a"]


def test_sliding_right_force_is_the_edge_that_opposes_the_motion():
    # Sliding right: the disc's point moves along -t = (+1, 0); Coulomb friction opposes
    # the motion, so the fixel pushes along n + mu t = (-mu, 1) (up and to the left).
    (s1, _) = contact_sketches(default_scene(), "ra")
    assert s1.force_edges.shape == (1, 2)
    assert np.allclose(s1.force_edges[0], np.array([-0.2, 1.0]) / math.hypot(0.2, 1.0))
    (s1, _) = contact_sketches(default_scene(), "la")
    assert np.allclose(s1.force_edges[0], np.array([0.2, 1.0]) / math.hypot(0.2, 1.0))


def test_no_mode_and_bad_mode():
    sk = contact_sketches(load_scene(PAWL))
    assert [s.letter for s in sk] == [None, None, None]
    assert all(s.force_edges.shape == (0, 2) for s in sk)
    assert [s.radius for s in sk] == [0.003] * 3
    with pytest.raises(ModeError):
        contact_sketches(default_scene(), "nn")  # fixel 2 is not in contact


def test_every_letter_has_a_colour():
    assert set(LETTER_COLOURS) == set(MODE_TABLE)


def test_line_of_force_has_the_wrench_moment_about_the_com():
    scene = load_scene(PAWL).with_pose(5.0, 5.0, 0.8)
    c = scene.com_world
    for g in RNG.normal(size=(50, 3)):
        q, d = line_of_force(scene, g)
        assert np.allclose(d * math.hypot(g[0], g[1]), g[:2])  # along the force
        for s in (-1.7, 0.0, 2.3):  # any point of the line: (p - com) x f = tau
            r = q + s * d - c
            assert r[0] * g[1] - r[1] * g[0] == pytest.approx(g[2], abs=1e-12)
    assert line_of_force(scene, (0.0, 0.0, 1.0)) is None


def test_sphere_angles_of_the_papers_generators():
    # g1 = (1, 0, -1), g2 = (-0.2, -1, -0.2), L = 1: worked by hand
    a = sphere_angles(np.array([1.0, 0.0, -1.0]))
    assert np.allclose(a, (0.0, -math.pi / 4))
    a = sphere_angles(np.array([[-0.2, -1.0, -0.2]]))[0]
    assert a[0] == pytest.approx(-math.pi + math.atan(1 / 0.2))
    assert a[1] == pytest.approx(-math.atan(0.2 / math.sqrt(1.04)))


def test_sphere_map_round_trip():
    u = RNG.normal(size=(200, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    a = sphere_angles(u)
    assert np.allclose(sphere_directions(a[:, 0], a[:, 1]), u, atol=1e-12)


def test_great_circle_is_orthogonal_to_its_normal():
    for e in RNG.normal(size=(10, 3)):
        c = great_circle(e, 100)
        assert np.allclose(c @ e, 0.0, atol=1e-12)
        assert np.allclose(np.linalg.norm(c, axis=1), 1.0)


def test_break_wraps_splits_at_the_seam():
    a = np.array([[3.0, 0.0], [3.1, 0.1], [-3.1, 0.2], [-3.0, 0.3]])
    out = break_wraps(a)
    assert out.shape == (5, 2) and np.isnan(out[2]).all()


def test_cone_generators_map_where_the_paper_says():
    cone = wrench_cone(default_scene(), "na")
    got = sorted(map(tuple, np.round(sphere_angles(cone.G_hat), 9)))
    want = sorted(tuple(np.round((math.atan2(y, x), math.atan2(z, math.hypot(x, y))), 9))
                  for x, y, z in [(1, 0, -1), (-0.2, -1, -0.2), (0.2, -1, 0.2)])
    assert got == want


def test_fan_triangles_cover_the_sector():
    from wrenchcone_ros.core.drawing import fan_triangles

    tri = fan_triangles((1.0, 2.0), -0.5, 1.0, 0.3)
    assert tri.shape[1:] == (3, 2) and tri.shape[0] >= 1.5 / math.radians(5.0)
    assert np.allclose(tri[:, 0], (1.0, 2.0))
    rims = tri[:, 1:].reshape(-1, 2) - (1.0, 2.0)
    assert np.allclose(np.hypot(rims[:, 0], rims[:, 1]), 0.3)
    # shoelace areas add up to the sector's (r^2 (hi - lo) / 2) less the chords' sag
    a, b = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area = 0.5 * np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    assert 0.995 * 0.3 ** 2 * 1.5 / 2 < area <= 0.3 ** 2 * 1.5 / 2
    with pytest.raises(ValueError):
        fan_triangles((0, 0), 1.0, 0.0, 1.0)


def test_best_arrow():
    from wrenchcone_ros.core.drawing import best_arrow

    tail, tip = best_arrow((0.1, -0.2), math.pi / 2, 0.5)  # straight up, 0.5 m
    assert tuple(tail) == (0.1, -0.2)
    assert tip == pytest.approx((0.1, 0.3), abs=1e-15)
    tail, tip = best_arrow((0.0, 0.0), math.atan2(-4.0, 3.0), 5.0)  # the 3-4-5 triangle
    assert tip == pytest.approx((3.0, -4.0), abs=1e-12)
