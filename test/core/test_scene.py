# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Scene geometry: discs, polygons, pins, poses; every bad-input path of the scene API."""

import math

import numpy as np
import pytest

from wrenchcone_ros.core import PAPER_DISC, SceneError, default_scene, load_scene
from wrenchcone_ros.core.numbers import EXACT


def scene(shape, fixels, pose=(0.0, 0.0, 0.0), com=(0.0, 0.0), **kw):
    d = {"workpiece": {"mass": 1.0, "inertia": 0.1, "com": list(com), "shape": shape,
                       "pose": list(pose)}, "friction": 0.3, "fixels": fixels}
    d.update(kw)
    return load_scene(d)


SQUARE = {"type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}


def test_paper_disc_frames():
    c1, c2 = default_scene().contacts
    assert c1.in_contact and not c2.in_contact
    assert np.allclose(c1.n, [0, 1]) and np.allclose(c1.t, [-1, 0])
    assert np.allclose(c2.n, [-1, 0]) and np.allclose(c2.t, [0, -1])
    assert c2.gap == pytest.approx(0.001)
    assert np.allclose(c1.p, [0, -1]) and np.allclose(c2.p, [1, 0])


@pytest.mark.parametrize("theta", [0.0, 0.3, -2.0, math.pi])
@pytest.mark.parametrize("offset", [(0.0, 0.0), (3.0, -2.0), (1e6, 1e6)])
def test_rigid_motion_invariance(theta, offset):
    """Moving workpiece and fixels together changes frames by the rotation only."""
    base = scene(SQUARE, [{"position": [0.2, -1.05], "radius": 0.05}, [1.0, 0.3], [0.0, 1.2]],
                 com=(0.1, 0.2))
    c, s = math.cos(theta), math.sin(theta)
    R = np.array([[c, -s], [s, c]])
    moved_fixels = [{"position": list(R @ np.array(f.position) + offset), "radius": f.radius}
                    for f in base.fixels]
    moved = scene(SQUARE, moved_fixels, pose=(*offset, theta), com=(0.1, 0.2))
    for a, b in zip(base.contacts, moved.contacts):
        assert a.in_contact == b.in_contact
        assert b.gap == pytest.approx(a.gap, abs=1e-9 * max(1.0, abs(offset[0])))
        assert np.allclose(R @ a.n, b.n, atol=1e-9)
        assert np.allclose(R @ a.t, b.t, atol=1e-9)
        assert b.r_n == pytest.approx(a.r_n, abs=1e-9) and b.r_t == pytest.approx(a.r_t, abs=1e-9)


def test_polygon_edge_pin_and_free_fixels():
    s = scene(SQUARE, [{"position": [0.3, -1.2], "radius": 0.2}, [1.5, 0.0], [0.0, 1.0]])
    a, b, c = s.contacts
    assert a.in_contact and np.allclose(a.n, [0, 1]) and np.allclose(a.p, [0.3, -1.0])
    assert not b.in_contact and b.gap == pytest.approx(0.5) and np.allclose(b.n, [-1, 0])
    assert c.in_contact and np.allclose(c.n, [0, -1])  # point fixel on the top edge
    # torque arms about the com (origin): r x n
    assert a.r_n == pytest.approx(0.3 * 1 - (-1.0) * 0)
    assert a.r_t == pytest.approx(0.3 * 0 - (-1.0) * (-1))


def test_nonconvex_polygon_notch():
    """A fixel in the notch of an L touches the inner edge, not a far edge."""
    L_shape = {"type": "polygon", "vertices": [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]}
    s = scene(L_shape, [[1.5, 1.0], [1.0, 1.5]], com=(0.7, 0.7))
    a, b = s.contacts
    assert a.in_contact and np.allclose(a.n, [0, -1])
    assert b.in_contact and np.allclose(b.n, [-1, 0])


def test_vertex_contact_with_pin_uses_direction_to_vertex():
    d = 0.1 / math.sqrt(2)
    s = scene(SQUARE, [{"position": [1 + d, 1 + d], "radius": 0.1}])
    (c,) = s.contacts
    assert c.in_contact and c.vertex
    assert np.allclose(c.n, [-math.sqrt(0.5), -math.sqrt(0.5)])


def test_point_fixel_on_vertex_is_refused():
    with pytest.raises(SceneError, match="vertex"):
        scene(SQUARE, [[1.0, 1.0]])


def test_penetration_is_refused_with_gap_and_tolerance():
    with pytest.raises(SceneError, match=r"fixel 1 .* penetrates .* by 0\.5 m"):
        scene(SQUARE, [[0.0, -0.5]])
    with pytest.raises(SceneError, match="penetrates"):
        load_scene({**PAPER_DISC, "fixels": [[0.0, -0.9]]})


def test_gap_at_the_contact_tolerance():
    tol = 1e-6
    inside = load_scene({**PAPER_DISC, "contact_tolerance": tol, "fixels": [[0, -1 - 0.5 * tol]]})
    outside = load_scene({**PAPER_DISC, "contact_tolerance": tol, "fixels": [[0, -1 - 2 * tol]]})
    assert inside.contacts[0].in_contact and not outside.contacts[0].in_contact


def test_coincident_fixels_are_independent_contacts():
    s = load_scene({**PAPER_DISC, "fixels": [[0.0, -1.0], [0.0, -1.0]], "modes": []})
    assert s.in_contact == (True, True)


def test_exact_geometry_is_rational_when_possible():
    frames = default_scene().contact_frames(EXACT)
    assert frames[1].p.tolist() == [1, 0]
    assert frames[0].r_t == -1


def test_length_scale_and_com():
    s = scene(SQUARE, [[0, -1]], pose=(1.0, 2.0, math.pi / 2), com=(0.5, 0.0))
    assert s.length_scale == pytest.approx(math.hypot(1.5, 1.0))
    assert np.allclose(s.com_world, [1.0, 2.5])


def test_round_trip_to_dict():
    s = load_scene("examples/pawl_polygon.yaml")
    assert load_scene(s.to_dict()) == s


def test_with_pose_and_fixels():
    s = default_scene().with_pose(0.0, 0.5, 0.0)
    assert not s.contacts[0].in_contact
    s2 = default_scene().with_fixels([(0.0, -1.0)])
    assert s2.n_fixels == 1


@pytest.mark.parametrize("patch, match", [
    ({"friction": -0.1}, "friction must be >= 0"),
    ({"friction": "lots"}, "friction must be a number"),
    ({"friction": float("nan")}, "finite"),
    ({"fixels": []}, "at least one fixel"),
    ({"fixels": "x"}, "fixels must be a list"),
    ({"fixels": [[0, -1, 2]]}, r"pair \[x, y\]"),
    ({"fixels": [{"position": [0, -2], "radius": -1}]}, "radius must be >= 0"),
    ({"fixels": [{"pos": [0, -2]}]}, "unknown key"),
    ({"contact_tolerance": 0}, "contact_tolerance must be > 0"),
    ({"modes": [1]}, "modes must be a list"),
    ({"colour": "red"}, "unknown key"),
])
def test_bad_scene_values(patch, match):
    with pytest.raises(SceneError, match=match):
        load_scene({**PAPER_DISC, **patch})


@pytest.mark.parametrize("wp, match", [
    ({"mass": 0}, "mass must be > 0"),
    ({"inertia": -1}, "inertia must be > 0"),
    ({"com": [0]}, "com must be a pair"),
    ({"pose": [0, 0]}, "pose must be"),
    ({"shape": {"type": "ellipse"}}, "'disc' or 'polygon'"),
    ({"shape": {"type": "disc"}}, "missing required key 'radius'"),
    ({"shape": {"type": "disc", "radius": 0}}, "radius must be > 0"),
    # m L^2 would underflow to 0 and 1 / L overflow
    ({"shape": {"type": "disc", "radius": 1e-300}}, r"characteristic length .* 1e-12 m"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [1e-13, 0], [0, 1e-13]]}},
     "characteristic length"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [1, 0]]}}, "at least 3"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [0, 1], [1, 0]]}}, "counter-clockwise"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [1, 1], [1, 0], [0, 1]]}},
     "not simple"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [2, 0], [0, 1], [2, 1]]}},
     "not simple"),
    ({"shape": {"type": "polygon", "vertices": [[0, 0], [1, 0], [1, 0], [0, 1]]}}, "distinct"),
])
def test_bad_workpiece(wp, match):
    d = {**PAPER_DISC, "workpiece": {**PAPER_DISC["workpiece"], **wp}, "fixels": [[5.0, 5.0]]}
    with pytest.raises(SceneError, match=match):
        load_scene(d)


