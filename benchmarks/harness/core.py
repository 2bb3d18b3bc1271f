# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The cone-building variants the core benchmarks compare (cone_timing.py,
error_vs_runtime.py), and the core's fallback counters they report."""

from __future__ import annotations


def cone_methods() -> list[tuple[str, str, bool]]:
    """Every (label, method name, exact) that ``wrench_cone`` offers right now.

    Read from ``methods.METHODS`` at run time, so a method added later is benchmarked too;
    "paper" first (it is the reference the ratios are taken against).
    """
    from wrenchcone_ros.core.batch import METHODS

    names = sorted(METHODS, key=lambda m: (m != "paper", m))
    return [(f"{m}-{'exact' if ex else 'float'}", m, ex) for ex in (False, True)
            for m in names]


def default_method() -> str:
    from wrenchcone_ros.core.batch import DEFAULT_METHOD

    return DEFAULT_METHOD


def feasible_case(rng, n: int):
    """(generated scene, Scene, mode): a random valid scene with n fixels
    (``strategies.random_scene``) and a random valid mode whose open mode is feasible (the
    LP oracle ``lp_mode_feasible``). The cases of cone_timing.py and cone3d_vs_cdd.py."""
    from helpers.strategies import random_mode, random_scene

    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.lp_check import lp_mode_feasible

    while True:
        gs = random_scene(rng, n_fixels=n)
        scene = load_scene(gs.data)
        for _ in range(60):
            mode = random_mode(rng, scene.in_contact)
            if lp_mode_feasible(scene, mode).consistent:
                return gs, scene, mode


def paper_raw(scene, mode: str):
    """The paper's algorithm in float *without* the core's verification: K, P, Theorem 1,
    canonical form, feasibility, as ``paper.paper_cone`` does them, minus its soundness
    check (NNLS) and its comparison with the planar closure (which computes the planar
    cone inside every paper-float call). Used to time the paper's algorithm itself and to
    show what float cddlib does unchecked. Emulated here with the core's own functions."""
    from wrenchcone_ros.core import paper as pm
    from wrenchcone_ros.core.cones import cone_from_hrep, hrep_to_vrep, infeasible_cone
    from wrenchcone_ros.core.constraints import acceleration_constraints, open_mode_feasible
    from wrenchcone_ros.core.dynamics import problem

    prob = problem(scene, mode, False)
    K, P = pm.kp_matrices(prob)
    F, E = pm.theorem1(K, P, False)
    closure = cone_from_hrep(F, E, mode=prob.mode, length_scale=prob.length_scale,
                             method="paper-raw", exact=False)
    acc = acceleration_constraints(prob)
    ineq = acc.ineq.tolist() if hasattr(acc.ineq, "tolist") else list(acc.ineq)
    eq = acc.eq.tolist() if hasattr(acc.eq, "tolist") else list(acc.eq)
    rays, lines = hrep_to_vrep(ineq, eq, False)
    if not open_mode_feasible(acc, rays, lines, False):
        return infeasible_cone(closure)
    return closure


def core_fallbacks() -> tuple[int, int, int]:
    """(float conversions or cones, exact fallbacks after a failed float check, cones
    computed exactly because the acceleration rows are nearly parallel) so far, summed
    over the core's fallback counters (``core.stats``: FALLBACKS, PLANAR_FALLBACKS,
    PAPER_FALLBACKS)."""
    from wrenchcone_ros.core import stats

    calls = fb = ill = 0
    for d in (stats.FALLBACKS, stats.PLANAR_FALLBACKS, stats.PAPER_FALLBACKS):
        calls += d.get("float_calls", 0) + d.get("conversions", 0) + d.get("float_cones", 0)
        fb += d.get("exact_fallbacks", 0)
        ill += d.get("exact_ill_conditioned", 0)
    return calls, fb, ill
