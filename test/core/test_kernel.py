# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The compiled kernel (kernel.py) against the numpy reference it transcribes.

* its 3-D conversions == cone3d's on every input family of test/helpers/cone3d_cases.py (cone3d is
  itself checked against exact cddlib there), both raising / declining together;
* its ``nearly_parallel`` == constraints.nearly_parallel;
* whole cones: the kernel engine == the numpy reference engine on every scene family of
  the error-vs-runtime study (test/helpers/families.py FAMILIES, the new shared-edge family
  included), and it declines exactly the modes the reference does not take in float;
* its contact geometry == Scene.contact_frames, and the J_hat^T rows it computes with it
  == dynamics.float_rows (bit for bit); a batch cone's F (given by the engine) == F_hat
  times the scale row, the doubles Cone.F computes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from helpers.cones import assert_same_cone
from helpers.cone3d_cases import FAMILIES as CONE3_FAMILIES
from helpers.cone3d_cases import span_distance

from wrenchcone_ros.core import cone3d, engines, load_scene, planar, wrench_cones
from wrenchcone_ros.core.constraints import nearly_parallel
from wrenchcone_ros.core.geometry import SceneError

kernel = pytest.importorskip("wrenchcone_ros.core.kernel", reason="numba not installed")

from helpers.families import FAMILIES  # noqa: E402

SEED = 20261123
CASES = 150


def _same3(ref: cone3d.Cone3, got: tuple) -> None:
    F, E, R, L = got
    for a, b in ((ref.F, F), (ref.rays, R)):
        assert a.shape == b.shape
        if a.size:
            p, q = np.sort(np.round(a, 9), axis=0), np.sort(np.round(b, 9), axis=0)
            assert np.abs(p - q).max() <= 2e-9
    for a, b in ((ref.E, E), (ref.lines, L)):
        assert a.shape == b.shape and span_distance(a, b) <= 1e-9


def _both(ref_fn, kern_fn, a, b):
    try:
        ref = ref_fn(a, b)
    except cone3d.Cone3Error:
        ref = None
    try:
        got = kern_fn(np.asarray(a, dtype=float).reshape(-1, 3),
                      np.asarray(b, dtype=float).reshape(-1, 3))
    except kernel.KernelCone3Error:
        got = None
    return ref, got


@pytest.mark.parametrize("family", sorted(CONE3_FAMILIES))
def test_conversions_equal_cone3d(family):
    rng = np.random.default_rng(SEED)
    for _ in range(CASES):
        R, L = CONE3_FAMILIES[family](rng)
        for ref_fn, kern_fn in ((cone3d.from_generators, kernel.from_generators),
                                (cone3d.from_inequalities, kernel.from_inequalities)):
            ref, got = _both(ref_fn, kern_fn, R, L)
            assert (ref is None) == (got is None)
            if ref is not None:
                _same3(ref, got)


def test_nearly_parallel_equals_reference():
    rng = np.random.default_rng(SEED)
    for k in range(400):
        rows = rng.normal(size=(int(rng.integers(0, 6)), 3))
        if rows.shape[0] >= 2:
            angle = 10.0 ** -rng.uniform(3, 12)
            w = rng.normal(size=3)
            rows[1] = np.cos(angle) * rows[0] + np.sin(angle) * np.linalg.norm(rows[0]) * (
                w / np.linalg.norm(w))
            if k % 3 == 0:
                rows[1] = rows[0] * (-2.0 if k % 2 else 3.0)  # exactly parallel
        assert kernel.nearly_parallel(rows, 1e-6) == nearly_parallel(rows)


