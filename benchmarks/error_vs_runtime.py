#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Error against run time, on normal, stiff and extreme scene families.

    python benchmarks/error_vs_runtime.py           # full run (~5-10 min on 2 cores)
    python benchmarks/error_vs_runtime.py --quick   # a short run (~1 min)

Writes docs/error_vs_runtime.md (tables, definitions, fallback counts) and
docs/error_vs_runtime.png (log-log: error against time per call, one marker per method
and family). Ground truth is exact rational arithmetic: ``wrench_cone(scene, mode,
exact=True, method="paper")`` (cddlib GMP, Fractions from the scene's numbers as
written); membership of a sampled wrench in the exact cone is decided in Fractions too.

Methods compared, in one run, on the same (scene, mode) pairs:

* every ``(method, exact)`` that ``wrench_cone`` offers (``methods.METHODS``, read at run
  time): "paper-float", "paper-exact", "planar-float", "planar-exact", ...;
* "<method>-float-unscaled" variants: the same float pipeline fed the *dimensional*
  problem (J with torque rows in N m per N, M = diag(m, m, I)) instead of the
  nondimensional one (J_hat, diag(1, 1, I / (m L^2))), the cone mapped back afterwards:
  what the code would do without nondimensionalisation;
* "paper-float-raw": the paper's algorithm in float without the core's verification
  (``harness.core.paper_raw``), i.e. float cddlib unchecked;
* "LP per query": ``lp_check.lp_consistent`` (scipy HiGHS) on a subset of the samples; one
  LP per query (the mode's feasibility LP is solved once per pair, not timed).

See the module-level constants for the sample sizes, the band and the face-matching
angle; docs/error_vs_runtime.md restates every definition.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
import traceback
from collections import defaultdict
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)
from helpers.families import BAND, FAMILIES, band_for, exact_contains, sample_directions, si_wrench  # noqa: E402,E501
from harness import fmt_time, median  # noqa: E402
from harness.core import cone_methods, core_fallbacks, default_method, paper_raw  # noqa: E402

from wrenchcone_ros.core import load_scene, wrench_cone  # noqa: E402
from wrenchcone_ros.core.batch import METHODS  # noqa: E402
from wrenchcone_ros.core.cones import Cone, _orthonormal_rows  # noqa: E402
from wrenchcone_ros.core.dynamics import problem  # noqa: E402
from wrenchcone_ros.core.lp_check import lp_consistent, lp_mode_feasible  # noqa: E402

OUT_MD = harness.DOCS / "error_vs_runtime.md"
OUT_PNG = harness.DOCS / "error_vs_runtime.png"
OUT_JSON = harness.RESULTS / "error_vs_runtime.json"
COMMAND = "python benchmarks/error_vs_runtime.py"

#: BAND (test/helpers/families.py, 1e-8, dimensionless): a sampled unit nondimensional direction u
#: with |exact margin(u)| < BAND may be classified either way; disagreements there are
#: reported separately.
#: Two unit face normals "match" when they are at most this far apart (radians).
FACE_MATCH = 1e-6
#: Ground truth method.
TRUTH = ("paper", True)


# ----------------------------------------------------------------------------- variants


def _unit_rows(rows: np.ndarray) -> np.ndarray:
    if rows.shape[0] == 0:
        return rows
    n = np.linalg.norm(rows, axis=1)
    keep = n > 0
    return rows[keep] / n[keep, None]


def unscaled_cone(scene, mode: str, method: str) -> Cone:
    """Float ``method`` run on the dimensional problem, mapped to the nondimensional metric.

    Emulates the code without nondimensionalisation: cddlib and every clean-up tolerance
    of the float pipeline see J in (N, N, N m) per N and M = diag(m, m, I) in SI.
    The result (a cone of SI wrenches) is mapped to g_hat = (f_x, f_y, tau / L): face rows
    F_hat = F_SI diag(1, 1, L), generators G_hat = G_SI diag(1, 1, 1/L), renormalised, so
    contains() and margin() are measured in the same metric as every other method.
    """
    prob = problem(scene, mode, False)
    try:  # the core's guard decides on the nondimensional rows and recomputes from the
        # scene exactly; emulate it the same way so that only the float conversions differ
        from wrenchcone_ros.core.constraints import acceleration_constraints, ill_conditioned

        if ill_conditioned(prob, acceleration_constraints(prob)):
            return wrench_cone(scene, mode, method=method)
    except ImportError:  # a core without the guard
        pass
    L = float(prob.length_scale)
    J = np.array(prob.J, dtype=float)
    J[2, :] *= L
    m, inertia = float(scene.workpiece.mass), float(scene.workpiece.inertia)
    M = np.diag([m, m, inertia])
    dims = {"J": J, "M": M, "length_scale": 1.0}
    if hasattr(prob, "scene"):  # no exact recomputation from the (nondimensional) scene:
        dims["scene"] = None    # exact fallbacks then use this dimensional data
    cone = METHODS[method](replace(prob, **dims))
    s = np.array([1.0, 1.0, L])
    E = _orthonormal_rows(cone.E_hat * s) if cone.feasible else np.eye(3)
    F = _unit_rows(cone.F_hat * s)
    if E.shape[0] and F.shape[0]:
        F = _unit_rows(F - (F @ E.T) @ E)
    return Cone(mode, cone.feasible, F, E, _unit_rows(cone.G_hat / s),
                _orthonormal_rows(cone.L_hat / s), L, f"{method}-unscaled", False)


#: Counters of the proposed guard (``planar-float-guarded``): builds, and builds computed
#: exactly because two acceleration rows are nearly (not exactly) parallel.
VERIFY_STATS = {"builds": 0, "exact_ill_conditioned": 0}
VERIFY_ANGLE = 1e-4  # rad: acceleration rows closer than this -> whole cone exact


def _unit_list(rows) -> np.ndarray:
    a = np.array([[float(x) for x in r] for r in rows], dtype=float).reshape(-1, 3)
    n = np.linalg.norm(a, axis=1) if a.shape[0] else np.zeros(0)
    return a[n > 0] / n[n > 0, None] if a.shape[0] else a


