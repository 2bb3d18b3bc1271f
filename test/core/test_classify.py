# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Classification over all modes, wildcard unions, and "consistent only with this mode".

Independent references: brute force over every mode's cone (each cone itself checked
against the LP in test_crosscheck.py) and the LP oracle directly.
"""

import numpy as np
import pytest
from helpers.strategies import random_scene

from wrenchcone_ros.core import (
    ModeError,
    consistent_modes,
    default_scene,
    enumerate_modes,
    load_scene,
    wrench_cone,
)
from wrenchcone_ros.core.classify import ModeClassifier, exclusive_region, only_mode
from wrenchcone_ros.core.wrenchset import WrenchSet
from wrenchcone_ros.core.lp_check import lp_consistent

BAND = 1e-6  # skip wrenches this close (margin) to any mode's boundary


def brute_force(scene, g):
    out = {}
    for m in enumerate_modes(scene.in_contact):
        c = wrench_cone(scene, m)
        out[m] = (c.contains(g), c.margin(g))
    return out


@pytest.mark.slow
def test_consistent_modes_equals_brute_force_on_random_scenes():
    rng = np.random.default_rng(20261121)
    checked = pruned_total = 0
    for _ in range(25):
        gen = random_scene(rng, n_fixels=int(rng.integers(1, 5)))
        scene = load_scene(gen.data)
        clf = ModeClassifier(scene)
        for _ in range(8):
            g = rng.normal(size=3) * [1, 1, scene.length_scale]
            ref = brute_force(scene, g)
            if any(abs(m) < BAND for _, m in ref.values()):
                continue
            got = clf.consistent_modes(g)
            assert sorted(x.mode for x in got) == sorted(m for m, (ok, _) in ref.items() if ok)
            for x in got:
                assert x.margin == pytest.approx(ref[x.mode][1])
            checked += 1
        n_modes = len(list(enumerate_modes(scene.in_contact)))
        pruned_total += n_modes
    assert checked >= 120


def test_classification_prunes_the_enumeration():
    """A 4-fixel scene: far fewer search nodes than the 4^3 * 2 = 128 leaves."""
    s = load_scene({"workpiece": {"mass": 1.0, "inertia": 0.3, "shape": {
        "type": "polygon", "vertices": [[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]}},
        "friction": 0.3, "fixels": [[-0.5, -0.5], [0.5, -0.5], [1.0, 0.2], [-1.2, 0.0]]})
    clf = ModeClassifier(s)
    found = clf.consistent_modes((0.0, -1.0, 0.05))
    assert found and clf.nodes_visited < 128
    assert len(clf._cones) < 128  # cones built only for leaves reached


@pytest.mark.slow
def test_classification_agrees_with_the_lp():
    s = default_scene()
    rng = np.random.default_rng(7)
    for _ in range(40):
        g = rng.normal(size=3)
        got = {m.mode for m in consistent_modes(s, g)}
        for m in enumerate_modes(s.in_contact):
            c = wrench_cone(s, m)
            if abs(c.margin(g)) < BAND:
                continue
            assert (m in got) == lp_consistent(s, m, g).consistent


@pytest.mark.slow
def test_wildcards_are_unions():
    s = default_scene()
    u = wrench_cone(s, "c*")
    assert isinstance(u, WrenchSet)
    assert set(u.modes) | set(u.impossible) == {"la", "ls", "ra", "rs", "na", "ns"}
    rng = np.random.default_rng(3)
    for _ in range(200):
        g = rng.normal(size=3)
        pieces = [wrench_cone(s, m) for m in ("la", "ls", "ra", "rs", "na", "ns")]
        assert u.contains(g) == any(p.contains(g) for p in pieces)
        assert u.margin(g) == pytest.approx(max(p.margin(g) for p in pieces))
    star = wrench_cone(s, "**")
    assert set(star.modes) | set(star.impossible) == set(enumerate_modes(s.in_contact))


def test_wildcard_errors():
    with pytest.raises(ModeError, match="wildcard 'c' at fixel 2 needs contact"):
        wrench_cone(default_scene(), "nc")
    with pytest.raises(ModeError, match="3 letter"):
        wrench_cone(default_scene(), "n**")


@pytest.mark.slow
def test_only_mode_and_exclusive_region():
    s = default_scene()
    pieces = exclusive_region(s, "na")
    assert pieces
    rng = np.random.default_rng(11)
    inside = 0
    for _ in range(300):
        g = rng.normal(size=3)
        ans = only_mode(s, "na", g)
        ref = brute_force(s, g)
        if any(abs(m) < BAND for _, m in ref.values()) or any(
                abs(p.margin(g)) < BAND for p in pieces):
            continue
        others = [m for m, (ok, _) in ref.items() if ok and m != "na"]
        assert ans.consistent == ref["na"][0]
        assert ans.only == (ref["na"][0] and not others)
        assert ans.only == any(p.contains(g) for p in pieces)
        inside += ans.only
    assert inside > 0


def test_non_finite_wrench_refused():
    with pytest.raises(ValueError, match="finite"):
        consistent_modes(default_scene(), (np.inf, 0, 0))


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["kernel", "numpy"])
def test_classify_many_fixels_has_no_recursion_limit_and_a_node_budget(engine):
    """1000 fixels used to raise RecursionError (one stack frame per fixel); the search is
    iterative now, shown here under a recursion limit of only 40 frames more than the
    caller's depth with 80 fixels, and max_nodes bounds its work (SearchBudgetError)."""
    import inspect
    import sys

    from wrenchcone_ros.core import Fixel, Scene, Workpiece
    from wrenchcone_ros.core.classify import SearchBudgetError
    from wrenchcone_ros.core.geometry import Disc

    # every fixel on the +x axis: one normal direction, so a mode mixing a (a_n < 0) and
    # s (a_n >= 0) is impossible; with zero wrench only all-a and all-s remain
    n = 80
    fixels = tuple(Fixel((2.0 + 0.001 * k, 0.0)) for k in range(n))
    scene = Scene(Workpiece(1.0, 1.0, Disc(1.0)), fixels, 0.2)
    with pytest.raises(SearchBudgetError, match="more than 50 "):
        ModeClassifier(scene, engine=engine).consistent_modes((0.0, 0.0, 0.0), max_nodes=50)
    old = sys.getrecursionlimit()
    sys.setrecursionlimit(len(inspect.stack(0)) + 40)
    try:
        found = ModeClassifier(scene, engine=engine).consistent_modes((0.0, 0.0, 0.0))
    finally:
        sys.setrecursionlimit(old)
    assert {m.mode for m in found} == {"a" * n, "s" * n}


