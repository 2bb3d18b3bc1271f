# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchset.py: one type for every set of wrenches (a cone, a wildcard union, a robust
set) and its guarantee.

Independent references: the LP oracle (lp_check.py) for membership in a union of modes,
the scenario bound's text for the guarantee, and the scalar calls for the vectorised ones
(elementwise identical by construction, checked on every row).
"""

import numpy as np
import pytest

from wrenchcone_ros.core import (
    EXACT_GUARANTEE,
    NOMINAL,
    Guarantee,
    Uncertainty,
    WrenchSet,
    default_scene,
    load_scene,
    mode_union,
    robust_cone,
    wrench_cone,
)
from wrenchcone_ros.core.lp_check import lp_consistent
from wrenchcone_ros.core.modes import expand_mode

BAND = 1e-6  # skip wrenches this close (margin) to a piece's boundary
PAWL = "examples/pawl_polygon.yaml"


@pytest.mark.parametrize("mode", ["c*", "**", "*a"])
def test_union_membership_is_the_lp_over_its_modes(mode):
    """g is in a wildcard mode's set iff the LP finds it consistent with one of the
    concrete modes; the margin is positive inside and negative outside."""
    s = default_scene()
    ws = mode_union(s, mode)
    concrete = expand_mode(mode, s.in_contact)
    assert sorted(ws.modes + ws.impossible) == sorted(concrete)
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(40):
        g = rng.normal(size=3)
        if any(abs(c.margin(g)) < BAND for c in ws.pieces):
            continue
        inside, margin = ws.check(g)
        assert inside == any(lp_consistent(s, m, g).consistent for m in concrete), g
        assert (margin > 0) == inside
        checked += 1
    assert checked > 30


def test_one_piece_is_exactly_its_cone_and_many_rows_are_the_scalar_calls():
    s = load_scene(PAWL)
    G = np.random.default_rng(5).normal(size=(300, 3))
    for mode in ("arr", "ann", "a**"):
        got = wrench_cone(s, mode)
        ws = got if isinstance(got, WrenchSet) else WrenchSet.of(got)
        inside, margin = ws.check_many(G)
        assert inside.tolist() == [ws.contains(g) for g in G]
        assert margin.tolist() == [ws.margin(g) for g in G]
        assert ws.contains_many(G).tolist() == inside.tolist()
        assert ws.margin_many(G).tolist() == margin.tolist()
        if len(ws.pieces) == 1:
            assert margin.tolist() == ws.cone.margin_many(G).tolist()
    empty = WrenchSet("xx", ())
    assert not empty.feasible and empty.check((1.0, 0.0, 0.0)) == (False, -1.0)
    with pytest.raises(ValueError, match="union of 0 cones"):
        _ = empty.cone


def test_a_robust_set_carries_its_guarantee_and_the_nominal_one_is_exact():
    s = default_scene()
    scenario = Uncertainty(mass=(0.9, 1.1))
    rs = robust_cone(s, "na", scenario, "any")
    n = scenario.scenario_size()
    assert rs.guarantee == Guarantee("scenario", scenario.epsilon, scenario.beta, n)
    assert str(rs.guarantee) == f"scenario(eps=0.05, beta=0.001, N={n})"
    d = rs.to_dict()
    assert d["quantifier"] == "any" and d["guarantee"]["kind"] == "scenario"
    assert len(d["pieces"]) == len(rs.pieces)
    nominal = robust_cone(s, "na", NOMINAL, "all")
    assert nominal.guarantee is EXACT_GUARANTEE and nominal.guarantee.exact
    assert np.array_equal(nominal.cone.F_hat, wrench_cone(s, "na").F_hat)
    with pytest.raises(ValueError, match="guarantee kind"):
        Guarantee("probably")
