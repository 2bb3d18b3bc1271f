# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans whose part reaches its next contact moving (core/plan: the capture test, the
search that uses its own evidence), checked against the engine run independently of the
planner's capture test.

The reproducer: a disc rolled back around its pin onto its nest pin. The quasi-static
margins of the plan (roll on pin 1 approaching pin 2, then hold on both) are positive,
but under the full pull the disc arrives fast enough to roll on over the nest pin and
is lost. A plan is never called guaranteed when its own nominal run does not seat the
part; the search finds one that does (a slower arrival).
"""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

pytest.importorskip("pymunk")

from helpers.arrival_family import arrival_family, disc_scene, pawl_scene  # noqa: E402

from wrenchcone_ros.core.plan import (  # noqa: E402
    capture,
    execute,
    lifted_scene,
    plan_seating,
    search,
)
from wrenchcone_ros.core.plan.results import RunResult  # noqa: E402
from wrenchcone_ros.core.scene_yaml import scene_from_dict  # noqa: E402

pytestmark = pytest.mark.slow  # plans searched and checked in the physics engine

#: The disc of the reproducer: radius 25 mm on pin 1, nest pin 20 mm to its right, the
#: start 10 degrees of arc past the nest, mu 0.3.
DISC = disc_scene(0.025, 0.02, 10.0)


def refuted(scene, plan) -> bool:
    """The plan is called guaranteed, yet its nominal run, made here again (the
    engine, not the planner's record), does not seat the part."""
    return plan.guaranteed and not execute(scene, plan).success


@pytest.fixture(scope="module")
def disc_plan():
    scene = scene_from_dict(DISC)
    return scene, plan_seating(scene, [1, 2], simulate_runs=False, budget=60.0)


def test_disc_rolled_onto_its_nest_is_not_guaranteed_and_refuted(disc_plan):
    scene, plan = disc_plan
    assert not refuted(scene, plan)
    # ... and the search found a plan that seats it, from its own evidence
    assert plan.guaranteed, plan.missing
    assert plan.nominal.success and plan.nominal.matches
    assert [s.mode for s in plan.segments] == ["na", "nn"]


def test_the_fast_arrival_is_refused(disc_plan):
    """The same plan under the full pull (force scale 1): the disc arrives fast, rolls
    over the nest pin and is lost; the capture test refuses it, and the search says so
    in its tried list."""
    scene, plan = disc_plan
    assert plan.segments[0].scale < 1.0
    fast = replace(plan, segments=tuple(replace(s, scale=1.0) for s in plan.segments),
                   checks=())
    run = execute(scene, fast)
    assert not run.success
    checks = capture(scene, fast, None)
    assert not all(r.seats_as_planned for r in checks)
    assert not replace(fast, checks=checks).guaranteed
    assert any("capture at the contact events" in t for t in plan.tried)


def test_a_mutated_capture_test_is_caught(monkeypatch):
    """Mutation: a capture test that always passes (the quasi-static margins alone, as
    before) makes the disc's first candidate, the fast arrival, guaranteed, and the
    independent check above catches it."""
    def always(scene, plan, uncertainty, should_stop=None, engines=()):
        return (RunResult(tuple(scene.mu(i) for i in range(scene.n_fixels)), True,
                          tuple(plan.segments[0].reached), True, tuple(scene.pose),
                          label="nominal"),)
    monkeypatch.setattr(search, "capture", always)
    scene = scene_from_dict(DISC)
    plan = plan_seating(scene, [1, 2], simulate_runs=False)
    assert refuted(scene, plan)


def test_guaranteed_plans_seat_at_the_edges_of_the_impact_assumptions(disc_plan):
    """The guarantee assumes inelastic impacts (restitution 0, the engine's contact
    model). Independent check: the guaranteed disc plan, run with restitution 0.05 and
    with mu at each end of [0.2, 0.4] (not only the planner's nominal 0.3) still seats."""
    scene, plan = disc_plan
    for e in (0.0, 0.05):
        for mu in (0.2, 0.4):
            run = execute(scene, plan, [mu, mu], restitution=e)
            assert run.success, (e, mu, run.reason)


#: The impacts' restitution at the edge of what the guarantee assumes (0: inelastic).
EDGE_RESTITUTION = 0.05


def edge_runs(scene, plan, friction):
    """The plan run (the engine, not the planner's capture test) with the impact
    parameters at the edges of what its guarantee assumes: restitution 0 and
    EDGE_RESTITUTION, every fixel's mu at the low end and at the high end of
    ``friction``, and each fixel alone at its low end (the others high): the friction
    the engine applies at the impact. The failed runs, labelled."""
    lo, hi = friction
    n = scene.n_fixels
    models = [("all low", [lo] * n), ("all high", [hi] * n)]
    models += [(f"fixel {i + 1} low", [lo if j == i else hi for j in range(n)])
               for i in range(n)]
    return [(e, label, run.reason) for e in (0.0, EDGE_RESTITUTION) for label, mu in models
            if not (run := execute(scene, plan, mu, restitution=e)).success]


@pytest.mark.heavy
def test_arrival_family_guaranteed_plans_seat_and_hold_at_the_impact_edges():
    """A few seeded arrival tasks of each kind (test/helpers/arrival_family.py; all of
    them, with 100 sampled models each, in benchmarks/plan_arrival.py), planned for
    every fixel's mu in the task's mu +- 0.1: no guaranteed plan is refuted by its own
    nominal run, and every guaranteed one still seats the part with the impact
    parameters at the edges of what the guarantee assumes (:func:`edge_runs`)."""
    guaranteed = 0
    for task in arrival_family(6, seed=0):
        scene = scene_from_dict(task.scene)
        mu = scene.friction
        friction = (max(0.0, mu - 0.1), mu + 0.1)
        plan = plan_seating(scene, list(task.target), uncertainty=friction,
                            simulate_runs=False, budget=4.0)
        assert not refuted(scene, plan), (task.name, plan.missing)
        print(task.name, plan.guaranteed, [s.mode for s in plan.segments],
              [round(math.degrees(s.direction), 2) for s in plan.segments])
        if plan.guaranteed:
            guaranteed += 1
            assert plan.nominal.success, task.name
            assert edge_runs(scene, plan, friction) == [], task.name
    assert guaranteed >= 1  # the check is not vacuous


def pivot_scene(com, pin2_x: float, lift: float) -> dict:
    """The L part of the arrival family's pivot kind: tipped forward on its front pin
    (fixel 3) and the stop (fixel 1), the seated part lifted ``lift`` (m) off its rear
    pin (fixel 2)."""
    d = pawl_scene(com, pin2_x)
    near = lifted_scene(scene_from_dict(d), 1, [0, 2], lift)
    d["workpiece"]["pose"] = [float(v) for v in near.pose]
    return d


def test_the_l_part_turned_back_onto_its_rear_pin_seats_where_guaranteed():
    """The second reproducer: an L part tipped forward on its front pin and the stop,
    turned back onto its rear pin (roll on the stop and pin 3 approaching pin 2, then
    hold), lifted 11 mm so that it lands on pin 2 turning. Quasi-static margins alone
    may call such a plan guaranteed while its own nominal run ends at rest on two pins,
    turned past the seat; the plan must be guaranteed only if the engine, run here
    independently of the planner, seats it (flat on all three fixels) for the nominal
    model and at the edges of the impact assumptions."""
    scene = scene_from_dict(pivot_scene((0.0319, 0.0099), 0.1082, 0.011))
    friction = (0.2, 0.4)
    plan = plan_seating(scene, [1, 2, 3], uncertainty=friction, simulate_runs=False,
                        budget=4.0)
    assert plan.feasible, plan.reason
    assert [s.mode for s in plan.segments] == ["rar", "nnn"]
    assert not refuted(scene, plan), plan.missing
    if plan.guaranteed:
        run = execute(scene, plan)
        assert run.success and run.final_pose[2] == pytest.approx(0.0, abs=math.radians(0.5))
        assert edge_runs(scene, plan, friction) == []
    else:
        assert plan.missing


def test_models_of_every_uncertain_parameter(disc_plan):
    """The capture test's boundary models and the Monte Carlo's samples carry every
    simulated parameter (mu per fixel, mass, inertia, centre of mass), and a run uses
    them: the engine's body has the model's mass, inertia and centre of mass."""
    from wrenchcone_ros.core import Uncertainty
    from wrenchcone_ros.core.plan import capture_models, sample_models
    from wrenchcone_ros.core.plan.execution import as_model, model_scene
    from wrenchcone_ros.core.simulate import Simulation

    scene, plan = disc_plan
    u = Uncertainty(friction=(0.2, 0.4), mass=(0.04, 0.06), inertia=(1.4e-5, 1.7e-5),
                    com_box=(0.001, 0.002), normal_error=0.01)
    labels = [label for label, _m in capture_models(scene, u)]
    assert labels == ["nominal", "friction lo", "friction hi", "mass lo, inertia hi",
                      "mass hi, inertia lo", "com +x", "com -x", "com +y", "com -y"]
    models = dict(capture_models(scene, u))
    assert models["friction lo"].friction == (0.2, 0.2)
    assert (models["mass lo, inertia hi"].mass, models["mass lo, inertia hi"].inertia) \
        == (0.04, 1.7e-5)
    assert models["com -y"].com == (0.0, -0.002)
    samples = sample_models(scene, u, 50, seed=4)
    assert all(0.2 <= m <= 0.4 for s in samples for m in s.friction)
    assert all(0.04 <= s.mass <= 0.06 and 1.4e-5 <= s.inertia <= 1.7e-5 for s in samples)
    assert all(abs(s.com[0]) <= 0.001 and abs(s.com[1]) <= 0.002 for s in samples)
    assert len({s.mass for s in samples}) == 50  # drawn, not fixed
    m = samples[0]
    sim = Simulation(model_scene(scene, as_model(scene, m)), plan.actuator, 0.0, m.friction)
    assert sim.sp.body.mass == pytest.approx(m.mass)
    assert sim.sp.body.moment == pytest.approx(m.inertia)
    assert tuple(sim.sp.body.center_of_gravity) == pytest.approx(m.com)
    run = execute(scene, plan, m)
    assert run.model == m and run.friction == m.friction