def nearly_parallel_rows(scene, mode: str, angle: float = VERIFY_ANGLE) -> bool:
    """Whether two acceleration rows of the mode (unit, up to sign) are closer than
    ``angle`` but not exactly parallel: nearly coincident lines of action, where the
    acceleration cone X (and the feasibility of the open mode) is decided by differences
    far below the rounding of the float geometry (error ~ 1e-16 / angle)."""
    from wrenchcone_ros.core.constraints import acceleration_constraints

    acc = acceleration_constraints(problem(scene, mode, False))
    rows = _unit_list(list(acc.ineq) + list(acc.eq))
    if rows.shape[0] < 2:
        return False
    # |a -+ b| is accurate for tiny angles; exactly equal rows (two fixels on one line of
    # action, e.g. tangent rows on one flat edge) are harmless and excluded
    d = np.minimum(np.linalg.norm(rows[:, None] - rows[None], axis=2),
                   np.linalg.norm(rows[:, None] + rows[None], axis=2))
    np.fill_diagonal(d, np.inf)
    return bool(np.any((d > 0) & (d < angle)))


def guarded_default(scene, mode: str) -> Cone:
    """A sketch of the fix proposed to the lead (not in the core): the default float
    method, except that the cone is computed exactly from the scene (``exact=True``) when
    :func:`nearly_parallel_rows` says the acceleration rows are ill-conditioned."""
    VERIFY_STATS["builds"] += 1
    if nearly_parallel_rows(scene, mode):
        VERIFY_STATS["exact_ill_conditioned"] += 1
        return wrench_cone(scene, mode, exact=True)
    return wrench_cone(scene, mode)


def _fallback_count() -> int:
    """The core's float -> exact fallbacks so far (every counter the core has), including
    cones computed exactly because their acceleration rows are nearly parallel."""
    c = core_fallbacks()
    return c[1] + c[2]


def _float_conversions() -> int:
    return core_fallbacks()[0]


def variants() -> list[tuple[str, object, bool]]:
    """(label, build(scene, mode) -> Cone, exact) for every cone-producing variant."""
    out = []
    for label, meth, ex in cone_methods():
        out.append((label, (lambda s, m, meth=meth, ex=ex:
                            wrench_cone(s, m, exact=ex, method=meth)), ex))
    for meth in sorted(METHODS, key=lambda m: (m != "paper", m)):
        out.append((f"{meth}-float-unscaled",
                    (lambda s, m, meth=meth: unscaled_cone(s, m, meth)), False))
    out.append(("paper-float-raw", paper_raw, False))
    return out


# ----------------------------------------------------------------------------- errors


