# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""plan_seating (core/plan): plans on the pawl, checked against the geometry by hand
(friction-cone edges, where the foot meets the stop) and against the engine."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("pymunk")

from helpers.seating_family import seating_family  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    NOMINAL,
    Uncertainty,
    consistent_modes,
    force_directions,
    load_scene,
)
from wrenchcone_ros.core.plan import (  # noqa: E402
    PlanError,
    candidate_modes,
    execute,
    funnel_checks,
    lifted_scene,
    plan_seating,
    project_pose,
    robust_directions,
    run_models,
    sample_models,
)
from wrenchcone_ros.core.simulate import Actuator, initial_mode  # noqa: E402
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND  # noqa: E402

pytestmark = pytest.mark.slow  # plans searched and checked in the physics engine

SEATING = "examples/pawl_seating.yaml"
TIPPED = "examples/pawl_tipped.yaml"
PAWL = "examples/pawl_polygon.yaml"

#: Where the foot (right edge x + 0.06 m) meets the stop (pin of radius 3 mm at 0.167 m).
SEAT_X = 0.167 - 0.003 - 0.06


@pytest.fixture(scope="module")
def nominal_plan():
    return plan_seating(load_scene(SEATING), [1, 2, 3], "tilt", simulate_runs=False)


def test_the_nominal_plan_is_the_zero_width_uncertainty_plan(nominal_plan):
    """No uncertainty and NOMINAL plan the same segments (modes, intervals, directions,
    margins, poses), with the same guarantee; the physics engine seats the nominal run."""
    plan = plan_seating(load_scene(SEATING), [1, 2, 3], "tilt", uncertainty=NOMINAL,
                        simulate_runs=False)
    assert [s.to_dict() for s in plan.segments] == \
        [s.to_dict() for s in nominal_plan.segments]
    assert (plan.guaranteed, plan.guarantee, plan.missing) == \
        (nominal_plan.guaranteed, nominal_plan.guarantee, nominal_plan.missing)
    # one shape whatever the uncertainty: the zero-width set and every fixel's own mu
    mu = load_scene(SEATING).mu(0)
    assert plan.to_dict()["uncertainty"] == NOMINAL.to_dict()
    assert plan.friction == ((mu, mu),) * 3 == nominal_plan.friction
    assert plan.nominal.success and plan.nominal.matches


def test_pawl_plan_slides_right_then_holds(nominal_plan):
    plan = nominal_plan
    assert plan.feasible, plan.reason
    assert [s.mode for s in plan.segments] == ["arr", "nnn"]
    slide, hold = plan.segments
    # sliding right on both pins: the pull may not be steeper than the friction cone's
    # edge c_n (-mu, 1), i.e. phi >= -atan2(1, mu) (mu = 0.3), nor point upwards (lift-off)
    assert slide.interval.lo == pytest.approx(-math.atan2(1.0, 0.3), abs=1e-7)
    assert slide.interval.hi == pytest.approx(0.0, abs=1e-7)
    assert slide.interval.lo <= slide.direction <= slide.interval.hi
    assert slide.margin > 0
    assert slide.start_pose == (0.096, 0.2, 0.0)
    assert slide.end_pose == pytest.approx((SEAT_X, 0.2, 0.0), abs=1e-9)
    assert slide.event == slide.predicted_event == "fixel 1 reached"
    assert hold.hold and hold.start_pose == hold.end_pose == slide.end_pose
    assert hold.direction == slide.direction  # the same tilt holds the seated pawl
    assert hold.interval.lo <= hold.direction <= hold.interval.hi and hold.margin > 0
    assert plan.nominal.success and plan.nominal.events == (1,) and plan.nominal.matches
    assert plan.success_rate == 1.0  # no uncertainty: the nominal run


def test_pawl_plan_under_friction_uncertainty():
    """mu in [0.2, 0.4] at every pin: the slide's interval shrinks to the edge of the
    largest friction cone, -atan2(1, 0.4); sampled models all seat (few runs here; the
    100-run figures are in benchmarks/plan_cost.py)."""
    plan = plan_seating(load_scene(SEATING), [1, 2, 3], uncertainty=(0.2, 0.4), runs=12,
                        seed=3, workers=2)
    assert plan.feasible
    assert plan.segments[0].interval.lo == pytest.approx(-math.atan2(1.0, 0.4), abs=1e-7)
    assert all(s.margin > 0 for s in plan.segments)
    assert len(plan.runs) == 12 and plan.success_rate == 1.0 and plan.contradicted == 0
    for r in plan.runs:
        assert all(0.2 <= m <= 0.4 for m in r.friction)
    # seeded: run k's model is lo + (hi - lo) U(0, 1) per fixel from default_rng(seed)
    rng = np.random.default_rng(3)
    assert [r.friction for r in plan.runs] == [
        tuple(0.2 + 0.2 * rng.random(3)) for _ in range(12)]


