# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The search's time budget (core/plan/search.py): CPU seconds of the searching thread,
bounding everything after the first descent, the constant-direction stage included.

Checked from outside the planner: the CPU time of a child process's planning thread,
the number of candidates in its ``tried`` list, with and without busy processes pinned
to the same core (a loaded machine, made so by construction).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

from helpers.arrival_family import arrival_family  # noqa: E402

from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from wrenchcone_ros.core.scene import scene_from_dict  # noqa: E402

pytestmark = pytest.mark.slow  # plans searched in the physics engine

TESTS = Path(__file__).resolve().parents[1]  # where helpers/ is


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


CHILD = """
import json, time
from helpers.arrival_family import arrival_family
from wrenchcone_ros.core.plan import plan_seating
from wrenchcone_ros.core.scene import scene_from_dict
found = {{t.name: t for t in arrival_family(3, seed=0)}}["disc_0_0"]
scene, target = scene_from_dict(found.scene), list(found.target)
friction = (max(0.0, scene.friction - 0.1), scene.friction + 0.1)
plan_seating(scene, target, uncertainty=friction, simulate_runs=False, budget=0.01)  # warm
w0, c0 = time.perf_counter(), time.thread_time()
plan = plan_seating(scene, target, uncertainty=friction, simulate_runs=False, budget=1.5)
print(json.dumps({{"wall": time.perf_counter() - w0, "cpu": time.thread_time() - c0,
                   "tried": len(plan.tried)}}))
"""


def plan_on_one_core(core: int, busy: int) -> dict:
    """disc_0_0 planned with a 1.5 s budget in a child process pinned to ``core``, with
    ``busy`` spinning processes pinned to the same core: (wall s, CPU s, candidates)."""
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(busy)]
    try:
        for h in hogs:
            os.sched_setaffinity(h.pid, {core})
        out = subprocess.run([sys.executable, "-c", CHILD.format()], capture_output=True, text=True,
                             timeout=600, check=True,
                             env=dict(os.environ, PYTHONPATH=os.pathsep.join(
                                 [str(TESTS)] + sys.path)),
                             preexec_fn=lambda: os.sched_setaffinity(0, {core}))
        return json.loads(out.stdout.strip().splitlines()[-1])
    finally:
        for h in hogs:
            h.kill()
            h.wait()


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="needs Linux CPU affinity")
def test_a_loaded_machine_finds_the_same_candidates():
    """The budget is the planning thread's CPU time: two busy processes on the planner's
    core make the search take about three times as long in wall time, yet it tries as
    many candidates (a wall-clock budget would leave it the first descent alone)."""
    core = sorted(os.sched_getaffinity(0))[0]
    quiet = plan_on_one_core(core, 0)
    time.sleep(0.1)
    loaded = plan_on_one_core(core, 2)
    assert loaded["wall"] > 2.0 * loaded["cpu"], loaded  # the load is real
    assert quiet["tried"] >= 8, quiet  # the budget buys candidates after the descent
    assert abs(loaded["tried"] - quiet["tried"]) <= 2, (quiet, loaded)


def refuted(plan) -> int:
    """How many complete candidates the search refuted (its ``tried`` lines 'plan ...')."""
    return sum(t.startswith("plan ") for t in plan.tried)


def test_the_candidate_limit_ends_the_search_whatever_the_budget():
    """disc_0_0 refutes more than 3 candidates within the default budget; with
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
    ({"max_candidates": 0}, "max_candidates must be None or a whole number >= 1"),
    ({"max_candidates": 2.5}, "max_candidates must be None or a whole number >= 1"),
    ({"max_candidates": True}, "max_candidates must be None or a whole number >= 1")])
def test_a_bad_goal_or_limit_is_refused_with_what_is_allowed(kw, allowed):
    from wrenchcone_ros.core.plan import PlanError

    scene, target, friction = task("disc_0_0")
    with pytest.raises(PlanError, match=re.escape(allowed)):
        plan_seating(scene, target, uncertainty=friction, **kw)