def _angles(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Angles (rad) between unit rows of A and B, |A| x |B|, accurate for tiny angles."""
    d = np.linalg.norm(A[:, None, :] - B[None, :, :], axis=2)
    return 2.0 * np.arcsin(np.clip(d / 2.0, 0.0, 1.0))


def face_error(c: Cone, ex: Cone) -> dict:
    """Largest angle from a computed face normal to the nearest exact one, and the number
    of missing (exact faces with no computed face within FACE_MATCH) and extra faces.
    Equalities: a different number of equality rows counts as missing/extra faces; equal
    numbers contribute the largest principal angle between the two row spaces."""
    if c.feasible != ex.feasible:
        return {"feasible_mismatch": True, "angle": math.nan, "missing": 0, "extra": 0}
    if not ex.feasible:
        return {"feasible_mismatch": False, "angle": 0.0, "missing": 0, "extra": 0}
    A, B = c.F_hat, ex.F_hat
    angle, missing, extra = 0.0, 0, 0
    if A.shape[0] and B.shape[0]:
        ang = _angles(A, B)
        near_a = ang.min(axis=1)
        near_b = ang.min(axis=0)
        angle = float(near_a.max())
        extra = int(np.sum(near_a > FACE_MATCH))
        missing = int(np.sum(near_b > FACE_MATCH))
    else:
        extra, missing = A.shape[0], B.shape[0]
    ea, eb = c.E_hat.shape[0], ex.E_hat.shape[0]
    if ea != eb:
        extra += max(0, ea - eb)
        missing += max(0, eb - ea)
    elif ea:
        from scipy.linalg import subspace_angles

        angle = max(angle, float(np.max(subspace_angles(c.E_hat.T, ex.E_hat.T))))
    return {"feasible_mismatch": False, "angle": angle, "missing": missing, "extra": extra}


# ----------------------------------------------------------------------------- one case


def run_case(case, mode: str, rng, args, var) -> dict:
    """Everything measured on one (scene, mode)."""
    scene = load_scene(case.data)
    L = scene.length_scale
    t0 = time.perf_counter()
    truth = wrench_cone(scene, mode, exact=TRUTH[1], method=TRUTH[0])
    t_truth = time.perf_counter() - t0
    target = truth if truth.feasible else truth.closure
    U = sample_directions(rng, target, args.uniform, args.boundary)
    n_u = args.uniform
    inside = np.array([exact_contains(truth, u) for u in U])
    G = [si_wrench(u, L) for u in U]
    m_exact = np.array([truth.margin(g) for g in G])
    band = band_for(scene)
    in_band = np.abs(m_exact) < band
    if not truth.feasible:
        in_band[:] = False  # an impossible mode has no boundary: every wrench is outside
    rec = {"family": case.family, "param": case.param, "mode": mode, "n": scene.n_fixels,
           "band": band,
           "feasible": bool(truth.feasible), "faces": int(truth.F_hat.shape[0]),
           "eq": int(truth.E_hat.shape[0]), "samples": len(U), "n_uniform": n_u,
           "in_band": int(in_band.sum()), "methods": {}}
    for label, build, ex in var:
        f0 = _fallback_count() + VERIFY_STATS["exact_ill_conditioned"]
        times = []
        err = None
        cone = None
        reps = 1 if ex else args.repeats
        for _ in range(reps):
            t0 = time.perf_counter()
            try:
                cone = build(scene, mode)
            except Exception as exc:  # a crash is a finding, not a reason to stop
                err = f"{type(exc).__name__}: {exc}"
                break
            times.append(time.perf_counter() - t0)
        if label == "paper-exact" and times:
            times.append(t_truth)
        fb = _fallback_count() + VERIFY_STATS["exact_ill_conditioned"] - f0
        if err is not None or cone is None:
            rec["methods"][label] = {"error": err or "no result", "time": median(times)}
            continue
        got = np.array([cone.contains(g) for g in G])
        m = np.array([cone.margin(g) for g in G])
        wrong = got != inside
        fe = face_error(cone, truth)
        bad = []
        for k in np.flatnonzero(wrong & ~in_band)[:3]:
            bad.append({"u": U[k].tolist(), "g": G[k].tolist(), "exact": bool(inside[k]),
                        "method": bool(got[k]), "exact_margin": float(m_exact[k])})
        out_idx = np.flatnonzero(wrong & ~in_band)
        rec["methods"][label] = {
            "time": median(times), "fallbacks": fb / max(1, reps),
            "worst_wrong": float(np.max(np.abs(m_exact[out_idx]))) if out_idx.size else 0.0,
            "wrong_out": int(np.sum(wrong & ~in_band)),
            "wrong_in": int(np.sum(wrong & in_band)),
            "wrong_out_uniform": int(np.sum(wrong[:n_u] & ~in_band[:n_u])),
            "margin_err": float(np.max(np.abs(m - m_exact))) if len(m) else 0.0,
            "feasible": bool(cone.feasible), **fe, "bad": bad,
        }
    # LP per query on a subset: the first lp_uniform uniform and lp_boundary boundary samples
    idx = list(range(min(args.lp_uniform, n_u))) + list(
        range(n_u, n_u + min(args.lp_boundary, len(U) - n_u)))
    times, wrong_out, wrong_in, bad, worst = [], 0, 0, [], 0.0
    feas = None  # the mode's feasibility LP: solved once (first query), reused after
    for k in idx:
        t0 = time.perf_counter()
        try:
            if feas is None:
                feas = lp_mode_feasible(scene, mode)
                t0 = time.perf_counter()
            ans = lp_consistent(scene, mode, G[k], feasibility=feas).consistent
        except Exception as exc:
            rec["methods"]["LP per query"] = {"error": f"{type(exc).__name__}: {exc}"}
            break
        times.append(time.perf_counter() - t0)
        if ans != inside[k]:
            if in_band[k]:
                wrong_in += 1
            else:
                wrong_out += 1
                worst = max(worst, abs(float(m_exact[k])))
                if len(bad) < 3:
                    bad.append({"u": U[k].tolist(), "g": G[k].tolist(), "exact": bool(inside[k]),
                                "method": bool(ans), "exact_margin": float(m_exact[k])})
    else:
        sel_band = in_band[idx]
        rec["methods"]["LP per query"] = {
            "time": median(times), "wrong_out": wrong_out, "wrong_in": wrong_in,
            "worst_wrong": worst, "samples": len(idx), "in_band": int(sel_band.sum()),
            "bad": bad,
            "fallbacks": 0, "angle": math.nan, "missing": 0, "extra": 0,
            "margin_err": math.nan, "feasible_mismatch": False}
    return rec


# ----------------------------------------------------------------------------- aggregate


def aggregate(records: list[dict], labels: list[str]) -> dict:
    """Per (family, method): totals and worst values."""
    agg: dict = defaultdict(lambda: defaultdict(lambda: {
        "cases": 0, "samples": 0, "in_band": 0, "wrong_out": 0, "wrong_in": 0,
        "feas_mismatch": 0, "angle": 0.0, "missing": 0, "extra": 0, "margin_err": 0.0,
        "times": [], "fallbacks": 0.0, "fb_times": [], "nofb_times": [], "errors": 0,
        "angle_cases": 0, "worst_wrong": 0.0}))
    for r in records:
        for label in labels:
            mr = r["methods"].get(label)
            if mr is None:
                continue
            a = agg[r["family"]][label]
            a["cases"] += 1
            if "error" in mr:
                a["errors"] += 1
                continue
            n = mr.get("samples", r["samples"])
            a["samples"] += n
            a["in_band"] += mr.get("in_band", r["in_band"])
            a["wrong_out"] += mr["wrong_out"]
            a["wrong_in"] += mr["wrong_in"]
            a["worst_wrong"] = max(a["worst_wrong"], mr.get("worst_wrong", 0.0))
            a["times"].append(mr["time"])
            if mr.get("feasible_mismatch"):
                a["feas_mismatch"] += 1
            if mr["angle"] == mr["angle"]:
                a["angle"] = max(a["angle"], mr["angle"])
                a["angle_cases"] += 1
            a["missing"] += mr["missing"]
            a["extra"] += mr["extra"]
            if mr["margin_err"] == mr["margin_err"]:
                a["margin_err"] = max(a["margin_err"], mr["margin_err"])
            fb = mr.get("fallbacks", 0)
            a["fallbacks"] += fb
            (a["fb_times"] if fb else a["nofb_times"]).append(mr["time"])
    return agg


def _frac(k: int, n: int) -> str:
    if n == 0:
        return "-"
    return "0" if k == 0 else f"{k / n:.2%} ({k}/{n})"


def _sci(x: float) -> str:
    if x != x:
        return "-"
    return "0" if x == 0 else f"{x:.1e}"


# ----------------------------------------------------------------------------- plot


def plot(agg: dict, labels: list[str], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fams = list(agg)
    cmap = plt.get_cmap("tab10")
    colors = {f: cmap(i % 10) for i, f in enumerate(fams)}
    markers = dict(zip(labels, "os^vDP*Xh<>p"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 7.4))
    floors = (1e-6, 1e-17)
    for ax, key, floor, title in (
            (axes[0], "class", floors[0],
             f"classification error outside the band (|margin| >= {BAND:g})"),
            (axes[1], "angle", floors[1], "face error: largest angle to nearest exact face")):
        for f in fams:
            for label in labels:
                a = agg[f].get(label)
                if not a or not a["times"]:
                    continue
                t = median(a["times"])
                if key == "class":
                    n_out = a["samples"] - a["in_band"]
                    y = a["wrong_out"] / n_out if n_out else 0.0
                    if a["feas_mismatch"] and y == 0:
                        y = 0.0
                else:
                    if label == "LP per query":
                        continue
                    y = a["angle"]
                    if a["feas_mismatch"] or a["missing"] or a["extra"]:
                        y = max(y, math.pi / 2)  # topology wrong: drawn at pi/2
                ax.scatter(t, max(y, floor), color=colors[f], marker=markers.get(label, "o"),
                           s=46, alpha=0.8, edgecolors="k", linewidths=0.4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axhline(floor, color="0.6", ls=":", lw=1)
        ax.set_xlabel("time per call (s): one cone build, or one LP query")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel(f"fraction misclassified (0 drawn at {floors[0]:g})")
    axes[1].set_ylabel(f"radians (0 drawn at {floors[1]:g}; missing/extra faces at pi/2)")
    from matplotlib.lines import Line2D

    h1 = [Line2D([], [], ls="", marker=markers.get(m, "o"), color="0.3", label=m)
          for m in labels]
    h2 = [Line2D([], [], ls="", marker="s", color=colors[f], label=f) for f in fams]
    fig.legend(handles=h1, title="method (marker)", fontsize=8, title_fontsize=8,
               loc="lower left", bbox_to_anchor=(0.06, 0.0), ncol=4)
    fig.legend(handles=h2, title="family (colour)", fontsize=8, title_fontsize=8,
               loc="lower right", bbox_to_anchor=(0.98, 0.0), ncol=5)
    fig.suptitle("wrenchcone_ros: error against time per call (exact cddlib GMP = ground truth)")
    fig.tight_layout(rect=(0, 0.14, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------- report


def render(records, rejected, agg, labels, args, facts, load_end, elapsed, fb_global,
           crashes, verify) -> str:
    default = f"{default_method()}-float"
    out = []
    w = out.append
    w("# Error against run time, and numerical stability\n")
    w(f"Generated by `benchmarks/error_vs_runtime.py` from a real run "
      f"({'--quick, ' if args.quick else ''}{len(records)} (scene, mode) pairs, "
      f"{elapsed / 60:.1f} min); do not edit by hand. Regenerate with\n")
    w(f"    {COMMAND}{' --quick' if args.quick else ''}\n")
    w("(any Python with numpy, scipy, pycddlib, matplotlib and tqdm, e.g. the `.venv` that "
      "`make test` builds; `--quick` for a one-minute run). The plot: "
      "[error_vs_runtime.png](error_vs_runtime.png).\n")
    w("## Machine\n")
    w(harness.facts_markdown(facts, load_end) + "\n")
    w("Times are wall-clock medians on a shared 2-core machine with other jobs running: "
      "compare methods within this run, not with other machines.\n")
    w("## Headline\n")
    w(headline(agg, labels))
    w("## Findings (computed from this run)\n")
    w(findings(records, agg, labels, verify))
    w("## Definitions\n")
    w("- **Ground truth**: `wrench_cone(scene, mode, exact=True, method=\"paper\")`: the "
      "paper's algorithm in rational arithmetic (cddlib GMP), from the scene's numbers as "
      "written (floats via their shortest repr; square roots and cos/sin of non-zero angles "
      "rounded once, then carried exactly). Whether a sampled wrench is in the exact cone is "
      "decided in Fractions from its exact face rows (the sample's floats taken exactly). An "
      "impossible open mode contains no wrench.")
    w("- **Samples** (per (scene, mode)): "
      f"{args.uniform} directions uniform on the unit sphere of the nondimensional wrench "
      f"space g_hat = (f_x, f_y, tau / L), plus {args.boundary} near the exact boundary: a "
      "random point of a random face of the exact cone (of its closure for an impossible "
      "mode), pushed off the face by an angle log-uniform in [1e-14, 1e-2] rad in a random "
      "direction. Each method is asked about the SI wrench (f_x, f_y, L u_3).")
    w(f"- **Band**: a sample whose exact margin (angular distance of its unit direction to "
      f"the exact cone's boundary, `Cone.margin` of the exact cone) is below "
      f"**{BAND:g}** in absolute value may be classified either way (contains() itself "
      "accepts 1e-9 outside, and the inputs are rounded to doubles). The band is widened "
      "only where the inputs' own rounding is larger: max(1e-8, 64 eps C / L) with C the "
      "largest world coordinate of the scene (`band_for` in test/helpers/families.py; exact arithmetic reads a "
      "float as its shortest decimal, float arithmetic as the double, up to half an ulp "
      "apart: for the 1e7 m offsets and a 6 cm body that is about 2e-6; for every other "
      "family it is 1e-8). Impossible modes have no boundary: all their samples are outside "
      "the band.")
    w("- **Classification error**: the fraction of samples a method classifies differently "
      "from the exact cone (`cone.contains(g)` against exact membership), counted outside "
      "the band (must be 0 for the default) and inside it (reported, allowed). Inside the "
      "band about half the samples lie outside the exact cone by less than 1e-9, where "
      "contains() accepts by design, so in-band figures near 40-50 % are the tolerance "
      "at work, not an error. **Worst wrong (abs. margin)**: the largest |exact margin| of "
      "a sample misclassified outside the band (1 for a wrong feasibility verdict): the band "
      "a method would need to be error-free.")
    w(f"- **Face error**: the largest angle between a computed unit face normal (nondimensional "
      f"metric) and the nearest exact one; **missing** / **extra** faces: exact faces with no "
      f"computed one within {FACE_MATCH:g} rad, and vice versa; equality rows: a different "
      "number counts as missing/extra, the same number contributes the largest principal "
      "angle between the two row spaces. A method that gets feasibility wrong has no face "
      "error (counted under 'feasibility').")
    w("- **Margin error**: the largest |margin_method(g) - margin_exact(g)| over the samples "
      "(margins are dimensionless, in [-1, 1]).")
    w("- **Time per call**: median wall time of one `wrench_cone` call (float methods: "
      f"median of {args.repeats} repeats per pair; exact: one call) or of one LP query.")
    w("- **Unscaled variants** (`<method>-float-unscaled`): the same float code fed the "
      "dimensional problem (J with torque rows in N m per N, M = diag(m, m, I) in kg and "
      "kg m^2) instead of the nondimensional one (J_hat = diag(1, 1, 1/L) J, M_hat = "
      "diag(1, 1, I/(m L^2))), built with `dataclasses.replace` on the core's `Problem`; "
      "the resulting cone of SI wrenches is mapped to the nondimensional metric "
      "(F_hat = F diag(1, 1, L) renormalised) only to be measured like the others. The "
      "core's guard for nearly parallel acceleration rows (an exact recomputation from the "
      "scene) is applied first, as in the core, so only the float conversions differ; an "
      "exact redo after a failed float self-check uses the dimensional float data. It shows "
      "what nondimensionalisation buys; it is not offered by the API.")
    w(f"- **LP per query**: `lp_check.lp_consistent(scene, mode, g)` (HiGHS, open mode with a "
      f"maximised slack > 1e-7) on the first {args.lp_uniform} uniform and "
      f"{args.lp_boundary} boundary samples of each pair; one LP per query, the mode's "
      "feasibility LP solved once per pair and not timed.")
    w("")
    w("## Per family and method\n")
    w("Classification errors as a fraction of the samples outside / inside the band. "
      "'feasibility': pairs where the method's `cone.feasible` differs from exact. "
      "'crashes': pairs where the method raised.\n")
    head = ["family", "method", "pairs", "time/call", "class. err. outside band",
            "worst wrong (abs. margin)", "class. err. in band", "feasibility",
            "face angle", "missing/extra faces",
            "margin err.", "fallbacks", "crashes"]
    w("| " + " | ".join(head) + " |")
    w("|" + "---|" * len(head))
    for fam in agg:
        for label in labels:
            a = agg[fam].get(label)
            if not a:
                continue
            n_out = a["samples"] - a["in_band"]
            cells = [fam, label if label != default else f"**{label}** (default)",
                     str(a["cases"]), fmt_time(median(a["times"])),
                     _frac(a["wrong_out"], n_out), _sci(a["worst_wrong"]),
                     _frac(a["wrong_in"], a["in_band"]), str(a["feas_mismatch"]),
                     "-" if label == "LP per query" else _sci(a["angle"]),
                     "-" if label == "LP per query" else f"{a['missing']}/{a['extra']}",
                     "-" if label == "LP per query" else _sci(a["margin_err"]),
                     f"{a['fallbacks']:.0f}" if "float" in label else "-",
                     str(a["errors"])]
            w("| " + " | ".join(cells) + " |")
    w("")
    w(f"## Default method ({default}) per family and parameter value\n")
    w(per_param_table(records, default))
    w("## Fallbacks (float cddlib -> exact)\n")
    w(fallback_text(agg, labels, fb_global))
    w(verify_text(verify, agg))
    w("## Scenes refused by `load_scene`\n")
    if rejected:
        w("These scenes were built by the family generators but refused as input (not a "
          "numerical failure of a cone method; listed so no family is silently thinner):\n")
        by = defaultdict(list)
        for c in rejected:
            by[(c.family, c.param)].append(c.rejected)
        for (fam, param), msgs in by.items():
            w(f"- {fam} / {param}: {len(msgs)} refused, e.g. \"{msgs[0]}\"")
        w("")
    else:
        w("None.\n")
    w("## Disagreements with exact arithmetic outside the band\n")
    w(disagreements_text(records, labels, default, crashes))
    return "\n".join(out) + "\n"


def findings(records: list[dict], agg: dict, labels: list[str], verify: dict) -> str:
    """Plain-language summary, every figure computed from this run's records."""
    default = f"{default_method()}-float"
    fams = list(agg)
    out = []

    def bad_pairs(label):
        return [r for r in records if label in r["methods"] and "error" not in r["methods"][label]
                and (r["methods"][label]["wrong_out"] or r["methods"][label].get(
                    "feasible_mismatch"))]

    bp = bad_pairs(default)
    ok = [f for f in fams if not any(r["family"] == f for r in bp)]
    if not bp:
        out.append(f"- The default method ({default}) agrees with exact arithmetic outside the "
                   f"band on all {len(fams)} families.")
    else:
        by = defaultdict(set)
        for r in bp:
            by[r["family"]].add(r["param"])
        feas = sum(1 for r in bp if r["methods"][default].get("feasible_mismatch"))
        out.append(
            f"- The default method ({default}) agrees with exact arithmetic outside the band on "
            f"{len(ok)} of {len(fams)} families ({', '.join(ok)}). It disagrees on "
            + "; ".join(f"{f} ({', '.join(sorted(ps))})" for f, ps in by.items())
            + f": {len(bp)} (scene, mode) pairs, {feas} of them with the wrong feasibility "
            "verdict for the open mode (reproducers at the end).")
    fbp = sum(1 for r in records if r["methods"].get(default, {}).get("fallbacks"))
    if fbp:
        fb_t = [t for f in fams for t in agg[f].get(default, {}).get("fb_times", [])]
        no_t = [t for f in fams for t in agg[f].get(default, {}).get("nofb_times", [])]
        fam_fb = sorted({r["family"] for r in records
                         if r["methods"].get(default, {}).get("fallbacks")})
        out.append(
            f"- The default method fell back to exact arithmetic (a failed float self-check, or "
            f"the core's guard for nearly parallel acceleration rows) on {fbp} of "
            f"{len(records)} pairs ({fbp / max(1, len(records)):.1%}; families "
            f"{', '.join(fam_fb)}); median time per build {fmt_time(median(fb_t))} with a "
            f"fallback against {fmt_time(median(no_t))} without.")
    g = f"{default}-guarded"
    if g in labels and verify.get("builds"):
        gb = bad_pairs(g)
        tg = median([t for f in fams for t in agg[f].get(g, {}).get("times", [])])
        td = median([t for f in fams for t in agg[f].get(default, {}).get("times", [])])
        out.append(
            f"- The proposed guard ({g}: exact when two acceleration rows are nearly but not "
            f"exactly parallel) {'removes every disagreement' if not gb else 'leaves ' + str(len(gb)) + ' pairs wrong'}"
            f"; it computed {verify['exact_ill_conditioned']:.0f} of {verify['builds']:.0f} "
            f"builds exactly ({verify['exact_ill_conditioned'] / verify['builds']:.1%}, mostly "
            f"the coincident, parallel and gaps families); median time per build {fmt_time(tg)} "
            f"against {fmt_time(td)} (the benchmark's sketch recomputes the acceleration rows; "
            "inside the core the check reuses them and costs a few microseconds).")
    for label in labels:
        if not label.endswith("-exact"):
            continue
        a = max((agg[f][label]["angle"] for f in fams if label in agg[f]), default=0.0)
        w = sum(agg[f][label]["wrong_out"] for f in fams if label in agg[f])
        out.append(f"- {label}: no classification error outside the band, largest face angle "
                   f"to the reference {_sci(a)} rad ({'identical cones' if a < 1e-12 else 'check'}"
                   f"{'' if not w else ', ' + str(w) + ' wrong samples'}).")
    pf = "paper-float"
    if pf in labels:
        red = [r for r in records if pf in r["methods"] and "error" not in r["methods"][pf]
               and r["methods"][pf].get("extra") and not r["methods"][pf]["wrong_out"]
               and not r["methods"][pf].get("feasible_mismatch")]
        if red:
            out.append(
                f"- {pf} returns face rows that are not irredundant in {len(red)} pairs (extra "
                f"faces with no classification error: redundant or duplicated rows; families "
                f"{', '.join(sorted({r['family'] for r in red}))}). The face rows should be "
                "irredundant.")
    for base in [lb for lb in labels if lb.endswith("-float")]:
        un = base + "-unscaled"
        if un not in labels:
            continue
        wb = sum(agg[f][base]["wrong_out"] for f in fams if base in agg[f])
        wu = sum(agg[f][un]["wrong_out"] for f in fams if un in agg[f])
        mb = sum(agg[f][base]["missing"] + agg[f][base]["extra"] for f in fams if base in agg[f])
        mu_ = sum(agg[f][un]["missing"] + agg[f][un]["extra"] for f in fams if un in agg[f])
        out.append(f"- Without nondimensionalisation ({un}) against with ({base}): "
                   f"{wu} against {wb} misclassified samples outside the band, {mu_} against "
                   f"{mb} missing/extra faces.")
    lp = "LP per query"
    if lp in labels:
        worst = {f: agg[f][lp]["worst_wrong"] for f in fams if lp in agg[f]}
        finite = [v for v in worst.values() if 0 < v < 1]
        lpb = bad_pairs(lp)
        feas_pairs = [r for r in lpb if not r["feasible"]]
        feas_wrong = len(feas_pairs)
        feas_fams = ", ".join(sorted({r["family"] for r in feas_pairs})) or "none"
        out.append(
            f"- {lp} (scipy HiGHS, slack > 1e-7) misclassifies samples outside the band in "
            f"{sum(1 for v in worst.values() if v > 0)} of {len(worst)} families; apart from "
            f"impossible modes it calls possible ({feas_wrong} pairs; families {feas_fams}), its "
            f"wrong answers lie within {max(finite) if finite else 0:.1g} of the exact boundary: "
            "its own tolerances make its effective band about 1e-7..1e-6, wider than the "
            "cones' (the cross-check in test_crosscheck.py uses a 1e-6 band for that reason).")
    return "\n".join(out) + "\n"


def headline(agg: dict, labels: list[str]) -> str:
    """One row per method over all families."""
    default = f"{default_method()}-float"
    rows = []
    rows.append("Over every family (worst family in the last column): classification error "
                f"outside the band |margin| >= {BAND:g}, feasibility mismatches, face error, "
                "median time per call.\n")
    rows.append("| method | time/call (median) | class. err. outside band | "
                "worst wrong (abs. margin) | feasibility mismatches | max face angle | "
                "missing/extra faces | families with errors |")
    rows.append("|---|---|---|---|---|---|---|---|")
    for label in labels:
        tot = {"n": 0, "w": 0, "f": 0, "ang": 0.0, "me": 0, "times": [], "ww": 0.0}
        bad_fams = []
        for fam in agg:
            a = agg[fam].get(label)
            if not a:
                continue
            n_out = a["samples"] - a["in_band"]
            tot["n"] += n_out
            tot["w"] += a["wrong_out"]
            tot["f"] += a["feas_mismatch"]
            tot["ww"] = max(tot["ww"], a["worst_wrong"])
            tot["ang"] = max(tot["ang"], a["angle"])
            tot["me"] += a["missing"] + a["extra"]
            tot["times"] += a["times"]
            if a["wrong_out"] or a["feas_mismatch"] or a["errors"]:
                bad_fams.append(fam)
        name = f"**{label}** (default)" if label == default else label
        face = "-" if label == "LP per query" else _sci(tot["ang"])
        me = "-" if label == "LP per query" else str(tot["me"])
        rows.append(f"| {name} | {fmt_time(median(tot['times']))} | {_frac(tot['w'], tot['n'])} "
                    f"| {_sci(tot['ww'])} | {tot['f']} | {face} | {me} | {', '.join(bad_fams) or 'none'} |")
    return "\n".join(rows) + "\n"


def per_param_table(records: list[dict], label: str) -> str:
    groups: dict = defaultdict(lambda: {"pairs": 0, "n_out": 0, "w_out": 0, "n_in": 0,
                                        "w_in": 0, "feas": 0, "angle": 0.0, "me": 0,
                                        "times": [], "fb": 0.0, "infeasible": 0})
    for r in records:
        mr = r["methods"].get(label)
        if not mr or "error" in mr:
            continue
        g = groups[(r["family"], r["param"])]
        g["pairs"] += 1
        g["infeasible"] += not r["feasible"]
        g["n_out"] += r["samples"] - r["in_band"]
        g["n_in"] += r["in_band"]
        g["w_out"] += mr["wrong_out"]
        g["w_in"] += mr["wrong_in"]
        g["feas"] += bool(mr.get("feasible_mismatch"))
        if mr["angle"] == mr["angle"]:
            g["angle"] = max(g["angle"], mr["angle"])
        g["me"] += mr["missing"] + mr["extra"]
        g["times"].append(mr["time"])
        g["fb"] += mr.get("fallbacks", 0)
    lines = ["| family | parameter | pairs (impossible) | time/call | class. err. outside "
             "band | in band | feasibility | face angle | missing+extra | fallbacks |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for (fam, param), g in groups.items():
        lines.append(f"| {fam} | {param} | {g['pairs']} ({g['infeasible']}) | "
                     f"{fmt_time(median(g['times']))} | {_frac(g['w_out'], g['n_out'])} | "
                     f"{_frac(g['w_in'], g['n_in'])} | {g['feas']} | {_sci(g['angle'])} | "
                     f"{g['me']} | {g['fb']:.0f} |")
    return "\n".join(lines) + "\n"


def fallback_text(agg: dict, labels: list[str], fb_global: dict) -> str:
    lines = [
        "`cones.FALLBACKS` counts float cddlib conversions and those that raised a numerical "
        "inconsistency and were redone in exact arithmetic; `stats.PLANAR_FALLBACKS` counts "
        "the planar method's float 3-D conversions whose self-check failed and were redone "
        "with exact cddlib; `paper.PAPER_FALLBACKS` the float paper cones that failed their "
        "soundness / agreement check and were redone exactly; `exact_ill_conditioned` (the "
        "core's PARALLEL_GUARD) the float cones computed exactly from the scene because two "
        "acceleration rows are nearly, not exactly, parallel. All are summed here. Over "
        f"this whole run: {fb_global['float_calls']:.0f} float "
        f"conversions or cones, {fb_global['exact_fallbacks']:.0f} exact fallbacks "
        f"(of which {fb_global.get('ill_conditioned', 0):.0f} by the parallel guard) "
        f"({fb_global['exact_fallbacks'] / max(1, fb_global['float_calls']):.3%}).\n",
        "Per family and float method: cone builds that needed a fallback, and the median "
        "time of builds with and without one (the cost):\n",
        "| family | method | fallbacks per build (sum over pairs) | median time with | "
        "median time without |", "|---|---|---|---|---|"]
    any_fb = False
    for fam in agg:
        for label in labels:
            a = agg[fam].get(label)
            if not a or "float" not in label or label.endswith("guarded"):
                continue
            if a["fallbacks"] == 0:
                continue
            any_fb = True
            lines.append(f"| {fam} | {label} | {a['fallbacks']:.1f} | "
                         f"{fmt_time(median(a['fb_times']))} | "
                         f"{fmt_time(median(a['nofb_times']))} |")
    if not any_fb:
        lines.append("| (none) | | | | |")
    return "\n".join(lines) + "\n"


def verify_text(verify: dict, agg: dict) -> str:
    if not verify.get("builds"):
        return ""
    b = verify["builds"]
    label = f"{default_method()}-float"
    lines = [
        f"### The proposed guard, measured (`{label}-guarded`)\n",
        f"`{label}-guarded` is a sketch of a fix for the default path, written in the "
        "benchmark only (`guarded_default` in benchmarks/error_vs_runtime.py; the core is "
        "unchanged): the default float method, except that the cone is computed exactly "
        "from the scene (`exact=True`) when two of the mode's acceleration rows "
        f"(unit, up to sign) are within {VERIFY_ANGLE:g} rad of each other but not exactly "
        "parallel (nearly coincident lines of action; the float geometry's rounding, about "
        "1e-16, is then amplified by 1 / angle in the acceleration cone and the feasibility "
        f"verdict). Over this run: {b:.0f} builds, {verify['exact_ill_conditioned']:.0f} "
        f"({verify['exact_ill_conditioned'] / b:.1%}) computed exactly. Per family (pairs "
        "where it fired, and the median time per build against the default's):\n",
        "| family | guard fired | time/call guarded | time/call default |",
        "|---|---|---|---|"]
    for fam in agg:
        g, d = agg[fam].get(f"{label}-guarded"), agg[fam].get(label)
        if not g or not d:
            continue
        lines.append(f"| {fam} | {g['fallbacks']:.0f} of {g['cases']} | "
                     f"{fmt_time(median(g['times']))} | {fmt_time(median(d['times']))} |")
    return "\n".join(lines) + "\n"


def disagreements_text(records: list[dict], labels: list[str], default: str,
                       crashes: list) -> str:
    lines = []
    for label in labels:
        bad = [r for r in records if label in r["methods"] and (
            r["methods"][label].get("wrong_out") or r["methods"][label].get("feasible_mismatch")
            or "error" in r["methods"][label])]
        if not bad:
            lines.append(f"- {label}: none.")
            continue
        fams = sorted({r["family"] for r in bad})
        lines.append(f"- {label}: {len(bad)} pair(s), families {', '.join(fams)}.")
    lines.append("")
    dbad = [r for r in records if default in r["methods"] and (
        r["methods"][default].get("wrong_out") or r["methods"][default].get("feasible_mismatch")
        or "error" in r["methods"][default])]
    if dbad:
        lines.append(f"Reproducers for the default method ({default}), up to 10 (the scene "
                     "dict is accepted by `load_scene`):\n")
        for r in dbad[:10]:
            mr = r["methods"][default]
            lines.append(f"- family {r['family']} ({r['param']}), mode `{r['mode']}`: exact "
                         f"feasible={r['feasible']}, method feasible={mr.get('feasible')}, "
                         f"wrong outside band={mr.get('wrong_out')}, error={mr.get('error')}")
            for b in mr.get("bad", [])[:1]:
                lines.append(f"  - e.g. g = {b['g']}: exact {b['exact']}, method "
                             f"{b['method']}, exact margin {b['exact_margin']:.3g}")
            lines.append(f"  - scene: `{json.dumps(r['data'])}`")
        lines.append("")
    else:
        lines.append(f"The default method ({default}) had none: classification error outside "
                     "the band is 0 on every family, and its feasibility verdict always "
                     "matched exact arithmetic.\n")
    if crashes:
        lines.append("Pairs that raised or crashed (the exact ground truth refusing a scene the "
                     "float geometry accepts, or a process killed by cddlib):\n")
        for c in crashes[:10]:
            lines.append(f"- {c}")
        lines.append("")
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- processes
# Float cddlib can crash the interpreter (free(): invalid pointer / SIGSEGV) on some nearly
# flat cones (test_crosscheck's regression cases). The pairs therefore run in a child
# process that prints one JSON line per pair; if it dies, the pair it was on is recorded
# as a crash and a new child continues with the next one.

_PASS = ("seed", "uniform", "boundary", "lp_uniform", "lp_boundary", "repeats")


def worker(args) -> int:
    import types

    pairs = json.loads(args.worker.read_text())
    var = variants()
    for k in range(args.start, len(pairs)):
        p = pairs[k]
        print(json.dumps({"start": k}), flush=True)
        fb0, fc0, vs0 = _fallback_count(), _float_conversions(), dict(VERIFY_STATS)
        ill0 = core_fallbacks()[2]
        case = types.SimpleNamespace(family=p["family"], param=p["param"], data=p["data"])
        rng = np.random.default_rng([args.seed, k])
        try:
            rec = run_case(case, p["mode"], rng, args, var)
        except Exception:
            print(json.dumps({"item": k, "crash": traceback.format_exc().splitlines()[-1]}),
                  flush=True)
            continue
        rec["data"] = p["data"]
        rec["item"] = k
        rec["totals"] = {"exact_fallbacks": _fallback_count() - fb0,
                         "ill_conditioned": core_fallbacks()[2] - ill0,
                         "float_calls": _float_conversions() - fc0,
                         **{key: VERIFY_STATS[key] - vs0[key] for key in vs0}}
        print(json.dumps(rec, default=float), flush=True)
    return 0


def run_children(pairs: list[dict], args, tqdm) -> tuple[list, list, dict]:
    import subprocess
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump(pairs, fh)
        job = fh.name
    records, crashes, totals = [], [], defaultdict(float)
    bar = tqdm(total=len(pairs), desc="error vs runtime", unit="pair",
               disable=args.no_progress)
    start = 0
    try:
        while start < len(pairs):
            cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", job,
                   "--start", str(start)]
            for name in _PASS:
                cmd += [f"--{name.replace('_', '-')}", str(getattr(args, name))]
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    text=True)
            current = start
            for line in proc.stdout:
                if not line.startswith("{"):
                    continue
                msg = json.loads(line)
                if "start" in msg:
                    current = msg["start"]
                    continue
                bar.update(1)
                if "crash" in msg:
                    p = pairs[msg["item"]]
                    crashes.append(f"{p['family']} {p['param']} mode {p['mode']}: "
                                   f"{msg['crash']} -- scene `{json.dumps(p['data'])}`")
                    continue
                for key, v in msg.pop("totals").items():
                    totals[key] += v
                records.append(msg)
            err = proc.stderr.read()
            code = proc.wait()
            if code == 0:
                break
            p = pairs[current]
            tail = err.strip().splitlines()[-1:] if err.strip() else []
            crashes.append(f"{p['family']} {p['param']} mode {p['mode']}: process died "
                           f"(exit {code}) {tail} -- scene `{json.dumps(p['data'])}`")
            bar.update(1)
            start = current + 1
    finally:
        bar.close()
        os.unlink(job)
    return records, crashes, dict(totals)