def test_tipped_pawl_needs_a_swing_then_a_slide():
    plan = plan_seating(load_scene(TIPPED), [1, 2, 3], simulate_runs=False)
    assert plan.feasible, plan.reason
    modes = [s.mode for s in plan.segments]
    assert modes[-1] == "nnn" and len(modes) == 3
    swing, slide, _hold = plan.segments
    assert swing.mode[1] == "a" and swing.event == swing.predicted_event == "fixel 2 reached"
    assert slide.mode == "arr" and slide.event == "fixel 1 reached"
    assert swing.direction != slide.direction
    assert slide.end_pose == pytest.approx((SEAT_X, 0.2, 0.0), abs=1e-9)
    assert swing.end_pose[2] == pytest.approx(0.0, abs=1e-9)  # foot flat on both pins
    assert plan.nominal.success and plan.nominal.events == (2, 1)


def test_no_plan_when_the_pawl_tips():
    """The original pawl 12 mm left of its seat: its com lies left of pin 2, every pull
    that slides it right also tips it off pin 3 (cones and engine agree), so no plan
    keeps both pins, no constant tilt seats it in the engine either, and the reason
    names the step."""
    scene = load_scene(PAWL).with_pose(0.092, 0.2, 0.0)
    plan = plan_seating(scene, [1, 2, 3], simulate_runs=False)
    assert not plan.feasible and plan.segments == () and plan.success_rate is None
    assert plan.reason.startswith("step 1:") and "fixel 1" in plan.reason
    assert any(t.startswith("constant directions: none of") for t in plan.tried)
    assert initial_mode(scene, math.radians(-60.0)) == "ars"


def test_the_tipping_pawl_seated_by_one_constant_tilt_is_not_guaranteed():
    """8 mm left of its seat the pawl still tips under every pull that slides it (no
    plan of the cones), but one constant tilt, -72 deg, seats it in the engine (the
    scan of test/helpers/tilt_scan.py: -72 deg seats it, -74 and -70 do not). The
    planner returns that tilt, from the start to the hold, not guaranteed: its moving
    segment starts by tipping ('ars'), so the cones certify no one mode on the way
    (margin 0), and the reason keeps the search's dead end."""
    scene = load_scene(PAWL).with_pose(0.096, 0.2, 0.0)
    plan = plan_seating(scene, [1, 2, 3], simulate_runs=False)
    assert plan.feasible and not plan.guaranteed
    assert [s.mode for s in plan.segments] == ["ars", "nnn"]
    assert {round(math.degrees(s.direction), 6) for s in plan.segments} == {-72.0}
    assert plan.segments[0].margin == 0.0 and not plan.margins_positive
    assert plan.nominal.success and execute(scene, plan).success
    assert "first dead end: step 1: no direction gives a mode" in plan.reason
    assert initial_mode(scene, math.radians(-72.0)) == "ars"


@pytest.mark.heavy
def test_random_family_events_match():
    """Seeded starts of the pawl (x, mu): the plan's predicted contact events are the
    simulated ones, and the nominal run seats the part."""
    rng = np.random.default_rng(7)
    base = load_scene(SEATING)
    for _ in range(3):
        x = float(rng.uniform(0.095, 0.101))
        mu = float(rng.uniform(0.2, 0.5))
        scene = load_scene({**base.to_dict(), "friction": mu}).with_pose(x, 0.2, 0.0)
        plan = plan_seating(scene, [1, 2, 3], simulate_runs=False)
        assert plan.feasible, (x, mu, plan.reason)
        for s in plan.segments:
            assert s.event == s.predicted_event, (x, mu, s)
        assert plan.nominal.success and plan.nominal.matches, (x, mu, plan.nominal)


def test_project_pose_restores_contacts():
    scene = load_scene(SEATING)
    rng = np.random.default_rng(0)
    for _ in range(5):
        d = rng.normal(size=3) * np.array([1e-4, 1e-4, 1e-3])
        pose = project_pose(scene, np.array(scene.pose) + d, [1, 2])
        moved = scene.with_pose(*pose)  # valid: no penetration beyond the tolerance
        assert moved.in_contact[1] and moved.in_contact[2]
        assert abs(pose[2]) < 1e-9  # both pins under one flat edge: theta back to 0


