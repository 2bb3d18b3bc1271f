#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""cone3d against float pycddlib: time per conversion (4..40 generators), agreement with
exact cddlib, and the planar cone on cone3d against the same on cddlib.

    python benchmarks/cone3d_vs_cdd.py             # full run (a few minutes), writes docs/cone3d.md
    python benchmarks/cone3d_vs_cdd.py --quick     # a short smoke run (still writes the file)
    python benchmarks/cone3d_vs_cdd.py --no-write  # print only

Timing. For each number n of generators, CASES random cones: V input (n rays of a random
pointed cone) and H input (n random rows d with d . x >= 0 of a nonempty pointed cone).
Every method gets the same Python lists (what the core passes today) and is called in
loops of at least 2 ms, interleaved (A, B, C, A, B, C, ...) REPEATS times, so that the
load of the shared machine hits all methods alike. The case's time is the median over its
repeats; the table shows the median over cases and the median over cases of the per-case
ratio. The clock is ``time.process_time`` (CPU time of this process: the machine has two
cores shared with other engineers' jobs, so wall time mostly measures them); wall-clock
medians are printed too.

* cone3d: ``from_generators`` / ``from_inequalities`` (both representations);
* cdd 1 conversion: ``cones.vrep_to_hrep`` / ``cones.hrep_to_vrep`` with exact=False (the
  wrappers the core calls; one representation only, not canonicalised);
* cdd both: the two conversions in a row, as ``cones.cone_from_vrep`` does (without its
  float post-processing).

Agreement: the families of test/helpers/cone3d_cases.py, AGREE cones each, V and H input,
against exact cddlib on Fractions of the same floats.

Planar cone: ``planar.planar_cone`` (on cone3d) against ``planar_cdd`` below (the same
method on float cddlib, as before cone3d) and the paper method, on the random scenes of
benchmarks/cone_timing.py; the two planar results are compared; a step breakdown.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)
from harness import GENERATED_END, facts_markdown, generated_begin, machine_facts, median  # noqa: E402,E501
from harness.core import feasible_case  # noqa: E402
from helpers import cone3d_cases as T  # noqa: E402  (test/helpers/cone3d_cases.py: the agreement families)

from wrenchcone_ros.core import cone3d, stats  # noqa: E402
from wrenchcone_ros.core.cones import (  # noqa: E402
    Cone,
    cone_from_vrep,
    hrep_to_vrep,
    infeasible_cone,
    vrep_to_hrep,
)
from wrenchcone_ros.core.constraints import (  # noqa: E402
    acceleration_constraints,
    force_generators,
    open_mode_feasible,
)
from wrenchcone_ros.core.dynamics import problem  # noqa: E402
from wrenchcone_ros.core.paper import paper_cone  # noqa: E402
from wrenchcone_ros.core.planar import planar_cone  # noqa: E402

OUT = harness.DOCS / "cone3d.md"
BEGIN, END = generated_begin("cone3d_vs_cdd.py"), GENERATED_END
SIZES = (4, 6, 8, 12, 16, 24, 32, 40)


# --- timing ------------------------------------------------------------------------------------
def loop_time(fn, min_time: float = 2e-3) -> tuple[float, float]:
    """(CPU, wall) seconds per call of fn, looping until min_time of CPU has elapsed."""
    loops = 1
    while True:
        c0, w0 = time.process_time(), time.perf_counter()
        for _ in range(loops):
            fn()
        dc, dw = time.process_time() - c0, time.perf_counter() - w0
        if dc >= min_time or loops >= 100_000:
            return dc / loops, dw / loops
        loops *= max(2, int(min_time / max(dc, 1e-7)) + 1)


def time_methods(methods: dict, repeats: int) -> dict[str, tuple[float, float]]:
    """Median (CPU, wall) per call of each method, interleaved repeats."""
    samples = {k: [] for k in methods}
    for fn in methods.values():
        fn()  # warm-up
    for _ in range(repeats):
        for k, fn in methods.items():
            samples[k].append(loop_time(fn))
    return {k: (median([c for c, _ in v]), median([w for _, w in v])) for k, v in samples.items()}