def test_union_many_queries_equal_the_scalar_calls():
    s = default_scene()
    rng = np.random.default_rng(3)
    G = rng.normal(size=(200, 3))
    for mode in ("*a", "cs", "**"):
        u = wrench_cone(s, mode)
        assert u.contains_many(G).tolist() == [u.contains(g) for g in G]
        assert u.margin_many(G).tolist() == [u.margin(g) for g in G]
    empty = WrenchSet("xx", ())
    assert empty.contains_many(G).tolist() == [False] * 200
    assert empty.margin_many(G).tolist() == [-1.0] * 200


@pytest.mark.slow
@pytest.mark.parametrize("shared_edge", [False, True])
def test_batched_search_equals_reference_search(shared_edge):
    """consistent_modes on the kernel engine (breadth first, batched relaxations) finds
    the same modes with the same margins (to rounding) as the reference depth-first search
    on the numpy engine, also for wrenches built inside a mode's cone."""
    from helpers.strategies import shared_edge_scene, wrench_from_cone

    rng = np.random.default_rng(20261123 + shared_edge)
    checked = 0
    for _ in range(10):
        gen = (shared_edge_scene(rng) if shared_edge
               else random_scene(rng, n_fixels=int(rng.integers(2, 6))))
        scene = load_scene(gen.data)
        cones = wrench_cone(scene, "*" * scene.n_fixels)
        for k in range(4):
            g = rng.normal(size=3) * [1, 1, scene.length_scale]
            if k and cones.pieces:
                piece = cones.pieces[int(rng.integers(len(cones.pieces)))]
                g = wrench_from_cone(rng, piece, scene.length_scale)
                if g is None:
                    continue
            got = consistent_modes(load_scene(gen.data), g, engine="kernel")
            ref = consistent_modes(load_scene(gen.data), g, engine="numpy")
            assert sorted(m.mode for m in got) == sorted(m.mode for m in ref)
            byname = {m.mode: m.margin for m in ref}
            for m in got:
                assert m.margin == pytest.approx(byname[m.mode], abs=1e-12)
            checked += 1
    assert checked >= 30


def rim_scene(n: int):
    """n fixels evenly on a unit disc's rim: every contact normal passes through the
    centre, so the kernel declines the relaxed search nodes (degenerate)."""
    import math

    return load_scene({"workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.0, 0.0],
                                     "shape": {"type": "disc", "radius": 1.0}},
                       "friction": 0.3,
                       "fixels": [[math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)]
                                  for k in range(n)]})


@pytest.mark.slow
@pytest.mark.parametrize("n", [3, 4, 8])
def test_batched_search_prunes_the_nodes_the_kernel_declines(n):
    """The kernel declines every relaxed node of a rim scene; the batched search kept
    them all, so 8 rim fixels used up 20,000 nodes (seconds, then LIMIT_EXCEEDED in the
    node) where the reference search visits a few dozen. Declined nodes are now pruned
    by the reference test: the same modes as the reference (and, for n <= 4, brute
    force), within the reference's node count times a small factor."""
    rng = np.random.default_rng(20261123 + n)
    for g in [(0.0, 1.0, 0.0), (0.3, -1.0, 0.1), *rng.normal(size=(4, 3))]:
        ref_clf = ModeClassifier(rim_scene(n), engine="numpy")
        ref = ref_clf.consistent_modes(g, max_nodes=20_000)
        clf = ModeClassifier(rim_scene(n), engine="kernel")
        got = clf.consistent_modes(g, max_nodes=20_000)
        assert sorted(m.mode for m in got) == sorted(m.mode for m in ref)
        assert clf.nodes_visited <= 10 * max(ref_clf.nodes_visited, n + 1)
        if n <= 4:
            truth = brute_force(rim_scene(n), np.asarray(g))
            if all(abs(m) >= BAND for _, m in truth.values()):
                assert sorted(m.mode for m in got) == sorted(
                    m for m, (ok, _) in truth.items() if ok)