def test_candidate_modes():
    assert candidate_modes((False, True, True), {0, 1, 2}) == [
        "a" + a + b for a in "lrn" for b in "lrn"]
    # a contact that is not a target may separate; some target must be approached
    assert set(candidate_modes((True, False), {1})) == {"la", "ra", "na", "sa"}
    assert candidate_modes((True, False), {0}) == []


def test_robust_directions_hold_in_every_sampled_model():
    """The robust interval of the slide lies inside the nominal interval of every
    sampled friction model (each pin's mu drawn in [0.2, 0.4])."""
    scene = load_scene(SEATING)
    (iv,) = robust_directions(scene, "arr", None, Uncertainty(friction=(0.2, 0.4)))
    rng = np.random.default_rng(5)
    for _ in range(10):
        mus = 0.2 + 0.2 * rng.random(3)
        model = load_scene({**scene.to_dict(), "fixels": [
            {"position": list(f.position), "radius": f.radius, "friction": float(m)}
            for f, m in zip(scene.fixels, mus)]})
        (nom,) = force_directions(model, "arr")
        assert nom.lo <= iv.lo + 1e-9 and iv.hi <= nom.hi + 1e-9


@pytest.mark.parametrize("kwargs, match", [
    ({"target": [0]}, "1..3"),
    ({"target": [4]}, "1..3"),
    ({"target": ["x"]}, "fixel numbers"),
    ({"uncertainty": (0.4, 0.2)}, "uncertainty: friction interval: lo must be <= hi"),
    ({"uncertainty": [(0.2, 0.4)] * 2}, "friction has 2 interval"),
    ({"uncertainty": Uncertainty(normal_error=(0.01, 0.01))}, "normal_error has 2"),
    ({"runs": -1}, "runs"),
    ({"budget": 0}, "budget"),
    ({"budget": float("nan")}, "budget"),
    ({"actuator": "push"}, "tilt' or 'spring"),
])
def test_bad_input(kwargs, match):
    args = {"target": [1, 2, 3], **kwargs}
    with pytest.raises((PlanError, ValueError), match=match):
        plan_seating(load_scene(SEATING), args.pop("target"), **args)


# --- the seat: hold, and funnel (module docstring of core/plan) ------------------------
def _model(scene, mus):
    """The scene with fixel i's friction mus[i]."""
    return load_scene({**scene.to_dict(), "fixels": [
        {"position": list(f.position), "radius": f.radius, "friction": float(m)}
        for f, m in zip(scene.fixels, mus)]})


def test_lifted_scene_by_hand():
    """Lifted off the stop with both pins kept: a slide straight back (x - lift); lifted
    off pin 3 with the stop and pin 2 kept: a turn about the meeting point of their
    normals (x = 0.12, y = 0.205), theta = lift / (0.15 - 0.12) to first order."""
    seated = load_scene(PAWL).with_pose(SEAT_X, 0.2, 0.0)
    lift = 1e-5
    back = lifted_scene(seated, 0, [1, 2], lift)
    assert back.pose == pytest.approx((SEAT_X - lift, 0.2, 0.0), abs=1e-12)
    turned = lifted_scene(seated, 2, [0, 1], lift)
    assert turned.gaps == pytest.approx((0.0, 0.0, lift), abs=1e-12)
    assert turned.pose[2] == pytest.approx(lift / 0.03, rel=1e-3)
    # the turn's centre (0.12, 0.205) stays put to first order: x, y follow the rotation
    # about it up to theta^2 times the part's size (0.06 m)
    c, th = np.array([0.12, 0.205]), turned.pose[2]
    R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    origin = c + R @ (np.array([SEAT_X, 0.2]) - c)
    assert turned.pose[:2] == pytest.approx(tuple(origin), abs=0.06 * th ** 2)
    assert abs(turned.pose[0] - SEAT_X) > 100 * 0.06 * th ** 2  # not merely unmoved
    # with both pins kept the part cannot lift off the flat foot's pin: no such pose
    assert lifted_scene(seated, 1, [0, 2], lift) is not None  # a turn about stop + pin 3
    assert lifted_scene(seated, 2, [1], 0.0) is None  # pin 3 would still touch