def v_case(rng, n):
    axis = T._unit(rng.normal(size=3))
    return (axis + rng.uniform(0.3, 1.0) * rng.normal(size=(n, 3))).tolist()


def h_case(rng, n):
    # rows d close to an axis: {x : d . x >= 0} is a nonempty pointed cone
    return v_case(rng, n)


def conversion_table(cases: int, repeats: int, rng) -> tuple[list[str], dict]:
    rows, raw = [], {}
    for kind in ("V", "H"):
        for n in SIZES:
            per = {"c3": [], "one": [], "both": [], "c3w": [], "bothw": []}
            ratios_both, ratios_one = [], []
            for _ in range(cases):
                a = (v_case if kind == "V" else h_case)(rng, n)
                if kind == "V":
                    methods = {
                        "c3": lambda a=a: cone3d.from_generators(a),
                        "one": lambda a=a: vrep_to_hrep(a, [], False),
                        "both": lambda a=a: _cdd_both_v(a),
                    }
                else:
                    methods = {
                        "c3": lambda a=a: cone3d.from_inequalities(a),
                        "one": lambda a=a: hrep_to_vrep(a, [], False),
                        "both": lambda a=a: _cdd_both_h(a),
                    }
                t = time_methods(methods, repeats)
                per["c3"].append(t["c3"][0])
                per["one"].append(t["one"][0])
                per["both"].append(t["both"][0])
                per["c3w"].append(t["c3"][1])
                per["bothw"].append(t["both"][1])
                ratios_both.append(t["both"][0] / t["c3"][0])
                ratios_one.append(t["one"][0] / t["c3"][0])
            m = {k: median(v) for k, v in per.items()}
            raw[(kind, n)] = (m, median(ratios_both), median(ratios_one))
            rows.append(f"| {kind} | {n} | {us(m['c3'])} | {us(m['one'])} | {us(m['both'])} | "
                        f"{median(ratios_one):.1f}x | {median(ratios_both):.1f}x | "
                        f"{us(m['c3w'])} / {us(m['bothw'])} |")
            print(rows[-1], flush=True)
    return rows, raw


def _cdd_both_v(a):
    F, E = vrep_to_hrep(a, [], False)
    return hrep_to_vrep([[-x for x in f] for f in F], E, False)


def _cdd_both_h(a):
    R, L = hrep_to_vrep(a, [], False)
    return vrep_to_hrep(R, L, False)


def us(t: float) -> str:
    return "-" if t != t else f"{t * 1e6:.0f} us"


# --- agreement ---------------------------------------------------------------------------------
def agreement(n: int, seed: int) -> list[str]:
    rows = []
    total = Counter()
    for ineq in (False, True):
        for name in T.FAMILIES:
            t0 = time.perf_counter()
            tally = T.run_family(name, n, seed, ineq)
            tally.pop("examples", None)
            dev = tally.pop("max_deviation", 0.0)
            total.update(tally)
            total["max_deviation"] = max(total.get("max_deviation", 0.0), dev)
            rows.append(f"| {'H' if ineq else 'V'} | {name} | {n} | {tally['agree']} | "
                        f"{tally['cone3error']} | {tally['silent']} | {dev:.1e} |")
            print(rows[-1], f"({time.perf_counter() - t0:.0f} s)", flush=True)
    rows.append(f"| all | | {2 * n * len(T.FAMILIES)} | {total['agree']} | "
                f"{total['cone3error']} | {total['silent']} | {total['max_deviation']:.1e} |")
    return rows


# --- the planar cone: cone3d (as wired in planar.py) against the same on cddlib ---------
def planar_cdd(prob) -> Cone:
    """The planar method with float cddlib for both conversions, as planar.py computed it
    before cone3d (hrep_to_vrep for X, cone_from_vrep for W), on today's helpers."""
    acc = acceleration_constraints(prob)
    rays, lines = hrep_to_vrep(np.asarray(acc.ineq, dtype=float).tolist(),
                               np.asarray(acc.eq, dtype=float).tolist(), False)
    M = np.asarray(prob.M, dtype=float)
    gens = [list(M.dot(np.array(r, dtype=float))) for r in rays]
    gens += np.asarray(force_generators(prob), dtype=float).reshape(-1, 3).tolist()
    lin = [list(M.dot(np.array(v, dtype=float))) for v in lines]
    cone = cone_from_vrep(gens, lin, mode=prob.mode, length_scale=prob.length_scale,
                          method="planar", exact=False)
    if not open_mode_feasible(acc, np.reshape(np.array(rays, dtype=float), (-1, 3)),
                              np.reshape(np.array(lines, dtype=float), (-1, 3)), False):
        return infeasible_cone(cone)
    return cone