@pytest.mark.slow
@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_kernel_equals_reference_on_every_family(family):
    rng = np.random.default_rng(SEED)
    cases = [c for c in FAMILIES[family](rng, 2) if not c.rejected]
    assert cases
    for case in cases[:24]:
        try:
            scene = load_scene(case.data)
        except SceneError:
            continue
        before = dict(planar.PLANAR_FALLBACKS)
        declined = engines.KERNEL_STATS["declined"]
        got = wrench_cones(scene, case.modes, engine="kernel")
        float_path = planar.PLANAR_FALLBACKS["exact_ill_conditioned"] == before[
            "exact_ill_conditioned"] and planar.PLANAR_FALLBACKS["exact_fallbacks"] == before[
            "exact_fallbacks"]
        # the kernel declines only where the reference leaves the float path
        assert float_path == (engines.KERNEL_STATS["declined"] == declined)
        ref = wrench_cones(load_scene(case.data), case.modes, engine="numpy")
        for a, b in zip(got, ref):
            assert_same_cone(a, b)


# --- contact geometry (kernel.contact_geometry against Scene.contact_frames) -----------
def _reference_arrays(scene):
    """The reference's float frames as arrays, or the SceneError it raises."""
    from wrenchcone_ros.core.numbers import FLOAT
    from wrenchcone_ros.core.geometry import ContactArrays

    try:
        return ContactArrays.of(scene.contact_frames(FLOAT))
    except SceneError as exc:
        return exc


def _kernel_arrays(scene):
    """kernel.contact_geometry on a scene's inputs: ContactArrays, or "refused"."""
    out = engines.get_engine("kernel").contact_arrays(scene)
    return "refused" if out is None else out


def _assert_same_geometry(ref, got) -> None:
    if isinstance(ref, SceneError):
        assert got == "refused", f"the reference refuses ({ref}); the kernel does not"
        return
    assert got != "refused", "the kernel refuses a scene the reference accepts"
    for name in ("p", "gap", "n", "r_n", "r_t", "in_contact", "vertex", "edge"):
        a, b = getattr(ref, name), getattr(got, name)
        assert a.shape == b.shape and a.dtype == b.dtype, name
        assert np.array_equal(a, b), f"{name}: {a} != {b} (must be the same doubles)"


def _moved(scene, rng):
    """The scene at a random pose near its own, and with a fixel moved onto a polygon
    vertex, into the workpiece or onto the disc's centre now and then: cases the reference
    refuses, besides the touching and free fixels of the family."""
    x, y, th = scene.pose
    L = scene.length_scale
    out = [_unvalidated(scene, pose=(x + L * rng.normal() * 1e-9, y,
                                     th + rng.normal() * 1e-9))]
    k = int(rng.integers(scene.n_fixels))
    shape = scene.workpiece.shape
    c, s = math.cos(th), math.sin(th)
    if hasattr(shape, "vertices"):
        vx, vy = shape.vertices[int(rng.integers(len(shape.vertices)))]
        targets = [(vx, vy), (0.5 * vx, 0.5 * vy)]
    else:
        targets = [(0.0, 0.0), (0.5 * shape.radius, 0.0)]
    for wx, wy in targets:  # workpiece frame -> world
        pos = [list(f.position) for f in scene.fixels]
        pos[k] = [x + c * wx - s * wy, y + s * wx + c * wy]
        out.append(_unvalidated(scene, positions=pos))
    return out


def _unvalidated(scene, pose=None, positions=None):
    """The scene with another pose or fixels, not validated (the constructor would
    refuse some: their geometry is what is compared)."""
    from dataclasses import fields

    from wrenchcone_ros.core.geometry import Fixel
    from wrenchcone_ros.core.scene import Scene

    new = object.__new__(Scene)
    new.__dict__.update({f.name: getattr(scene, f.name) for f in fields(Scene)})
    if pose is not None:
        new.__dict__["pose"] = tuple(pose)
    if positions is not None:
        new.__dict__["fixels"] = tuple(Fixel(tuple(p)) for p in positions)
    return new