@pytest.mark.heavy
def test_the_wedge_the_engine_shows_is_an_equilibrium_of_the_cones():
    """pawl_polygon from its own pose, one friction model of the sampled set: the engine
    ends with the foot against the stop, turned counter-clockwise by a fraction of a
    milliradian, off pin 3. At that pose (stop and pin 2 kept, pin 3 lifted by the gap the
    engine shows) the cones say the part at rest stays there under the plan's tilt: nns is
    the only consistent mode for this model; for the friction set it is possible but not
    certain. Jamming is physics, not an engine artefact."""
    scene = load_scene(PAWL)
    plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)
    mus = (0.3714808553175139, 0.2067171150610929, 0.3459310892859888)
    run = execute(scene, plan, mus)
    assert not run.success and run.events == (1,)
    x, y, th = run.final_pose
    assert 1e-4 < th < 1e-3  # tipped counter-clockwise, about the stop and pin 2
    # the engine's pose overlaps the fixels by up to its collision slop: its gaps in a
    # scene that tolerates that
    band = SIM_CONTACT_BAND * scene.length_scale
    gaps = replace(scene, contact_tolerance=band).with_pose(x, y, th).gaps
    assert gaps[0] <= band and gaps[1] <= band and gaps[2] > band
    seated = scene.with_pose(SEAT_X, 0.2, 0.0)
    wedge = lifted_scene(seated, 2, [0, 1], gaps[2])
    assert wedge.pose[2] == pytest.approx(th, rel=0.2)
    phi = plan.segments[-1].direction
    g = (math.cos(phi), math.sin(phi), 0.0)
    assert [m.mode for m in consistent_modes(_model(wedge, mus), g)] == ["nns"]
    robust = {m.mode: m for m in consistent_modes(
        wedge, g, uncertainty=Uncertainty(friction=(0.2, 0.4)), frame="com")}
    assert robust["nns"].possible and not robust["nns"].certain
    # ... and the plan says its seating is not guaranteed, naming the fixel
    hold = plan.segments[-1]
    assert not plan.guaranteed and hold.margin <= 0 < hold.hold_margin
    assert "seating not guaranteed" in plan.reason and "fixel 3" in plan.reason
    assert all(not c.intervals for c in hold.funnel if c.missing == 3)


def test_the_funnel_of_the_slide_back_is_the_slide_by_hand():
    """The seated pawl lifted off the stop (slid back on both pins): the directions that
    drive it on to the stop for every mu in [0.2, 0.4] are those of arr, [-atan2(1, 0.4),
    0], and those that lift it off both pins towards the stop (ass), (0, pi/2]."""
    seated = load_scene(SEATING).with_pose(SEAT_X, 0.2, 0.0)
    checks = funnel_checks(seated, {0, 1, 2}, None, Uncertainty(friction=(0.2, 0.4)))
    back = [c for c, _f, _iv in checks if c.missing == 1]
    assert len(back) >= 2
    for c in back:
        got = dict(zip(c.modes, c.intervals))
        assert set(got) == {"arr", "ass"}
        assert got["arr"] == pytest.approx((-math.atan2(1.0, 0.4), 0.0), abs=1e-7)
        assert got["ass"] == pytest.approx((0.0, math.pi / 2), abs=1e-7)


def test_the_hold_direction_funnels_in_every_sampled_model():
    """The guaranteed plan of pawl_seating: at every near-seated pose its hold direction
    gives, for sampled friction models, only modes that approach the missing fixel
    (nominal classification of each model: independent of the robust cones)."""
    scene = load_scene(SEATING)
    plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)
    assert plan.guaranteed
    hold = plan.segments[-1]
    phi = hold.direction
    g = (math.cos(phi), math.sin(phi), 0.0)
    rng = np.random.default_rng(2)
    for c in hold.funnel:
        near = scene.with_pose(*c.pose)
        for _ in range(5):
            modes = consistent_modes(_model(near, 0.2 + 0.2 * rng.random(3)), g)
            assert modes and all(m.mode[c.missing - 1] == "a" for m in modes), (c, modes)


def _plans():
    cases = [("pawl_seating", load_scene(SEATING)), ("pawl_tipped", load_scene(TIPPED)),
             ("pawl_polygon", load_scene(PAWL))]
    cases += [(t.name, load_scene(t.scene)) for t in seating_family(6, seed=1)]
    for name, scene in cases:
        plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)
        if plan.guaranteed:  # the Monte Carlo runs only where the acceptance point applies
            models = sample_models(scene, Uncertainty(friction=(0.2, 0.4)), 100, 0)
            plan = replace(plan, runs=tuple(run_models(scene, plan, models, workers=2)))
        yield name, plan