def _same_cone(a: Cone, b: Cone) -> bool:
    if a.feasible != b.feasible:
        return False
    x = cone3d.Cone3(a.F_hat, a.E_hat, a.G_hat, a.L_hat)
    y = cone3d.Cone3(b.F_hat, b.E_hat, b.G_hat, b.L_hat)
    return T.agree(x, y, 1e-6)


def planar_table(cases: int, repeats: int, rng) -> list[str]:

    rows = []
    same = Counter()
    before = dict(stats.PLANAR_FALLBACKS)
    for n in range(1, 9):
        per = {"c3": [], "cdd": [], "paper": []}
        r_paper, r_cdd = [], []
        for _ in range(cases):
            _gs, scene, mode = feasible_case(rng, n)
            prob = problem(scene, mode, False)
            same["same" if _same_cone(planar_cone(prob), planar_cdd(prob)) else "differ"] += 1
            t = time_methods({"c3": lambda p=prob: planar_cone(p),
                              "cdd": lambda p=prob: planar_cdd(p),
                              "paper": lambda p=prob: paper_cone(p)}, repeats)
            for k in per:
                per[k].append(t[k][0])
            r_paper.append(t["paper"][0] / t["c3"][0])
            r_cdd.append(t["cdd"][0] / t["c3"][0])
        rows.append(f"| {n} | {us(median(per['c3']))} | {us(median(per['cdd']))} | "
                    f"{us(median(per['paper']))} | {median(r_cdd):.1f}x | "
                    f"{median(r_paper):.1f}x |")
        print(rows[-1], flush=True)
    after = stats.PLANAR_FALLBACKS
    fb = {k: after[k] - before.get(k, 0) for k in after}
    rows.append("")
    rows.append(f"planar.py (cone3d) against the same method on cddlib (F, E, G, lineality "
                f"within 1e-6, same feasibility): {same['same']} of "
                f"{same['same'] + same['differ']} cases agree. planar.py's fallback "
                f"counters over the whole run (all calls, timing loops included): {fb}.")
    return rows


def _step_calls(prob) -> list:
    """planar_cone and each of its float steps, as calls on precomputed inputs."""
    from wrenchcone_ros.core.constraints import ill_conditioned

    acc = acceleration_constraints(prob)
    X = cone3d.from_inequalities(acc.ineq, acc.eq)
    M = np.asarray(prob.M, dtype=float)
    G = np.vstack([X.rays @ M.T, np.asarray(force_generators(prob), dtype=float).reshape(-1, 3)])
    Lx = X.lines @ M.T
    W = cone3d.from_generators(G, Lx)
    return [lambda: planar_cone(prob), lambda: acceleration_constraints(prob),
            lambda: ill_conditioned(prob, acc),
            lambda: cone3d.from_inequalities(acc.ineq, acc.eq),
            lambda: force_generators(prob), lambda: cone3d.from_generators(G, Lx),
            lambda: open_mode_feasible(acc, X.rays, X.lines, False),
            lambda: Cone(prob.mode, True, W.F, W.E, W.rays, W.lines, 1.0, "planar", False)]


def breakdown_table(cases: int, rng) -> list[str]:
    """Where planar_cone's time goes: median CPU time of each step over random cases."""

    steps = {k: [] for k in ("planar_cone (total)", "acceleration_constraints",
                             "ill_conditioned", "X = cone3d.from_inequalities",
                             "force_generators", "W = cone3d.from_generators",
                             "open_mode_feasible", "Cone(...)")}
    for n in range(2, 9):
        for _ in range(cases):
            _gs, scene, mode = feasible_case(rng, n)
            fns = _step_calls(problem(scene, mode, False))
            t = time_methods(dict(zip(steps, fns)), 3)
            for k in steps:
                steps[k].append(t[k][0])
    return [f"| {k} | {us(median(v))} |" for k, v in steps.items()]


