# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The simulation (core/simulate.py): the scene in pymunk, the readout, and the engine
against the cones: the paper's worked example, the pawl's arr interval, random scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest

pymunk = pytest.importorskip("pymunk")

from helpers.strategies import random_polygon, random_scene  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    consistent_modes,
    default_scene,
    force_directions,
    load_scene,
)
from wrenchcone_ros.core.simulate import (  # noqa: E402
    DEFAULT_TILT,
    Actuator,
    EngineSettings,
    Simulation,
    build_space,
    convex_pieces,
    initial_mode,
)
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND  # noqa: E402

PAWL = "examples/pawl_polygon.yaml"


def _area(pts) -> float:
    """Shoelace area (m^2) of a CCW polygon."""
    n = len(pts)
    return 0.5 * sum(pts[k][0] * pts[(k + 1) % n][1] - pts[(k + 1) % n][0] * pts[k][1]
                     for k in range(n))


def _convex(pts) -> bool:
    n = len(pts)
    return all((pts[k][0] - pts[k - 1][0]) * (pts[(k + 1) % n][1] - pts[k][1])
               - (pts[k][1] - pts[k - 1][1]) * (pts[(k + 1) % n][0] - pts[k][0]) >= -1e-15
               for k in range(n))


@pytest.mark.parametrize("seed", range(20))
def test_convex_pieces_cover_the_polygon(seed):
    """Pieces are convex, use only the polygon's vertices and their areas add up to the
    polygon's (shoelace): a partition, no boundary edge split."""
    rng = np.random.default_rng(seed)
    verts = [tuple(v) for v in random_polygon(rng, convex=False).tolist()]
    pieces = convex_pieces(verts)
    assert all(_convex(p) for p in pieces)
    assert all(v in verts for p in pieces for v in p)
    assert sum(_area(p) for p in pieces) == pytest.approx(_area(verts), rel=1e-12)


def test_pawl_is_two_pieces():
    scene = load_scene(PAWL)
    pieces = convex_pieces(scene.workpiece.shape.vertices)
    assert len(pieces) == 2
    assert sorted(round(_area(p), 9) for p in pieces) == sorted(
        [round(0.045 * 0.01, 9), round(0.015 * 0.035, 9)])


@pytest.mark.parametrize("seed", range(15))
def test_space_is_the_scene(seed):
    """Mass, inertia about the com, pose and every fixel's gap as the scene has them."""
    rng = np.random.default_rng(100 + seed)
    scene = load_scene(random_scene(rng).data)
    sp = build_space(scene, 1.0)
    assert sp.body.mass == scene.workpiece.mass
    assert sp.body.moment == pytest.approx(scene.workpiece.inertia, rel=1e-12)
    assert tuple(sp.body.center_of_gravity) == tuple(scene.workpiece.com)
    sim = Simulation(scene, Actuator(), 0.0)
    assert sim.pose == pytest.approx(scene.pose, abs=1e-12)
    L = scene.length_scale
    assert sim.gaps() == pytest.approx(list(scene.gaps), abs=1e-9 * L)
    for i in range(scene.n_fixels):
        assert sp.fixels[i].friction == scene.mu(i)


def test_engine_settings_scale_the_step_the_iterations_and_the_slop():
    """EngineSettings' factors reach pymunk: the space's iterations and collision slop,
    the simulation's step; the defaults are 40 iterations, SIM_TIME_STEP T and SIM_SLOP
    L; a bad factor is refused with what is allowed."""
    from wrenchcone_ros.core.tolerances import SIM_SLOP, SIM_TIME_STEP

    scene = load_scene(PAWL)
    L = scene.length_scale
    base = Simulation(scene, Actuator(), -math.pi / 2)
    T = base.sp.time_scale
    # T = sqrt(m L / |F|), |F| = m g sin(tilt): computed here from the scene alone
    assert T == pytest.approx(math.sqrt(L / (9.80665 * math.sin(DEFAULT_TILT))), rel=1e-12)
    assert base.dt == pytest.approx(SIM_TIME_STEP * T, rel=1e-12)
    assert base.sp.space.iterations == 40
    assert base.sp.space.collision_slop == pytest.approx(SIM_SLOP * L, rel=1e-12)
    other = Simulation(scene, Actuator(), -math.pi / 2,
                       engine=EngineSettings(step=0.25, iterations=4.0, slop=0.5))
    assert other.dt == pytest.approx(0.25 * SIM_TIME_STEP * T, rel=1e-12)
    assert other.sp.space.iterations == 160
    assert other.sp.space.collision_slop == pytest.approx(0.5 * SIM_SLOP * L, rel=1e-12)
    assert EngineSettings(iterations=0.001).label == "iterations x0.001"
    assert build_space(scene, 1.0, engine=EngineSettings(iterations=0.001)).space.iterations == 1
    for bad in (0.0, -1.0, float("nan"), float("inf"), True, "2"):
        with pytest.raises(ValueError, match="must be a factor > 0"):
            EngineSettings(step=bad)