# ----------------------------------------------------------------------------- main


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run")
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--families", default=",".join(FAMILIES),
                    help="comma-separated subset of: " + ", ".join(FAMILIES))
    ap.add_argument("--size", type=int, default=None,
                    help="scenes per family parameter value (default 4, quick 1)")
    ap.add_argument("--uniform", type=int, default=None)
    ap.add_argument("--boundary", type=int, default=None)
    ap.add_argument("--lp-uniform", type=int, default=6)
    ap.add_argument("--lp-boundary", type=int, default=6)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--no-progress", action="store_true")
    ap.add_argument("--json", type=Path, default=None, help="also dump raw records here")
    ap.add_argument("--worker", type=Path, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--start", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.size is None:
        args.size = 1 if args.quick else 4
    if args.uniform is None:
        args.uniform = 40 if args.quick else 60
    if args.boundary is None:
        args.boundary = 40 if args.quick else 60
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover
        def tqdm(x, **_):
            return x

    if args.worker is not None:
        return worker(args)
    facts = harness.machine_facts()
    rng = np.random.default_rng(args.seed)
    t_start = time.time()
    fams = [f.strip() for f in args.families.split(",") if f.strip()]
    cases, rejected = [], []
    for fam in fams:
        size = args.size * (10 if fam == "random" and not args.quick else
                            (4 if fam in ("random", "gaps") else 1))
        for c in FAMILIES[fam](rng, size):
            (rejected if c.rejected else cases).append(c)
    pairs = [{"family": c.family, "param": c.param, "data": c.data, "mode": m}
             for c in cases for m in c.modes]
    labels = [v[0] for v in variants()] + ["LP per query"]
    records, crashes, totals = run_children(pairs, args, tqdm)
    fb_global = {k: totals.get(k, 0) for k in ("float_calls", "exact_fallbacks",
                                                "ill_conditioned")}
    verify = {k: totals.get(k, 0) for k in VERIFY_STATS}
    elapsed = time.time() - t_start
    agg = aggregate(records, labels)
    load_end = " ".join(f"{x:.2f}" for x in os.getloadavg())
    text = render(records, rejected, agg, labels, args, facts, load_end, elapsed, fb_global,
                  crashes, verify)
    print(text)
    if args.json:
        args.json.write_text(json.dumps(records, default=float))
    if not args.no_write:
        OUT_MD.parent.mkdir(parents=True, exist_ok=True)
        OUT_MD.write_text(text)
        plot(agg, labels, OUT_PNG)
        print(f"wrote {OUT_MD} and {OUT_PNG}", file=sys.stderr)
        # when and where it ran (kept out of the doc): the results index cites this file
        harness.write_json(OUT_JSON, facts, {
            "pairs": len(records), "minutes": elapsed / 60, "crashes": len(crashes),
            "fallbacks": fb_global,
            "time_per_call_s": {label: median([t for fam in agg.values()
                                               for t in fam[label]["times"]])
                                for label in labels}})
    return 0


if __name__ == "__main__":
    sys.exit(main())