@pytest.mark.slow
@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_contact_geometry_equals_the_reference(family):
    """The same doubles as Scene.contact_frames (float) on every scene family, and the
    same refusals (the reference words them): so the contact state never depends on
    the engine."""
    rng = np.random.default_rng(SEED)
    compared = refused = 0
    for case in FAMILIES[family](rng, 6):
        if case.rejected:
            continue
        base = load_scene(case.data)
        for scene in [base, *_moved(base, rng)]:
            ref = _reference_arrays(scene)
            _assert_same_geometry(ref, _kernel_arrays(scene))
            compared += 1
            refused += isinstance(ref, SceneError)
    assert compared >= 4


@pytest.mark.slow
def test_scene_geometry_is_the_same_on_either_engine():
    """Scene.contact_arrays / contacts / in_contact / gaps / float_rows with the kernel
    engine == with the numpy engine, and the same SceneError text for a refused scene."""
    from wrenchcone_ros.core.dynamics import float_rows

    rng = np.random.default_rng(SEED + 1)
    cases = [c for fam in ("random", "gaps", "shared_edge", "offset")
             for c in FAMILIES[fam](rng, 4) if not c.rejected]
    for case in cases:
        got = {}
        for name in ("numpy", "kernel"):
            with engines.using_engine(name):
                scene = load_scene(case.data)
                moved = scene.with_pose(*scene.pose)
            got[name] = (scene.in_contact, scene.gaps, float_rows(scene)[0],
                           [(f.p.tolist(), f.gap, f.n.tolist(), f.t.tolist(), f.r_n, f.r_t,
                             f.in_contact, f.vertex, f.edge) for f in scene.contacts],
                           moved == scene, moved.contact_arrays.gap.tolist())
        a, b = got["numpy"], got["kernel"]
        assert a[0] == b[0] and a[1] == b[1] and np.array_equal(a[2], b[2])
        assert a[3] == b[3] and a[4] and b[4] and a[5] == b[5]
    for name in ("numpy", "kernel"):
        with engines.using_engine(name), pytest.raises(SceneError, match=r"fixel 2 .* penetrates"):
            load_scene({"workpiece": {"mass": 1, "inertia": 1,
                                      "shape": {"type": "disc", "radius": 1}},
                        "friction": 0.5, "fixels": [[0, -1], [0.5, 0]]})


_SHAPES = {
    "disc": {"type": "disc", "radius": 0.7},
    "square": {"type": "polygon", "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]},
    "notch": {"type": "polygon",  # non-convex: an L
              "vertices": [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]},
    "sliver": {"type": "polygon", "vertices": [[0, 0], [1e-3, 0], [0, 3.0]]},
}


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(shape=st.sampled_from(sorted(_SHAPES)),
       pose=st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(-4.0, 4.0)),
       fixels=st.lists(st.tuples(st.floats(0.0, 1.0), st.integers(0, 5),
                                 st.sampled_from([0.0, 1e-10, -1e-10, 1e-9, -1e-9, 2e-9,
                                                  -2e-9, 1e-3, -1e-3, 0.3]),
                                 st.sampled_from([0.0, 0.0, 0.05])),
                       min_size=1, max_size=5))
def test_contact_geometry_property(shape, pose, fixels):
    """Any pose, fixels on, near (within and beyond the contact tolerance, either side)
    and off the boundary, on edges and at vertices, points and pins: the kernel gives
    the reference's doubles, or refuses exactly where the reference raises."""
    base = load_scene({"workpiece": {"mass": 1.0, "inertia": 0.1,
                                     "shape": _SHAPES[shape], "com": [0.2, 0.1]},
                       "friction": 0.5, "fixels": [[50.0, 50.0]]})
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    positions, radii = [], []
    for t, k, gap, radius in fixels:
        if shape == "disc":  # boundary point at angle 2 pi t, outward normal
            a = 2 * math.pi * t
            ox, oy = math.cos(a), math.sin(a)
            bx, by, nx, ny = 0.7 * ox, 0.7 * oy, ox, oy
        else:
            verts = _SHAPES[shape]["vertices"]
            (x1, y1), (x2, y2) = verts[k % len(verts)], verts[(k + 1) % len(verts)]
            ex, ey = x2 - x1, y2 - y1
            le = math.hypot(ex, ey)
            bx, by, nx, ny = x1 + t * ex, y1 + t * ey, ey / le, -ex / le
        d = gap + radius
        wx, wy = bx + d * nx, by + d * ny  # workpiece frame -> world
        positions.append((x + c * wx - s * wy, y + s * wx + c * wy))
        radii.append(radius)
    scene = _unvalidated(base, pose=pose, positions=positions)
    from wrenchcone_ros.core.geometry import Fixel

    scene.__dict__["fixels"] = tuple(Fixel(p, r) for p, r in zip(positions, radii))
    _assert_same_geometry(_reference_arrays(scene), _kernel_arrays(scene))