def test_actuator_errors():
    with pytest.raises(ValueError, match="tilt' or 'spring"):
        Actuator("push")
    with pytest.raises(ValueError, match="hook point"):
        Actuator("spring")
    with pytest.raises(ValueError, match=r"\(0, pi/2\]"):
        Actuator(tilt=2.0)
    with pytest.raises(ValueError, match="spring:X,Y"):
        Actuator.parse("spring:1")
    assert Actuator.parse("spring:0.1,0.2").point == (0.1, 0.2)


# --- the paper's worked example ---------------------------------------------------------
def test_paper_example_na_interval_in_simulation():
    """The paper's disc, a force at its top (0, 1): inside the 'na' interval the engine
    rolls the disc on fixel 1 towards fixel 2 ('na'); just outside it does not."""
    scene = default_scene()
    spring = Actuator("spring", point=(0.0, 1.0))
    (iv,) = force_directions(scene, "na", point=(0.0, 1.0))
    for phi in (iv.best, iv.lo + 0.01, iv.hi - 0.01):
        assert initial_mode(scene, phi, spring) == "na", math.degrees(phi)
    for phi in (iv.lo - 0.1, iv.hi + 0.1):
        assert initial_mode(scene, phi, spring) != "na", math.degrees(phi)


# --- the pawl's arr interval --------------------------------------------------------------
def _slide(phi: float, duration: float = 0.6):
    scene = load_scene(PAWL)
    sim = Simulation(scene, Actuator(), phi)
    band = SIM_CONTACT_BAND * sim.sp.length_scale

    def stop(s):
        return "fixel 1" if s.gaps()[0] <= band else None

    return scene, sim.run(duration, stop, record_every=10)


@pytest.mark.parametrize("deg", [-70.0, -40.0, -10.0])
def test_pawl_inside_arr_slides_right_to_fixel_1(deg):
    (iv,) = force_directions(load_scene(PAWL), "arr")
    assert iv.contains(math.radians(deg))
    scene, traj = _slide(math.radians(deg))
    assert traj.reason == "fixel 1"
    moving = [f.letters for f in traj.frames[1:-1]]
    assert moving and all(m == "arr" for m in moving), moving
    x, y, th = traj.frames[-1].pose
    assert x == pytest.approx(0.104, abs=2e-5) and y == pytest.approx(0.2, abs=1e-5)
    assert abs(th) < 1e-4


@pytest.mark.parametrize("deg, mode", [(-80.0, "snn"), (-100.0, "sns"), (10.0, "ass")])
def test_pawl_outside_arr_sticks_or_lifts(deg, mode):
    (iv,) = force_directions(load_scene(PAWL), "arr")
    assert not iv.contains(math.radians(deg))
    scene, traj = _slide(math.radians(deg), duration=0.2)
    assert initial_mode(scene, math.radians(deg)) == mode
    if mode == "ass":  # lifts off both pins
        assert min(traj.frames[-1].gaps[1:]) > 1e-4
    else:  # sticks (snn) or tips over pin 3 (sns): fixel 1 never reached
        assert traj.reason == "time"
    if mode == "snn":
        assert traj.frames[-1].pose == pytest.approx(scene.pose, abs=1e-6)


# --- the engine against consistent_modes on random scenes --------------------------------
#: Compare only where one mode is predicted, with at least this margin.
MARGIN_THRESHOLD = 0.05


