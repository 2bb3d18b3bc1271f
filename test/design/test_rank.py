# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Ranking of designs (design/rank.py) against its definition, written here as a pairwise
comparison: at the first column of the ranking where two designs differ, the better value
(larger or smaller, per column) ranks first, a missing value (None, NaN) last; equal on
every column, the smaller design_id first. Seeded random tables with ties and gaps, and
a table worked by hand."""

from __future__ import annotations

import functools
import math
import random

import pytest

from wrenchcone_ros.design.problem import DesignError
from wrenchcone_ros.design.rank import DEFAULT_RANKING, parse_ranking, rank_rows

#: The better direction of each column, as the docs state it (docs/fixture_design.md).
LARGER_IS_BETTER = {"plan_guaranteed", "plan_feasible", "success_rate", "hold_margin",
                    "funnel_margin", "placements", "located", "region_size",
                    "region_fraction"}


def missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def compare(a: dict, b: dict, ranking) -> int:
    """-1 when a ranks before b, +1 after, by the definition in the module docstring."""
    for k in ranking:
        x, y = a.get(k), b.get(k)
        if missing(x) and missing(y):
            continue
        if missing(x) != missing(y):
            return 1 if missing(x) else -1
        if x != y:
            better = x > y if k in LARGER_IS_BETTER else x < y
            return -1 if better else 1
    return (a["design_id"] > b["design_id"]) - (a["design_id"] < b["design_id"])


def test_a_table_worked_by_hand():
    rows = [
        {"design_id": "d", "plan_guaranteed": False, "hold_margin": 0.9, "locating_accuracy": 1.0},
        {"design_id": "c", "plan_guaranteed": True, "hold_margin": None, "locating_accuracy": 0.5},
        {"design_id": "b", "plan_guaranteed": True, "hold_margin": 0.2, "locating_accuracy": 2.0},
        {"design_id": "a", "plan_guaranteed": True, "hold_margin": 0.2, "locating_accuracy": 1.5},
        {"design_id": "e", "plan_guaranteed": True, "hold_margin": 0.2, "locating_accuracy": 1.5},
    ]
    ranked = rank_rows([dict(r) for r in rows], DEFAULT_RANKING)
    assert [r["design_id"] for r in ranked] == ["a", "e", "b", "c", "d"]
    assert [r["rank"] for r in ranked] == [1, 2, 3, 4, 5]


@pytest.mark.parametrize("seed", range(20))
def test_random_tables_are_ordered_by_the_definition(seed):
    rng = random.Random(seed)
    keys = sorted(LARGER_IS_BETTER | {"locating_accuracy"})
    ranking = tuple(rng.sample(keys, rng.randint(1, 4)))

    def value(k):
        r = rng.random()
        if r < 0.15:
            return None if r < 0.08 else float("nan")
        if k in ("plan_guaranteed", "plan_feasible"):
            return rng.random() < 0.5
        return float(rng.choice([0.0, 0.1, 0.5, 1.0, 2.0]))  # ties are common

    rows = [{"design_id": f"id{n:03d}", **{k: value(k) for k in keys}} for n in range(40)]
    rng.shuffle(rows)
    ranked = rank_rows([dict(r) for r in rows], ranking)
    expected = sorted(rows, key=functools.cmp_to_key(lambda a, b: compare(a, b, ranking)))
    assert [r["design_id"] for r in ranked] == [r["design_id"] for r in expected]


def test_parse_ranking():
    assert parse_ranking(None) == DEFAULT_RANKING
    assert parse_ranking("hold_margin, success_rate") == ("hold_margin", "success_rate")
    assert parse_ranking(["located"]) == ("located",)
    for bad in ("", "hold_margin,speed", ["margin"]):
        with pytest.raises(DesignError, match="rank keys must be .*'hold_margin'"):
            parse_ranking(bad)