def test_kernel_pose_rows_are_float_rows():
    """J_hat^T as the kernel's contact geometry computes it (kept for pose_arrays) is
    float_rows' doubles, at a scene's pose, a new Scene there and a moved pose
    (Scene.with_pose)."""
    from wrenchcone_ros.core.dynamics import float_rows
    from wrenchcone_ros.core.engines import pose_arrays

    from helpers.strategies import random_scene, shared_edge_scene

    rng = np.random.default_rng(SEED + 2)
    compared = 0
    with engines.using_engine("kernel"):
        for shape in ("disc", "convex", "nonconvex", "shared edge"):
            for _ in range(4):
                data = (shared_edge_scene(rng) if shape == "shared edge"
                        else random_scene(rng, shape=shape)).data
                base = load_scene(data)
                x, y, th = base.pose
                scenes = [base, base.with_pose(x, y, th)]
                try:  # a new pose: some fixels may penetrate there
                    scenes.append(base.with_pose(x + 1e-3, y - 2e-3, th + 0.01))
                except SceneError:
                    pass
                for scene in scenes:
                    got = pose_arrays(scene)
                    scene.__dict__.pop("_pose_rows")  # float_rows from the frames
                    ref = float_rows(scene)
                    assert np.array_equal(got[0], ref[0]) and got[0].dtype == ref[0].dtype
                    assert got[1] == ref[1] and np.array_equal(got[2], ref[2])
                    assert got[0].flags.c_contiguous and got[2].flags.writeable
                    compared += 1
    assert compared >= 32


def test_batch_cones_carry_their_si_rows():
    """A batch cone's F (given by the engine) is F_hat * [1, 1, 1/L], the doubles the
    lazy Cone.F computes; an infeasible mode's F is empty, its closure's given too."""
    from dataclasses import fields

    from wrenchcone_ros.core.cones import Cone

    scene = load_scene({"workpiece": {"mass": 1.0, "inertia": 0.2, "com": [0.05, -0.02],
                                      "shape": {"type": "polygon",
                                                "vertices": [[-0.5, -0.5], [0.5, -0.5],
                                                             [0.5, 0.5], [-0.5, 0.5]]}},
                        "friction": 0.4,
                        "fixels": [[-0.2, -0.5], [0.3, -0.5], [0.5, 0.1], [-0.5, 0.2]]})
    modes = list(engines.batch_plan(("****",), scene.in_contact).concrete)
    cones = wrench_cones(scene, modes, engine="kernel")
    assert any(not c.feasible for c in cones) and any(c.feasible for c in cones)
    for c in cones:
        assert set(f.name for f in fields(Cone)) <= set(c.__dict__)
        for x in (c, c.closure) if not c.feasible else (c,):
            s = np.array([1.0, 1.0, 1.0 / x.length_scale])
            assert np.array_equal(x.F, x.F_hat * s) and x.F.shape == x.F_hat.shape
            assert not x.F.flags.writeable and np.array_equal(x.nondimensional([1, 2, 3]),
                                                              np.array([1, 2, 3]) * s)
