# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The pictures show what the core computes: the cone map's shading against the LP check
(written from Table 2, not from the cone), generators where the paper puts them, cones
with an empty interior drawn on their equalities, the scene where the scene is."""

from __future__ import annotations

import cmath
import math
from collections import namedtuple

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from matplotlib.patches import Circle, Polygon, Wedge  # noqa: E402

from wrenchcone_ros.core import default_scene, load_scene, wrench_cone  # noqa: E402
from wrenchcone_ros.core.drawing import outline, sphere_directions  # noqa: E402
from wrenchcone_ros.core.lp_check import lp_consistent  # noqa: E402
from wrenchcone_ros.core.plot import cone_map_values, figure, save  # noqa: E402

PAWL = "examples/pawl_polygon.yaml"
DISC_MU0 = {"workpiece": {"mass": 1, "inertia": 1, "shape": {"type": "disc", "radius": 1}},
            "friction": 0.0, "fixels": [[0, -1]]}
SQUARE_MU0 = {"workpiece": {"mass": 1, "inertia": 0.2, "shape": {
    "type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}},
    "friction": 0.0, "fixels": [[0, -1], [0, 1]]}
Interval = namedtuple("Interval", "lo hi best margin")


def _panels(fig):
    left, right = fig.axes[:2]
    return left, right


@pytest.mark.parametrize("source, mode", [(PAWL, "arr"), (None, "na"), (None, "sa")])
def test_cone_map_shading_agrees_with_the_lp_check(source, mode):
    scene = load_scene(source) if source else default_scene()
    cone = wrench_cone(scene, mode)
    P, S, value = cone_map_values(cone, grid=(73, 37))
    rng = np.random.default_rng(7)
    idx = [ij for ij in zip(*np.nonzero(np.abs(value) > 0.02))]
    picked = [idx[k] for k in rng.choice(len(idx), size=40, replace=False)]
    inside = 0
    for i, j in picked:
        u = sphere_directions(P[i, j], S[i, j])
        g = (u[0], u[1], u[2] * scene.length_scale)
        lp = lp_consistent(scene, mode, g).consistent
        assert lp == (value[i, j] <= 0), (mode, g, value[i, j])
        inside += lp
    assert 0 < inside < len(picked)  # both kinds of direction were checked


@pytest.mark.slow
def test_paper_generators_are_drawn_at_their_directions():
    fig = figure(default_scene(), "na", wrench=(1.0, -1.0, -1.0))
    _, right = _panels(fig)
    dots = sorted((round(float(line.get_xdata()[0]), 6), round(float(line.get_ydata()[0]), 6))
                  for line in right.lines if line.get_marker() == "o")
    want = sorted((round(math.degrees(math.atan2(y, x)), 6),
                   round(math.degrees(math.atan2(z, math.hypot(x, y))), 6))
                  for x, y, z in [(1, 0, -1), (-0.2, -1, -0.2), (0.2, -1, 0.2)])
    assert dots == want
    star = [line for line in right.lines if line.get_marker() == "*"]
    assert len(star) == 1  # the wrench (1, -1, -1): phi -45 deg, psi -atan(1/sqrt 2)
    assert star[0].get_xdata()[0] == pytest.approx(-45.0)
    assert star[0].get_ydata()[0] == pytest.approx(-math.degrees(math.atan(1 / math.sqrt(2))))


def test_one_equality_is_drawn_as_an_arc_of_its_great_circle():
    # a frictionless rolling contact: the cone is a half-plane (1 equality, 1 facet)
    scene = load_scene(DISC_MU0)
    cone = wrench_cone(scene, "n")
    assert cone.E_hat.shape[0] == 1 and cone.F_hat.shape[0] == 1
    _, right = _panels(figure(scene, "n"))
    arcs = [line for line in right.lines if line.get_linewidth() == 3 and len(line.get_xdata())]
    xy = np.column_stack([arcs[0].get_xdata(), arcs[0].get_ydata()])
    xy = np.radians(xy[~np.isnan(xy).any(axis=1)])
    u = sphere_directions(xy[:, 0], xy[:, 1])
    assert np.abs(u @ cone.E_hat[0]).max() < 1e-12
    assert (u @ cone.F_hat[0]).max() < 1e-9
    assert 0.45 < len(u) / 1441 < 0.55  # a half-plane: half of the great circle


def test_two_equalities_are_the_points_of_the_line():
    scene = load_scene(SQUARE_MU0)
    cone = wrench_cone(scene, "nn")
    assert cone.E_hat.shape[0] == 2 and cone.L_hat.shape[0] == 1
    _, right = _panels(figure(scene, "nn"))
    pts = np.radians([(line.get_xdata()[0], line.get_ydata()[0]) for line in right.lines
                      if line.get_marker() == "o" and line.get_markersize() == 9])
    assert len(pts) == 2
    u = sphere_directions(pts[:, 0], pts[:, 1])
    assert np.abs(u @ cone.E_hat.T).max() < 1e-12
    assert np.allclose(u[0], -u[1])


def test_infeasible_mode_says_so():
    _, right = _panels(figure(load_scene(PAWL), "ann"))
    assert any("infeasible" in t.get_text() for t in right.texts)


def test_scene_panel_draws_the_scene_where_it_is():
    scene = load_scene(PAWL).with_pose(0.1, 0.2, 0.3)
    fig = figure(scene, "ass", wrench=(0.5, -1.0, 0.0),
                 point=(0.12, 0.23), directions=[Interval(-2.0, -1.0, -1.5, 0.1)])
    left, _ = _panels(fig)
    polys = [p for p in left.patches if isinstance(p, Polygon) and p.get_zorder() == 1]
    assert len(polys) == 1
    assert np.allclose(polys[0].get_xy()[:6], outline(scene)[:-1])
    pins = sorted((tuple(c.center), c.radius) for c in left.patches if isinstance(c, Circle))
    assert pins == sorted((tuple(f.position), f.radius) for f in scene.fixels)
    (fan,) = [w for w in left.patches if isinstance(w, Wedge)]
    assert (fan.theta1, fan.theta2) == pytest.approx((math.degrees(-2.0), math.degrees(-1.0)))
    # the point is on the workpiece (its frame): rotated by 0.3 rad, moved by (0.1, 0.2)
    w = complex(0.12, 0.23) * cmath.exp(0.3j) + complex(0.1, 0.2)
    assert fan.center == pytest.approx((w.real, w.imag), abs=1e-12)
    labels = sorted(t.get_text() for t in left.texts if t.get_text())
    assert labels == ["1 a", "2 s", "3 s", "com"]


def test_wrench_verdict_in_the_title():
    scene = load_scene(PAWL)
    for g, word in [((0.5, -1.0, 0.0), ": consistent"), ((-0.5, 1.0, 0.0), "NOT consistent")]:
        left, _ = _panels(figure(scene, "arr", wrench=g))
        assert word in left.get_title()
        assert lp_consistent(scene, "arr", g).consistent == (word == ": consistent")


def test_wildcard_mode_is_refused():
    with pytest.raises(ValueError, match="wildcards"):
        figure(default_scene(), "c*")


@pytest.mark.slow
@pytest.mark.parametrize("ext, magic", [("png", b"\x89PNG"), ("svg", b"<?xml"),
                                        ("pdf", b"%PDF")])
def test_files_and_their_formats(tmp_path, ext, magic):
    def draw(name):
        return save(figure(default_scene(), "na", wrench=(0.1, -1.0, 0.0)), tmp_path / name)

    a, b = draw(f"a.{ext}"), draw(f"b.{ext}")
    assert a.read_bytes().startswith(magic)
    assert a.read_bytes() == b.read_bytes()  # no dates, no random ids: reproducible
    with pytest.raises(ValueError, match="unknown format"):
        draw("a.jpeg")