def test_initial_mode_agrees_with_consistent_modes_on_random_scenes():
    """Where exactly one mode is consistent with a random pull at the com, with margin
    >= MARGIN_THRESHOLD, the engine's letters at t = 0 are that mode in at least 95 % of
    the scenes (benchmarks/plan_cost.py measures it on more; docs/planning.md explains
    the disagreements)."""
    rng = np.random.default_rng(1)
    compared = agree = 0
    for _ in range(120):
        scene = load_scene(random_scene(rng).data)
        phi = float(rng.uniform(-math.pi, math.pi))
        ms = consistent_modes(scene, (math.cos(phi), math.sin(phi), 0.0))
        if len(ms) != 1 or ms[0].margin < MARGIN_THRESHOLD:
            continue
        compared += 1
        agree += initial_mode(scene, phi) == ms[0].mode
    assert compared >= 60
    assert agree / compared >= 0.95, (agree, compared)


def _hex(values) -> list[str]:
    return [float(v).hex() for v in values]


@pytest.mark.parametrize("deg", [-60.0, 10.0, -120.0])
def test_fast_queries_read_what_pymunks_public_calls_read(deg):
    """The gaps, closest points, normals and impulses that the simulation reads through
    Chipmunk directly (one reused query struct, its own arbiter callback) are the ones
    of pymunk's public calls (Shape.point_query, Body.each_arbiter), bit for bit, at
    every step of a run that makes and breaks contacts with a part of two pieces."""
    scene = load_scene("examples/pawl_seating.yaml")
    sim = Simulation(scene, Actuator(), math.radians(deg))
    assert sim._query is not None and sim._arbiters is not None
    impacts = 0
    for _ in range(300):
        sim.step()
        assert _hex(sim._impulses) == _hex(sim._impulses_reference())
        assert _hex(sim.gaps()) == _hex(sim._gaps_reference())
        for fx in scene.fixels:
            ref = min((s.point_query(fx.position) for s in sim.sp.shapes),
                      key=lambda q: q.distance)
            d, p, n = sim._query.closest(fx.position)
            assert _hex([d, *p, *n]) == _hex([ref.distance, *ref.point, *(-ref.gradient)])
        impacts += any(sim._impulses)
    assert impacts > 0  # the arbiters were read, not only empty lists


@pytest.mark.parametrize("seed", range(6))
def test_fast_point_queries_equal_point_query_inside_on_and_outside(seed):
    """Random non-convex parts (several convex pieces): the distance and the closest
    point of the nearest piece at random points inside, outside and on the boundary."""
    rng = np.random.default_rng(300 + seed)
    scene = load_scene(random_scene(rng, shape="nonconvex").data)
    sim = Simulation(scene, Actuator(), 0.0)
    verts = np.asarray(scene.workpiece.shape.vertices, float)
    c, s = math.cos(scene.pose[2]), math.sin(scene.pose[2])
    world = verts @ np.array([[c, s], [-s, c]]) + np.asarray(scene.pose[:2])
    lo, hi = world.min(axis=0), world.max(axis=0)
    points = [tuple(map(float, lo + (hi - lo) * rng.uniform(-0.2, 1.2, 2)))
              for _ in range(200)]
    points += [tuple(map(float, v)) for v in world]  # on the boundary
    for p in points:
        infos = [sh.point_query(p) for sh in sim.sp.shapes]
        assert sim._query.distance(p).hex() == min(q.distance for q in infos).hex()
        ref = min(infos, key=lambda q: q.distance)
        d, point, normal = sim._query.closest(p)
        assert _hex([d, *point]) == _hex([ref.distance, *ref.point])
        assert [v.hex() for v in normal] == [(-v).hex() for v in ref.gradient]


@pytest.mark.parametrize("deg, every", [(-60.0, 5), (10.0, 1), (-120.0, 7)])
def test_run_poses_are_the_poses_of_run(deg, every):
    """run_poses records the poses of run's frames (same instants, same doubles), and
    stops where run stops, for the same reason."""
    scene = load_scene("examples/pawl_seating.yaml")
    band = SIM_CONTACT_BAND * scene.length_scale

    def stop(s):
        g = s.gaps()
        return "reached" if g[0] <= band else ("lost" if g[1] > band else None)

    a = Simulation(scene, Actuator(), math.radians(deg))
    b = Simulation(scene, Actuator(), math.radians(deg))
    traj = a.run(3.0 * a.sp.time_scale, stop, record_every=every)
    poses, reason = b.run_poses(3.0 * b.sp.time_scale, stop, record_every=every)
    assert reason == traj.reason and len(poses) == len(traj.frames) > 2
    assert [_hex(p) for p in poses] == [_hex(f.pose) for f in traj.frames]
    assert a.t == b.t