@pytest.mark.heavy
def test_plans_with_positive_margins_seat_in_99_percent_of_models():
    """The acceptance point: for the tutorial scenes and a seeded family of seating
    tasks (test/helpers/seating_family.py), every plan whose every segment has a positive
    worst-case margin seats the part in >= 99 % of 100 sampled models (mu in [0.2, 0.4]
    at every fixel), with the contact events the plan predicts; every plan's predicted
    events are the nominal simulation's. The others are reported (print; their sampled
    runs are in benchmarks/plan_cost.py, the heavy version of this test)."""
    guaranteed, report = 0, []
    for name, plan in _plans():
        margins = [round(s.margin, 4) for s in plan.segments]
        if plan.feasible:  # the predicted contact events are the simulated ones
            assert all(s.event == s.predicted_event for s in plan.segments), name
            assert plan.nominal.matches, (name, plan.nominal)
        if plan.guaranteed:
            guaranteed += 1
            assert len(plan.runs) >= 100
            assert plan.success_rate >= 0.99, (name, margins, plan.success_rate)
            assert plan.contradicted <= 0.01 * len(plan.runs), (name, plan.contradicted)
        else:
            report.append(f"{name}: not guaranteed (margins {margins}), nominal run "
                          f"{'seated' if plan.nominal and plan.nominal.success else 'not seated'}"
                          f": {plan.reason}")
    print("\n".join(report))
    assert guaranteed >= 5  # not vacuous: measured 2 tutorial scenes and 3 variants


def test_the_slide_tilt_maximises_the_worst_case_margin_over_its_whole_path(nominal_plan):
    """The slide's direction is, among 200 directions of its interval, the one whose
    worst margin over the slide's poses (the simulated path put back onto both pins, up
    to the last pose before the stop) is largest, and the printed margin is that worst
    case. The poses come from a fresh simulation of the plan's direction."""
    from wrenchcone_ros.core.plan.segments import (
        margin_function,
        segment_path,
        simulate_segment,
    )

    scene = load_scene(SEATING)
    slide = nominal_plan.segments[0]
    motion = simulate_segment(scene, Actuator(), slide.direction, [1, 2])
    path = segment_path(scene, motion, [1, 2])
    assert motion.before is not None and path[-2][0] > SEAT_X - 1e-3  # up to the stop
    worst = margin_function([scene.with_pose(*p) for p in path[:-1]], "arr", None, None)
    assert slide.margin == pytest.approx(worst(slide.direction), abs=1e-9)
    grid = np.linspace(slide.interval.lo, slide.interval.hi, 200)
    assert worst(slide.direction) >= max(worst(float(p)) for p in grid) - 1e-6


@pytest.mark.heavy
@pytest.mark.slow
def test_pawl_plan_under_mass_com_and_friction_uncertainty():
    """docs/planning.md, section 8: the pawl under mu in [0.2, 0.4], mass in [0.045,
    0.055] kg and the com within 1 mm (the scenario approach at eps = 0.2, beta = 0.01:
    39 models per robust cone; benchmarks/plan_robust.py runs the default eps = 0.05,
    beta = 1e-3, 220 models). The slide keeps its tilt and margin; the seat's funnel
    fails for some model of the com region, so the plan is not guaranteed, and says why;
    every sampled model (each parameter drawn) still seats in the engine."""
    scene = load_scene(SEATING)
    u = Uncertainty(friction=(0.2, 0.4), mass=(0.045, 0.055), com_radius=0.001,
                    epsilon=0.2, beta=0.01)
    assert u.scenario_size() == 39
    plan = plan_seating(scene, [1, 2, 3], uncertainty=u, runs=20, workers=1)
    assert [s.mode for s in plan.segments] == ["arr", "nnn"]
    slide, hold = plan.segments
    assert math.degrees(slide.direction) == pytest.approx(-59.55, abs=0.01)
    assert hold.direction == slide.direction
    assert slide.margin == pytest.approx(0.150, abs=0.001)
    assert math.degrees(slide.accuracy) == pytest.approx(8.65, abs=0.01)
    assert hold.margin == pytest.approx(-0.053, abs=0.001)
    assert not plan.guaranteed
    assert plan.missing == ("a positive worst-case margin in segment(s) 2",)
    assert "scenario (violation probability <= 0.2 with confidence 1 - 0.01)" \
        in plan.guarantee
    assert plan.nominal.success and [r.label for r in plan.checks] == ["nominal"]
    assert len(plan.runs) == 20 and plan.success_rate == 1.0 and plan.contradicted == 0
    assert len({r.model.mass for r in plan.runs}) == 20  # every run its own mass