def test_self_intersecting_ccw_polygon_refused():
    bow = {"type": "polygon", "vertices": [[0, 0], [4, 0], [4, 2], [1, -1], [0, 2]]}
    with pytest.raises(SceneError, match="not simple"):
        scene(bow, [[10, 10]])


@pytest.mark.parametrize("vertices, match", [
    # zero-area bow-ties: self-intersecting, and were called "clockwise"
    ([[0, 0], [1, 1], [1, 0], [0, 1]], "not simple: edge 0 crosses edge 2"),
    ([[0, 0], [2, 0], [0, 1], [2, 1]], "not simple: edge 1 crosses edge 3"),
    # a clockwise bow-tie (negative area) is still not simple first
    ([[0, 0], [0, 2], [4, -1], [4, 0], [1, 1]], "not simple"),
    # simple but degenerate: all on one line
    ([[0, 0], [1, 0], [3, 0]], "degenerate"),
    # simple, clockwise
    ([[0, 0], [0, 1], [1, 1], [1, 0]], "clockwise"),
])
def test_polygon_simple_and_non_degenerate_before_orientation(vertices, match):
    """A zero-area bow-tie was refused as "must be counter-clockwise": the polygon is
    checked simple (no edge crosses another) and non-degenerate before its orientation,
    so the message names what is wrong."""
    shape = {"type": "polygon", "vertices": vertices}
    with pytest.raises(SceneError, match=match) as err:
        scene(shape, [[10, 10]])
    if match != "clockwise":
        assert "counter-clockwise" not in str(err.value)


