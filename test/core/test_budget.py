# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""core/budget.py: the per-thread time budget stops the loops a request makes long."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest

from wrenchcone_ros.core import load_scene, wrench_cone, wrench_cones
from wrenchcone_ros.core.budget import TimeBudgetExceeded, check_time_budget, time_budget
from wrenchcone_ros.core.classify import ModeClassifier

#: A budget no computation here meets (s) and one every computation here meets.
TINY_S, AMPLE_S = 1e-9, 1e6


def ring_scene(n: int = 8):
    """n fixels evenly on a unit disc's rim: all in contact, every normal through the
    centre (degenerate: the kernel declines these modes, the reference is slow)."""
    fixels = [[math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)]
              for k in range(n)]
    return load_scene({"workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.0, 0.0],
                                     "shape": {"type": "disc", "radius": 1.0}},
                       "friction": 0.3, "fixels": fixels})


def test_no_budget_never_raises():
    check_time_budget()
    with time_budget(None):
        time.sleep(0.002)
        check_time_budget()
    with time_budget(0.0):  # 0 = no budget, as the node's max_request_time
        time.sleep(0.002)
        check_time_budget()


def test_a_spent_budget_raises_and_says_how_long_it_was():
    with time_budget(0.001):
        time.sleep(0.003)
        with pytest.raises(TimeBudgetExceeded, match="0.001 s"):
            check_time_budget()
    check_time_budget()  # restored on exit


def test_nested_budgets_the_earlier_deadline_wins():
    with time_budget(AMPLE_S):
        with time_budget(0.001):
            time.sleep(0.003)
            with pytest.raises(TimeBudgetExceeded):
                check_time_budget()
        check_time_budget()  # the outer, ample budget is back
    with time_budget(0.001):
        with time_budget(AMPLE_S):  # cannot extend the outer one
            time.sleep(0.003)
            with pytest.raises(TimeBudgetExceeded):
                check_time_budget()


def test_the_budget_belongs_to_the_calling_thread():
    seen = []
    with time_budget(0.001):
        time.sleep(0.003)

        def other() -> None:
            try:
                check_time_budget()
                seen.append("ok")
            except TimeBudgetExceeded:
                seen.append("raised")

        t = threading.Thread(target=other)
        t.start()
        t.join()
    assert seen == ["ok"]


@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_a_wildcard_union_stops_on_its_budget_and_is_complete_without(engine):
    scene = ring_scene()
    mode = "cc" + "n" * 6  # 9 concrete modes
    with time_budget(TINY_S), pytest.raises(TimeBudgetExceeded):
        wrench_cone(scene, mode, engine=engine)
    with time_budget(AMPLE_S):
        union = wrench_cone(scene, mode, engine=engine)
    reference = wrench_cone(scene, mode, engine="numpy")
    assert sorted(union.modes) == sorted(reference.modes)
    assert sorted(union.impossible) == sorted(reference.impossible)


@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_a_batch_stops_on_its_budget(engine):
    scene = ring_scene()
    with time_budget(TINY_S), pytest.raises(TimeBudgetExceeded):
        wrench_cones(scene, ["ccnnnnnn", "nnnnnnnn"], engine=engine)


@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_a_classification_stops_on_its_budget(engine, monkeypatch):
    monkeypatch.setenv("WRENCHCONE_ENGINE", engine)
    scene = ring_scene()
    with time_budget(TINY_S), pytest.raises(TimeBudgetExceeded):
        ModeClassifier(scene).consistent_modes(np.array([0.0, 1.0, 0.0]), max_nodes=50)


def test_a_wildcard_plan_stops_on_its_budget(monkeypatch):
    """Found against the running node with max_concrete_modes raised to 100,000:
    check_wrench "********" on 8 touching fixels answered LIMIT_EXCEEDED only after
    5.7 s (budget 0.05 s), and held up the fast lane that long, because the packed
    plans of all 4^8 = 65,536 concrete modes were built before any budget check. The
    plan building now checks the budget per new mode: it stops long before the end."""
    from wrenchcone_ros.core import stats
    from wrenchcone_ros.core.engines import packing

    calls = []
    real = packing.plan_code

    def counting(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(packing, "plan_code", counting)
    stats.BATCH_PLANS.clear()
    with time_budget(TINY_S), pytest.raises(TimeBudgetExceeded):
        wrench_cone(ring_scene(), "*" * 8, engine="kernel")
    assert len(calls) < 4 ** 8 // 2
