#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Time per cone for n = 1..8 fixels, every method float and exact, against the baselines.

    python benchmarks/cone_timing.py            # full run (a few minutes), writes docs/benchmarks.md
    python benchmarks/cone_timing.py --quick    # a short smoke run (still writes the file)
    python benchmarks/cone_timing.py --no-write # print only

What is timed (wall clock, ``time.perf_counter``, one process, no warm caches beyond
Python's own):

* every ``(method, exact)`` that ``wrench_cone`` offers (read from ``methods.METHODS`` at run
  time): one call ``wrench_cone(scene, mode, exact=..., method=...)`` = geometry,
  matrices, cddlib conversions, canonical form, feasibility of the open mode;
* "LP per query": one ``lp_check.lp_consistent(scene, mode, g, feasibility=...)`` (scipy
  HiGHS; the mode's feasibility LP solved once beforehand, not timed), what a
  user without cones would write;
* "cached contains()": ``cone.contains(g)`` on a cone built once (default method);
  "cached margin()" likewise;
* ``classify.consistent_modes(scene, g)`` (all modes of the scene for one wrench, cold:
  a new classifier per call) and a warm ``ModeClassifier`` (cones cached), when
  :mod:`wrenchcone_ros.core.classify` exists.

Cases: for each n, random valid scenes from ``test/strategies.random_scene`` (discs,
convex and non-convex polygons, points and pins, random poses) with a random valid mode
string drawn until the open mode is feasible (``lp_mode_feasible``). For each case every
method is called ``REPEATS`` times, interleaved (method A, B, C, A, B, C, ...) so that
background load hits all methods alike; the case's time is the median of its repeats,
the table shows the median over cases, and ratios are medians over cases of the
per-case ratio (same case, same run).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)
from harness import fmt_ratio, fmt_time, median, time_once, time_per_call  # noqa: E402
from harness.core import cone_methods, default_method, feasible_case, paper_raw  # noqa: E402,E501

from helpers.strategies import random_wrench  # noqa: E402

from wrenchcone_ros.core import wrench_cone  # noqa: E402
from wrenchcone_ros.core.lp_check import lp_consistent, lp_mode_feasible  # noqa: E402

OUT = harness.DOCS / "benchmarks.md"
COMMAND = "python benchmarks/cone_timing.py"


def _classify_module():
    try:
        return importlib.import_module("wrenchcone_ros.core.classify")
    except ImportError:
        return None


def measure_case(rng, scene, mode, n, methods, args, classify, per_case, ratios, cls) -> None:
    """Time every method, the baselines and the classifier on one (scene, mode)."""
    for _ in range(2):  # warm-up (imports, first-call caches)
        for _label, build, ex in methods:
            if not ex:
                build(scene, mode)
    samples = {m[0]: [] for m in methods}
    for rep in range(args.repeats):
        for label, build, ex in methods:
            if ex and (rep >= args.exact_repeats or n > args.exact_max_n):
                continue
            samples[label].append(time_once(lambda build=build: build(scene, mode)))
    for label in samples:
        per_case[label].append(median(samples[label]) if samples[label] else None)
    ref = median(samples["paper-float"])
    raw = median(samples["paper-float-raw"])
    for label in samples:
        if samples[label]:
            ratios[label].append(ref / median(samples[label]))
            ratios["raw:" + label].append(raw / median(samples[label]))
    # baselines: LP per query vs cached contains() / margin() of the default cone
    cone = wrench_cone(scene, mode)
    per_case["n_faces"].append(cone.F_hat.shape[0])
    gs_w = [random_wrench(rng, scene.length_scale) for _ in range(args.queries)]
    # one LP per query: the mode's feasibility LP is solved once, outside the timing
    feas = lp_mode_feasible(scene, mode)
    lp_consistent(scene, mode, gs_w[0], feasibility=feas)  # warm-up
    t_lp = median([time_once(lambda g=g: lp_consistent(scene, mode, g, feasibility=feas))
                   for g in gs_w])
    t_in = median([time_per_call(lambda g=g: cone.contains(g)) for g in gs_w])
    t_mg = median([time_per_call(lambda g=g: cone.margin(g)) for g in gs_w])
    per_case["lp"].append(t_lp)
    per_case["contains"].append(t_in)
    per_case["margin"].append(t_mg)
    ratios["lp/contains"].append(t_lp / t_in)
    if classify is not None and 2 <= n <= args.classify_max_n:
        g = gs_w[0]
        cold = [time_once(lambda: classify.consistent_modes(scene, g))
                for _ in range(args.classify_repeats)]
        clf = classify.ModeClassifier(scene)
        clf.consistent_modes(g)  # fills the cone cache
        warm = [time_once(lambda g2=g2: clf.consistent_modes(g2)) for g2 in gs_w]
        cls[0].append(median(cold))
        cls[1].append(median(warm))
        cls[2].append(len(classify.consistent_modes(scene, g)))


def build_methods() -> list:
    """(label, build(scene, mode), exact): every method of methods.METHODS float and exact,
    plus "paper-float-raw" (the paper's algorithm without the core's verification)."""
    out = [(label, (lambda s, m, meth=meth, ex=ex: wrench_cone(s, m, exact=ex, method=meth)),
            ex) for label, meth, ex in cone_methods()]
    out.insert(1, ("paper-float-raw", paper_raw, False))
    return out


def run(args) -> dict:
    rng = np.random.default_rng(args.seed)
    methods = build_methods()
    default = default_method()
    classify = _classify_module()
    ns = list(range(1, args.max_n + 1))
    results: dict = {"methods": [m[0] for m in methods], "rows": {}, "classify": {}}
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        def tqdm(x, **_):
            return x

    total = len(ns) * args.cases
    bar = tqdm(total=total, desc="cone timing", unit="case", disable=args.no_progress)
    for n in ns:
        per_case: dict[str, list] = {m[0]: [] for m in methods}
        per_case.update({"lp": [], "contains": [], "margin": [], "n_faces": []})
        ratios: dict[str, list] = {m[0]: [] for m in methods}
        ratios.update({"raw:" + m[0]: [] for m in methods})
        ratios["lp/contains"] = []
        cls_cold, cls_warm, cls_modes = [], [], []
        for _case in range(args.cases):
            gs, scene, mode = feasible_case(rng, n)
            measure_case(rng, scene, mode, n, methods, args, classify, per_case, ratios,
                         (cls_cold, cls_warm, cls_modes))
            bar.update(1)
        row = {label: median(per_case[label]) for label, _, _ in methods}
        row.update({k: median(per_case[k]) for k in ("lp", "contains", "margin", "n_faces")})
        row["ratio"] = {k: median(v) for k, v in ratios.items()}
        row["ratio_min"] = {k: (min(v) if v else float("nan")) for k, v in ratios.items()}
        results["rows"][n] = row
        if cls_cold:
            results["classify"][n] = {"cold": median(cls_cold), "warm": median(cls_warm),
                                      "cold_max": max(cls_cold), "modes": median(cls_modes)}
    bar.close()
    results["default"] = default
    return results


def render(results: dict, args, facts: dict, load_end: str, elapsed: float) -> str:
    methods = results["methods"]
    rows = results["rows"]
    default = results["default"]
    out = []
    out.append("# Benchmarks: time per cone, per query and per classification\n")
    out.append("Generated by `benchmarks/cone_timing.py` from a real run; do not edit by hand. "
               "Regenerate with\n")
    out.append(f"    {COMMAND}{' --quick' if args.quick else ''}\n")
    out.append("(`python` with numpy, scipy, pycddlib and tqdm: the `.venv` that `make test` "
               f"builds will do. Full run: {args.cases} cases per n, about "
               f"{elapsed / 60:.0f} min here.)\n")
    out.append("## Machine\n")
    out.append(harness.facts_markdown(facts, load_end) + "\n")
    out.append("The machine has 2 cores and other jobs ran at the same time (see the load "
               "averages): absolute times are indicative, the ratios are taken within one run "
               "and one case (same scene, same mode, interleaved repeats) and are the figures to "
               "quote.\n")
    out.append("## Method\n")
    out.append(
        f"For each n = 1..{args.max_n}: {args.cases} random valid scenes "
        "(`test/strategies.random_scene`: discs, convex and non-convex polygons, point fixels "
        "and pins, random poses, mu including 0) each with a random valid mode string whose "
        "open mode is feasible (drawn until `lp_mode_feasible` says so; feasible modes are "
        "dominated by 's' and 'a' letters as n grows, since most random strings over many "
        "contacts are impossible). Per case each method runs "
        f"{args.repeats} times (exact: {args.exact_repeats}), interleaved; a case's time is the "
        "median of its repeats; the table shows the median over cases. Ratios are the median "
        "over cases of (paper-float time / method time) for the same case. "
        f"Exact arithmetic is timed up to n = {args.exact_max_n}.\n")
    out.append(
        "A cone call is `wrench_cone(scene, mode, exact=..., method=...)` from a loaded "
        "`Scene`: contact frames (cached in the scene), matrices, cone conversions, "
        "canonical form and the open-mode feasibility check. 'LP per query' is one "
        "`lp_check.lp_consistent(scene, mode, g, feasibility=...)` (scipy HiGHS, one LP: the "
        "mode's feasibility LP is solved once beforehand and not timed). 'contains()' and "
        "'margin()' "
        f"are calls on a cone built once with the default method ('{default}'), i.e. what a "
        "controller re-querying a cached cone pays.\n")
    out.append("## Time per cone (median over cases)\n")
    head = ["n", *methods, "LP per query", "cached contains()", "cached margin()", "faces"]
    out.append("| " + " | ".join(head) + " |")
    out.append("|" + "---|" * len(head))
    for n, r in rows.items():
        cells = [str(n)] + [fmt_time(r[m]) for m in methods] + [
            fmt_time(r["lp"]), fmt_time(r["contains"]), fmt_time(r["margin"]),
            f"{r['n_faces']:.0f}"]
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
    out.append("## Speed-up over paper-float, and LP per query over cached contains()\n")
    out.append("Median over cases of the per-case ratio (in brackets: the worst case). "
               "'paper-float' is the core's paper method, which verifies its float result "
               "(NNLS soundness check and comparison with the planar closure, so it builds the "
               "planar cone too); 'paper-float-raw' is the same algorithm without that "
               "verification (`benchmarks/harness/core.py`, `paper_raw`), the fair reference for the "
               "speed of the paper's algorithm.\n")
    fastm = [m for m in methods if m.endswith("-float") and not m.startswith("paper")]
    rhead = ["n", *[m for m in methods if m != "paper-float"],
             *[f"{m} vs paper-float-raw" for m in fastm], "LP / contains()"]
    out.append("| " + " | ".join(rhead) + " |")
    out.append("|" + "---|" * len(rhead))
    for n, r in rows.items():
        cells = [str(n)]
        for m in methods:
            if m == "paper-float":
                continue
            cells.append(f"{fmt_ratio(r['ratio'][m])} ({fmt_ratio(r['ratio_min'][m])})"
                         if r["ratio"][m] == r["ratio"][m] else "-")
        for m in fastm:
            cells.append(f"{fmt_ratio(r['ratio']['raw:' + m])} "
                         f"({fmt_ratio(r['ratio_min']['raw:' + m])})")
        cells.append(f"{fmt_ratio(r['ratio']['lp/contains'])} "
                     f"({fmt_ratio(r['ratio_min']['lp/contains'])})")
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
    if results["classify"]:
        out.append("## Classifying one wrench over all modes (`classify.consistent_modes`)\n")
        out.append("Cold: `consistent_modes(scene, g)` (builds every cone it needs). Warm: a "
                   "`ModeClassifier` reused for a new wrench (cones cached). Median over cases; "
                   "'matched' is the median number of modes the wrench was consistent with.\n")
        out.append("| n | cold | worst cold | warm | matched |")
        out.append("|---|---|---|---|---|")
        for n, c in results["classify"].items():
            out.append(f"| {n} | {fmt_time(c['cold'])} | {fmt_time(c['cold_max'])} | "
                       f"{fmt_time(c['warm'])} | {c['modes']:.0f} |")
        out.append("")
    out.append("## Targets, from this run\n")
    out.append(targets_markdown(results))
    return "\n".join(out) + "\n"


def targets_markdown(results: dict) -> str:
    rows = results["rows"]
    methods = results["methods"]
    fast = [m for m in methods if m.endswith("-float") and not m.startswith("paper")]
    lines = []
    for m in fast:
        for key, ref in ((m, "paper-float"), ("raw:" + m, "paper-float-raw")):
            rs = {n: rows[n]["ratio"][key] for n in rows if 2 <= n <= 6}
            if not rs:
                continue
            worst = min(rs.values())
            verdict = ("met" if worst >= 5 else
                       f"missed (worst n: {worst:.1f}x, {worst / 5:.0%} of target)")
            note = (" (the core's paper-float verifies its result, which includes building the "
                    "planar cone: this ratio overstates the speed-up)" if ref == "paper-float"
                    else " (the paper's algorithm alone: the fair comparison)")
            lines.append(f"- {m} >= 5x faster than {ref} for n = 2..6: median ratios "
                         + ", ".join(f"n={n}: {fmt_ratio(r)}" for n, r in rs.items())
                         + f" -> {verdict}{note}.")
    lc = {n: rows[n]["ratio"]["lp/contains"] for n in rows}
    worst = min(lc.values())
    lines.append("- cached contains() >= 100x faster than an LP per query: median ratios "
                 + ", ".join(f"n={n}: {fmt_ratio(r)}" for n, r in lc.items())
                 + f" -> {'met' if worst >= 100 else 'missed'} (worst n: {fmt_ratio(worst)}).")
    if 4 in results["classify"]:
        c = results["classify"][4]
        lines.append(f"- all modes of a 4-fixel scene classified in <= 20 ms: median cold "
                     f"{fmt_time(c['cold'])} (worst case {fmt_time(c['cold_max'])}), warm "
                     f"{fmt_time(c['warm'])} -> "
                     f"{'met' if c['cold'] <= 0.02 else 'missed'} (median, cold).")
    else:
        lines.append("- all modes of a 4-fixel scene in <= 20 ms: not measured in this run "
                     "(classify.py absent, or n = 4 not included).")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run (few cases)")
    ap.add_argument("--seed", type=int, default=20261122)
    ap.add_argument("--max-n", type=int, default=8)
    ap.add_argument("--cases", type=int, default=None, help="cases per n (default 10, quick 3)")
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--exact-repeats", type=int, default=3)
    ap.add_argument("--exact-max-n", type=int, default=8)
    ap.add_argument("--queries", type=int, default=5, help="wrenches per case for the baselines")
    ap.add_argument("--classify-max-n", type=int, default=6)
    ap.add_argument("--classify-repeats", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--no-progress", action="store_true")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    if args.cases is None:
        args.cases = 3 if args.quick else 10
    if args.quick:
        args.repeats, args.exact_repeats = 3, 1
    facts = harness.machine_facts()
    t0 = time.time()
    results = run(args)
    elapsed = time.time() - t0
    text = render(results, args, facts, harness.loadavg(), elapsed)
    print(text)
    if not args.no_write:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text)
        print(f"wrote {args.out}", file=sys.stderr)
        # when and where it ran (kept out of the doc)
        harness.write_json(harness.RESULTS / "cone_timing.json", facts,
                           {"minutes": elapsed / 60, "results": results})
    return 0


if __name__ == "__main__":
    sys.exit(main())