# --- output ------------------------------------------------------------------------------------
def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="few cases, short agreement run")
    ap.add_argument("--no-write", action="store_true", help="print only")
    ap.add_argument("--cases", type=int, default=None)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--agree", type=int, default=None, help="cones per family and input")
    ap.add_argument("--seed", type=int, default=12345)
    args = ap.parse_args()
    cases = args.cases or (3 if args.quick else 15)
    n_agree = args.agree or (50 if args.quick else 1000)
    rng = np.random.default_rng(args.seed)
    facts = machine_facts()

    print("conversions (CPU time per call)")
    conv, _ = conversion_table(cases, args.repeats, rng)
    print("planar cone")
    plan = planar_table(max(2, cases // 2), args.repeats, rng)
    print("planar_cone breakdown")
    brk = breakdown_table(max(2, cases // 5), rng)
    print("\n".join(brk))
    print("agreement with exact cddlib")
    agr = agreement(n_agree, args.seed)
    load_end = harness.loadavg()

    text = "\n".join([
        BEGIN,
        f"Command: `python benchmarks/cone3d_vs_cdd.py{' --quick' if args.quick else ''}`; "
        f"{cases} cases per row, {args.repeats} interleaved repeats.",
        "",
        facts_markdown(facts, load_end),
        "",
        "### Time per conversion (CPU time, median over cases)",
        "",
        "cone3d gives both representations; \"cdd 1\" is one float cddlib conversion "
        "(one representation), \"cdd both\" the two conversions the core needs for a "
        "canonical cone. Ratios are medians of per-case ratios (cdd time / cone3d time). "
        "Last column: wall-clock medians, cone3d / cdd both.",
        "",
        "| input | n | cone3d | cdd 1 | cdd both | cdd 1 / cone3d | cdd both / cone3d "
        "| wall: cone3d / cdd both |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
        *conv,
        "",
        "### Planar cone: planar.py (on cone3d) against the same method on cddlib",
        "",
        "Median CPU time per cone over random feasible (scene, mode) cases with n fixels "
        "(scenes of benchmarks/cone_timing.py). planar.py: `planar_cone` as committed "
        "(cone3d, with its guards and fallbacks); cddlib: `planar_cdd` in the benchmark "
        "script, the same method with float cddlib conversions as before cone3d; paper: "
        "`paper_cone` as committed. Ratios are medians of per-case ratios (other / "
        "planar.py).",
        "",
        "| n fixels | planar.py (cone3d) | planar on cddlib | paper | cddlib / cone3d "
        "| paper / cone3d |",
        "| --- | --- | --- | --- | --- | --- |",
        *plan,
        "",
        "Where planar_cone's time goes (median CPU time per step over random cases "
        "with 2..8 fixels; the steps are timed separately, so they need not add up):",
        "",
        "| step | median |",
        "| --- | --- |",
        *brk,
        "",
        "### Agreement with exact cddlib",
        "",
        f"{n_agree} random cones per family and input kind (V: from_generators, H: "
        "from_inequalities; families in test/helpers/cone3d_cases.py). agree: same counts and "
        "facets/rays within 1e-6 (one-to-one), same E and lineality spaces; Cone3Error: "
        "the self-check refused (the caller falls back to exact cddlib); silent: returned "
        "but different (must be 0). Max deviation: the largest distance between paired "
        "unit rows (or projector entries) among agreeing cones.",
        "",
        "| input | family | cones | agree | Cone3Error | silent | max deviation |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        *agr,
        END,
    ])
    harness.publish_generated(text, OUT, "cone3d_vs_cdd.py", "cone3d", facts,
                              {"conversions": conv, "planar": plan, "breakdown": brk,
                               "agreement": agr}, not args.no_write)


if __name__ == "__main__":
    main()
