# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The search's bounds (core/plan/search.py): counts of work by default (candidates,
segments), the same plan on every machine, loaded or not; a time budget only when asked
for, which then bounds everything after the first descent, the constant stage included.

Checked from outside the planner: plans made in child processes pinned to one core,
alone, beside busy processes on the same core (a loaded machine, made so by
construction) and beside a busy Python thread in the planning process, compared field by
field, ``tried`` lists included.
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

from helpers.arrival_family import arrival_family  # noqa: E402

from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from wrenchcone_ros.core.scene_yaml import scene_from_dict  # noqa: E402

pytestmark = pytest.mark.slow  # plans searched in the physics engine

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def task(name: str):
    """(scene, target, friction) of the arrival family's task ``name`` (seed 0), as
    benchmarks/plan_arrival.py plans it."""
    found = {t.name: t for t in arrival_family(3, seed=0)}[name]
    scene = scene_from_dict(found.scene)
    mu = scene.friction
    return scene, list(found.target), (max(0.0, mu - 0.1), mu + 0.1)


def test_the_budget_bounds_the_constant_stage():
    """bounce_0_2 (an L part that bounces off its stop): no candidate seats it, so the
    constant-direction stage runs; with a budget spent by the first descent it runs no
    direction, says so in ``tried``, and the plan's reason names the budget. With the
    default budget it runs all of them (and none seats the part)."""
    scene, target, friction = task("bounce_0_2")
    short = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                         budget=0.01)
    assert not short.feasible
    assert any(t.startswith("constant directions: the search's time budget ran out "
                            "after 0 of ") for t in short.tried), short.tried
    assert "time budget (0.01 s) ran out" in short.reason
    full = plan_seating(scene, target, uncertainty=friction, simulate_runs=False)
    assert not full.feasible
    assert any(t.startswith("constant directions: none of ") for t in full.tried), \
        full.tried
    assert "time budget" not in full.reason


#: The documented scenes (docs/planning.md and the tutorials): file, start pose or None
#: (the file's), target, friction interval or None (the nominal model).
SCENES = (("pawl_seating.yaml", None, [1, 2, 3], (0.2, 0.4)),
          ("pawl_tipped.yaml", None, [1, 2, 3], (0.2, 0.4)),
          ("tbar_swing.yaml", None, [1, 2], (0.2, 0.4)),
          ("disc_nest.yaml", None, [1, 2], (0.2, 0.4)),
          ("pawl_polygon.yaml", (0.092, 0.2, 0.0), [1, 2, 3], None),  # section 3, 12 mm
          ("pawl_polygon.yaml", (0.096, 0.2, 0.0), [1, 2, 3], None))  # section 3, 8 mm

CHILD = """
import json, math, sys, threading
from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.plan import plan_seating
busy_thread = {busy_thread}
stop = threading.Event()
def spin():  # a node's executor at work: pure Python, holding the GIL in turns
    while not stop.is_set():
        sum(i * i for i in range(1000))
if busy_thread:
    threading.Thread(target=spin, daemon=True).start()
out = []
for name, pose, target, friction in {scenes!r}:
    scene = load_scene({examples!r} + "/" + name)
    if pose is not None:
        scene = scene.with_pose(*pose)
    plan = plan_seating(scene, target, uncertainty=friction, simulate_runs=False)
    out.append({{"scene": name, "pose": pose, "feasible": plan.feasible,
                 "guaranteed": plan.guaranteed, "reason": plan.reason,
                 "tried": list(plan.tried), "candidates": plan.candidates,
                 "trials": plan.trials, "out_of_time": plan.out_of_time,
                 "segments": [[s.mode, s.direction.hex(), s.margin.hex(), s.scale.hex(),
                               [v.hex() for v in s.end_pose]] for s in plan.segments]}})
stop.set()
print(json.dumps(out))
"""

#: A process that streams memory (a busy neighbour on a shared cache and memory bus).
HOG = ("import numpy as np\na = np.ones(1 << 22)\nwhile True:\n    b = a.copy()\n"
       "    a += 1e-9 * b")


def plans_on_one_core(core: int, hogs_per_core: int, busy_thread: bool) -> list[dict]:
    """The SCENES planned with the default bounds in a child process pinned to
    ``core``, with ``hogs_per_core`` memory-streaming processes pinned to each core of
    this process and, with ``busy_thread``, a busy Python thread in the planning
    process."""
    hogs = []
    try:
        for c in sorted(os.sched_getaffinity(0)):
            for _ in range(hogs_per_core):
                h = subprocess.Popen([sys.executable, "-c", HOG])
                os.sched_setaffinity(h.pid, {c})
                hogs.append(h)
        code = CHILD.format(busy_thread=busy_thread, scenes=SCENES,
                            examples=str(EXAMPLES))
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             timeout=1800, check=True,
                             env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)),
                             preexec_fn=lambda: os.sched_setaffinity(0, {core}))
        return json.loads(out.stdout.strip().splitlines()[-1])
    finally:
        for h in hogs:
            h.kill()
            h.wait()