def test_malformed_yaml_keeps_line_and_column(tmp_path):
    """PyYAML's line and column of the problem reach the message (the first line of
    PyYAML's text, "while parsing a block mapping", said neither)."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("workpiece:\n  mass: 1\n  inertia: [1, 2\nfriction: 0.2\n")
    with pytest.raises(SceneError) as err:
        load_scene(bad)
    msg = str(err.value)
    assert "not valid YAML" in msg and str(bad) in msg
    assert "line 4, column 9" in msg and "expected ',' or ']'" in msg, msg
    assert "line 3, column 12" in msg  # where the unclosed sequence starts
    tab = tmp_path / "tab.yaml"
    tab.write_text("friction: 0.2\nfixels:\n\t- [0, 1]\n")
    with pytest.raises(SceneError, match="line 3, column 1"):
        load_scene(tab)


def test_bad_files(tmp_path):
    with pytest.raises(SceneError, match="cannot read"):
        load_scene(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("workpiece: [unclosed")
    with pytest.raises(SceneError, match="not valid YAML"):
        load_scene(bad)
    notmap = tmp_path / "list.yaml"
    notmap.write_text("- 1\n- 2\n")
    with pytest.raises(SceneError, match="must be a mapping"):
        load_scene(notmap)


def test_contact_tolerance_never_below_coordinate_resolution():
    """Far from the origin a double cannot resolve 1e-9 m: the applied tolerance grows to
    8 ulp of the largest coordinate, identically in float and exact arithmetic."""
    near = load_scene(PAPER_DISC)
    assert near.effective_contact_tolerance == near.contact_tolerance
    far = load_scene({**PAPER_DISC, "workpiece": {**PAPER_DISC["workpiece"],
                                                  "pose": [1e7, 0.0, 0.0]},
                      "fixels": [[1e7, -1.0 - 1.2e-8], [1e7 + 1.001, 0.0]]})
    assert far.effective_contact_tolerance == pytest.approx(8 * math.ulp(1e7 + 1.001))
    assert far.in_contact == (True, False)


@pytest.mark.parametrize("patch,match", [
    ({"fixels": [[1e200, 0.0]]}, "fixel 1"),
    ({"fixels": [[0.0, -1.0], {"position": [2.0, 0.0], "radius": 1e200}]}, "fixel radius"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "pose": [1e200, 0.0, 0.0]}}, "pose"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "pose": [0.0, 0.0, 1e200]}}, "theta"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "com": [0.0, 1e200]}}, "com"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "mass": 1e200}}, "mass"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "inertia": 1e-200}}, "inertia"),
    ({"workpiece": {**PAPER_DISC["workpiece"],
                    "shape": {"type": "disc", "radius": 1e200}}}, "radius"),
    ({"workpiece": {**PAPER_DISC["workpiece"], "shape": {
        "type": "polygon", "vertices": [[-1, -1], [1e200, -1], [1, 1], [-1, 1]]}}}, "vertex"),
    ({"friction": 1e200}, "friction"),
    ({"contact_tolerance": 1e200}, "contact_tolerance"),
])
def test_absurd_but_finite_numbers_are_refused_with_the_limit(patch, match):
    """Finite values that would overflow later (1e200 m) are refused at the scene, with
    the value and the limit; on a polygon a 1e200 fixel used to raise OverflowError."""
    with pytest.raises(SceneError, match=match) as info:
        load_scene({**PAPER_DISC, **patch})
    assert "1e+" in str(info.value) or "1e-" in str(info.value)


def test_polygon_with_a_far_fixel_is_a_scene_error_not_an_overflow():
    square = {**PAPER_DISC["workpiece"], "shape": {
        "type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}}
    for patch in ({"fixels": [[1e200, 0.0]]},
                  {"workpiece": {**square, "pose": [1e200, 0.0, 0.0]}}):
        with pytest.raises(SceneError):
            load_scene({**PAPER_DISC, "workpiece": square, **patch})
    far = load_scene({**PAPER_DISC, "workpiece": {**square, "pose": [1e9 - 6.0, 0.0, 0.0]},
                      "fixels": [[1e9 - 3.0, 0.0]]})  # at the limit: accepted
    assert far.gaps[0] == pytest.approx(2.0)
def test_fixels_on_one_edge_share_their_tangential_row_exactly():
    """Contacts on one straight edge take n, t and r x t from the edge, so their
    tangential Jacobian columns are identical (bitwise, and exactly equal in rationals),
    whatever the edge's angle; the moment arm r x n still differs along the edge."""
    from helpers.strategies import shared_edge_scene

    from wrenchcone_ros.core.dynamics import nondimensional

    rng = np.random.default_rng(8)
    for _ in range(20):
        gen = shared_edge_scene(rng)
        s = load_scene(gen.data)
        edge = gen.notes["shared_edge"]
        on = [c for c in s.contacts if c.edge == edge and c.in_contact]
        assert len(on) == gen.notes["n_shared"]
        for exact in (False, True):
            J = nondimensional(s, exact)[0]
            n = s.n_fixels
            cols = {tuple(J[:, n + c.index]) for c in on}
            assert len(cols) == 1  # t_x, t_y and r_t / L identical
            assert len({J[2, c.index] for c in on}) == len(on)  # r_n differs
        frames = s.contact_frames(EXACT)
        assert len({(f.r_t, tuple(f.t)) for f in frames if f.edge == edge and f.in_contact}) == 1


def test_edge_index_of_contacts():
    s = scene(SQUARE, [[0.2, -1.0], [-0.5, -1.0], [1.0, 0.3], [1.2, 1.2]])
    assert [c.edge for c in s.contacts] == [0, 0, 1, None]
    assert s.contacts[3].vertex
    assert default_scene().contacts[0].edge is None  # a disc has no edges


def test_a_workpiece_outside_the_verified_stiffness_range_warns_once_with_the_range():
    """I / (m L^2) outside the range the error study verifies: one warning naming the
    value and the range; inside it, none. The ratio is the scene's own arithmetic,
    checked here by hand (a disc of radius 0.1 m about its centre: L = 0.1 m)."""
    import warnings

    from wrenchcone_ros.core.geometry import Disc, UnverifiedRangeWarning, Workpiece
    from wrenchcone_ros.core.tolerances import VERIFIED_INERTIA_RATIO

    lo, hi = VERIFIED_INERTIA_RATIO
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        ok = Workpiece(mass=2.0, inertia=0.01, shape=Disc(0.1))  # 0.01 / (2 * 0.01) = 0.5
        heavy = Workpiece(mass=1e5, inertia=0.01, shape=Disc(0.1))  # 1e-5
    assert ok.inertia_ratio == pytest.approx(0.5) and ok.numerics_caveat is None
    assert heavy.inertia_ratio == pytest.approx(1e-5)
    [w] = seen
    assert w.category is UnverifiedRangeWarning
    assert "1e-05" in str(w.message) and f"[{lo:g}, {hi:g}]" in str(w.message)


@pytest.mark.parametrize("mass, inertia", [(1.0, 1e-10), (1e-7, 1.0)])
def test_a_workpiece_outside_the_accepted_stiffness_range_is_refused_with_the_range(
        mass, inertia):
    """I / (m L^2) outside ACCEPTED_INERTIA_RATIO (the range both studies cover to its
    edges) is refused, naming the value, the range and what L is. A disc of radius
    1 m about its centre: L = 1 m, so the ratio is inertia / mass (1e-10, 1e7)."""
    from wrenchcone_ros.core.geometry import Disc, SceneError, Workpiece
    from wrenchcone_ros.core.tolerances import ACCEPTED_INERTIA_RATIO

    lo, hi = ACCEPTED_INERTIA_RATIO
    with pytest.raises(SceneError) as err:
        Workpiece(mass=mass, inertia=inertia, shape=Disc(1.0))
    text = str(err.value)
    assert f"{inertia / mass:.3g}" in text and f"[{lo:g}, {hi:g}]" in text and "L = 1 m" in text
    # the edges themselves are accepted (as the studies' edge cases)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert Workpiece(mass=1.0, inertia=lo, shape=Disc(1.0)).inertia_ratio == lo
        assert Workpiece(mass=1.0, inertia=hi, shape=Disc(1.0)).inertia_ratio == hi