@pytest.mark.heavy
@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="needs Linux CPU affinity")
def test_the_same_plans_alone_loaded_and_beside_a_busy_thread():
    """The documented scenes give the same plans, bit for bit (modes, directions,
    margins, end poses, ``tried``, reason), planned alone on one core, beside two
    memory-streaming processes per core, and beside a busy Python thread in the planning
    process; and the planning.md section 3 pawls give their documented answers (12 mm:
    no plan, step 1; 8 mm: the constant -72 deg tilt)."""
    core = sorted(os.sched_getaffinity(0))[0]
    alone = plans_on_one_core(core, 0, False)
    loaded = plans_on_one_core(core, 2, False)
    threaded = plans_on_one_core(core, 0, True)
    for a, b, c in zip(alone, loaded, threaded):
        assert a == b, (a["scene"], a["pose"], "loaded")
        assert a == c, (a["scene"], a["pose"], "busy thread")
        assert not a["out_of_time"]
    twelve, eight = alone[4], alone[5]
    assert not twelve["feasible"]
    assert twelve["reason"] == ("step 1: no direction gives a mode that keeps fixels 2, 3 "
                                "and approaches fixel 1"), twelve["reason"]
    assert eight["feasible"] and not eight["guaranteed"]
    assert [m for m, *_ in eight["segments"]] == ["ars", "nnn"], eight["segments"]
    assert all(round(math.degrees(float.fromhex(d))) == -72
               for _m, d, *_ in eight["segments"]), eight["segments"]


def refuted(plan) -> int:
    """How many complete candidates the search refuted (its ``tried`` lines 'plan ...')."""
    return sum(t.startswith("plan ") for t in plan.tried)


def test_the_candidate_limit_ends_the_search_whatever_the_budget():
    """disc_0_0 refutes more than 3 candidates within the default bounds; with
    ``max_candidates=3`` and a budget no search reaches, it stops after the third, says
    so in its reason, and is not marked as ended by the time budget (its plan is the
    same on any machine)."""
    scene, target, friction = task("disc_0_0")
    free = plan_seating(scene, target, uncertainty=friction, simulate_runs=False)
    assert refuted(free) > 3, free.tried
    capped = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                          budget=1e6, max_candidates=3)
    assert refuted(capped) == 3, capped.tried
    assert "candidate limit (3) was reached" in capped.reason
    assert not capped.out_of_time and "time budget" not in capped.reason
    assert capped.candidates == 3 and free.candidates > 3


def test_the_segment_limit_ends_the_search():
    """disc_0_0 plans more than 3 segments unbounded; with ``max_trials=3`` it stops
    after the third (the first descent, never cut short, may plan more), says so in its
    reason, and is not marked as ended by the time budget."""
    scene, target, friction = task("disc_0_0")
    free = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                        max_candidates=None, max_trials=None)
    assert free.trials > 3, free.trials
    capped = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                          max_candidates=None, max_trials=3)
    assert "segment limit (3 segments planned) was reached" in capped.reason, capped.reason
    assert not capped.out_of_time
    assert capped.trials < free.trials


def test_goal_seated_stops_at_the_first_candidate_the_engine_seats():
    """With GOAL_SEATED the search returns a candidate whose nominal run seats the part
    (executed again in the engine, it does), says why it stopped, and has refuted no
    more candidates than the search for a guarantee does on the same task."""
    from wrenchcone_ros.core.plan import GOAL_SEATED, execute

    scene, target, friction = task("disc_0_0")
    seated = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                          goal=GOAL_SEATED)
    assert seated.feasible and execute(scene, seated).success
    if not seated.guaranteed:
        assert seated.tried[-1].startswith("goal 'seated': the search stopped"), seated.tried
    free = plan_seating(scene, target, uncertainty=friction, simulate_runs=False)
    assert refuted(seated) <= refuted(free) + 1, (seated.tried, free.tried)


@pytest.mark.parametrize("kw, allowed", [
    ({"goal": "best"}, "goal must be one of ['guaranteed', 'seated']"),
    ({"max_candidates": 0}, "max_candidates must be None (no limit) or a whole number >= 1"),
    ({"max_candidates": 2.5}, "max_candidates must be None (no limit) or a whole number"),
    ({"max_candidates": True}, "max_candidates must be None (no limit) or a whole number"),
    ({"max_trials": 0}, "max_trials must be None (no limit) or a whole number >= 1"),
    ({"budget": 0}, "budget must be None (no time cap) or a positive number of seconds"),
    ({"budget": float("inf")}, "budget must be None (no time cap) or a positive number")])
def test_a_bad_goal_or_limit_is_refused_with_what_is_allowed(kw, allowed):
    from wrenchcone_ros.core.plan import PlanError

    scene, target, friction = task("disc_0_0")
    with pytest.raises(PlanError, match=re.escape(allowed)):
        plan_seating(scene, target, uncertainty=friction, **kw)


def test_a_guaranteed_plan_also_seats_under_other_engine_settings():
    """The capture test of a guaranteed plan includes its nominal model under every
    engine setting of ENGINE_VARIATIONS (the time step, the solver iterations and the
    collision slop each scaled down and up), each run seated as planned; run again here
    under each setting, outside the search, the plan seats the part."""
    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.plan import ENGINE_VARIATIONS, execute

    scene = load_scene(EXAMPLES / "pawl_seating.yaml")
    plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)
    assert plan.guaranteed, plan.missing
    labels = [r.label for r in plan.checks]
    assert labels[-len(ENGINE_VARIATIONS):] == [f"nominal, engine {e.label}"
                                                for e in ENGINE_VARIATIONS], labels
    assert {e.step for e in ENGINE_VARIATIONS} >= {0.25, 2.0}
    for engine in ENGINE_VARIATIONS:
        assert execute(scene, plan, engine=engine).success, engine
