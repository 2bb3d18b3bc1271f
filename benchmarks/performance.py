# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Performance of the batched, compiled cone engine against its targets.

Writes the generated section of docs/performance.md. Every ratio is taken within one
run (interleaved per case), times are medians; the machine's load is printed with them.

1. One cone, default method (float), on a freshly loaded Scene, against ONE pycddlib float
   V-to-H conversion of that cone's own generators, n = 2..8 fixels, generic scenes and
   the shared-edge family.
2. Pose to F: a new pose (Scene.with_pose) to the F arrays of k = 1, 4, 16, 64 monitored
   modes with ``wrench_cones``, against the sum of the k cones' cddlib conversions, and
   against the numpy reference engine.
3. ``consistent_modes(scene, g)`` cold (a new Scene each call), n = 2..10.
4. ``contains_many`` on 10,000 wrenches against a Python loop of ``contains()``.
5. Start-up: importing the core, importing numba, compiling the kernel into an empty
   cache, loading it from the cache (each in a fresh process).

Usage: python benchmarks/performance.py [--quick] [--no-write]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import cdd
import harness
import harness.source_tree  # noqa: F401  (this checkout's package first)
import numpy as np
from harness import DOCS, facts_markdown, fmt_ratio, fmt_time, machine_facts, median

from wrenchcone_ros.core import (
    consistent_modes,
    enumerate_modes,
    load_scene,
    wrench_cone,
    wrench_cones,
)
from wrenchcone_ros.core import batch, engines, stats

OUT = DOCS / "performance.md"
BEGIN, END = harness.generated_begin("performance.py"), harness.GENERATED_END


def cdd_v_to_h(G: np.ndarray, L: np.ndarray):
    """One pycddlib float V-to-H conversion of a cone's generators (rays G, lines L)."""
    rows = [[0.0, *r] for r in G.tolist()] + [[0.0, *r] for r in L.tolist()]
    if not rows:
        rows = [[0.0, 0.0, 0.0, 0.0]]
    rows = [[1.0, 0.0, 0.0, 0.0]] + rows
    mat = cdd.matrix_from_array(rows, lin_set=range(1 + G.shape[0], len(rows)),
                                rep_type=cdd.RepType.GENERATOR)
    return cdd.copy_inequalities(cdd.polyhedron_from_matrix(mat))


def _generators(cone):
    c = cone if cone.feasible else cone.closure
    return c.G_hat, c.L_hat


def _scene_data(rng, family: str, n: int) -> dict:
    from helpers.strategies import random_scene, shared_edge_scene

    if family == "shared_edge":
        k = min(4, n)
        return shared_edge_scene(rng, n_shared=k, n_extra=n - k).data
    return random_scene(rng, n_fixels=n, n_contact=int(rng.integers(max(1, n - 2), n + 1))).data


# --- 1. one cone ----------------------------------------------------------------------------
def one_cone_case(rng, family: str, n: int) -> tuple[dict, str]:
    """(scene data, mode): a random scene of ``family`` with n fixels and one of its
    modes, drawn from ``rng``: a case of table 1 (and of benchmarks/guard.py)."""
    data = _scene_data(rng, family, n)
    modes = list(enumerate_modes(load_scene(data).in_contact))
    return data, modes[int(rng.integers(len(modes)))]


def one_cone_times(data: dict, mode: str, reps: int) -> tuple[list[float], list[float]]:
    """Wall times (s) of ``wrench_cone(scene, mode)`` on ``reps`` freshly loaded Scenes of
    ``data`` (nothing cached), each followed by one pycddlib float V-to-H conversion of
    that cone's own generators: (cone times, conversion times), interleaved."""
    G, L = _generators(wrench_cone(load_scene(data), mode))
    scenes = [load_scene(data) for _ in range(reps)]  # fresh: nothing cached
    tc, td = [], []
    for sc in scenes:  # interleaved
        t0 = time.perf_counter()
        wrench_cone(sc, mode)
        t1 = time.perf_counter()
        cdd_v_to_h(G, L)
        t2 = time.perf_counter()
        tc.append(t1 - t0)
        td.append(t2 - t1)
    return tc, td


def one_cone_table(rng, cases: int, reps: int) -> list[str]:
    rows = []
    for family in ("generic", "shared_edge"):
        for n in range(2, 9):
            t_cone, t_cdd, ratios = [], [], []
            for _ in range(cases):
                tc, td = one_cone_times(*one_cone_case(rng, family, n), reps)
                t_cone.append(median(tc))
                t_cdd.append(median(td))
                ratios.append(median(tc) / median(td))
            r = median(ratios)
            rows.append(f"| {family} | {n} | {fmt_time(median(t_cone))} | "
                        f"{fmt_time(median(t_cdd))} | {r:.2f} | "
                        f"{'yes' if r <= 2.0 else 'no'} |")
            print(rows[-1], flush=True)
    return rows


# --- 2. pose to F ---------------------------------------------------------------------------
HEXAGON = [[np.cos(k * np.pi / 3 + 0.4), np.sin(k * np.pi / 3 + 0.4)] for k in range(6)]


def pose_scenes(rng) -> dict[str, dict]:
    """An axis-aligned square with 4 point fixels in contact and a polygon, not
    axis-aligned, with two pins on one slanted edge and two more fixels."""
    from helpers.strategies import shared_edge_scene

    square = {"workpiece": {"mass": 1.0, "inertia": 0.2, "com": [0.05, -0.02],
                            "shape": {"type": "polygon",
                                      "vertices": [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5],
                                                   [-0.5, 0.5]]},
                            "pose": [0.0, 0.0, 0.0]},
              "friction": 0.4,
              "fixels": [[-0.2, -0.5], [0.3, -0.5], [0.5, 0.1], [-0.5, 0.2]]}
    while True:
        hexa = shared_edge_scene(rng, n_shared=2, n_extra=2, pins=True, convex=True)
        if sum(hexa.in_contact) == 4:
            break
    return {"square, 4 fixels": square, "polygon, 2 pins on one edge + 2": hexa.data}


def pose_to_f_times(base, modes: list[str], reps: int, numpy_reps: int = 0
                    ) -> dict[str, list[float]]:
    """Wall times (s) of a new pose and the F arrays of ``modes``, ``reps`` times: a new
    Scene at ``base``'s pose (``new_scene``: nothing cached), ``wrench_cones`` + F on it
    (``wrench_cones``), then the sum of the modes' cddlib conversions of their generators
    (``cdd``), interleaved; the first ``numpy_reps`` times also wrench_cones + F on the
    numpy reference engine (``numpy``)."""
    gens = [_generators(c) for c in wrench_cones(base, modes)]
    out = {"new_scene": [], "wrench_cones": [], "cdd": [], "numpy": []}
    for r in range(reps):
        pose = base.pose  # a new Scene at this pose: nothing cached
        t0 = time.perf_counter()
        scene = base.with_pose(*pose)
        out["new_scene"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        F = [c.F for c in wrench_cones(scene, modes)]
        t1 = time.perf_counter()
        for G, L in gens:
            cdd_v_to_h(G, L)
        t2 = time.perf_counter()
        out["wrench_cones"].append(t1 - t0)
        out["cdd"].append(t2 - t1)
        if r < numpy_reps:
            t3 = time.perf_counter()
            _ = [c.F for c in wrench_cones(base.with_pose(*pose), modes, engine="numpy")]
            out["numpy"].append(time.perf_counter() - t3)
        del F
    return out


def pose_to_f_table(rng, reps: int) -> list[str]:
    rows = []
    for name, data in pose_scenes(rng).items():
        base = load_scene(data)
        every = list(enumerate_modes(base.in_contact))
        order = [every[k] for k in rng.permutation(len(every))]
        for k in (1, 4, 16, 64):
            # the reference is slow: a few repeats
            t = pose_to_f_times(base, order[:k], reps, numpy_reps=max(3, reps // 10))
            ts, tk, td, tn = t["new_scene"], t["wrench_cones"], t["cdd"], t["numpy"]
            rows.append(f"| {name} | {k} | {fmt_time(median(ts))} | {fmt_time(median(tk))} | "
                        f"{fmt_time(median(ts) + median(tk))} | {fmt_time(median(td))} | "
                        f"{median(td) / median(tk):.1f}x | {fmt_time(median(tn))} | "
                        f"{median(tn) / median(tk):.0f}x |")
            print(rows[-1], flush=True)
    return rows


# --- 3. consistent_modes cold -----------------------------------------------------------------
def classify_table(rng, cases: int) -> list[str]:
    from helpers.strategies import random_scene, random_wrench

    rows = []
    for n in range(2, 11):
        tk, tn = [], []
        for c in range(cases):
            data = random_scene(rng, n_fixels=n, n_contact=n if c % 2 == 0 else None).data
            s = load_scene(data)
            consistent_modes(s, random_wrench(rng, s.length_scale))  # plans for this state
            for _ in range(3):
                g = random_wrench(rng, s.length_scale)
                sc = load_scene(data)
                t0 = time.perf_counter()
                consistent_modes(sc, g)
                tk.append(time.perf_counter() - t0)
            if n <= 7:
                sc = load_scene(data)
                t0 = time.perf_counter()
                consistent_modes(sc, g, engine="numpy")
                tn.append(time.perf_counter() - t0)
        rows.append(f"| {n} | {fmt_time(median(tk))} | {fmt_time(median(tn))} | "
                    f"{(median(tn) / median(tk)) if tn else float('nan'):.1f}x |")
        print(rows[-1], flush=True)
    return rows


def classify_first_call(rng) -> str:
    """n = 6, all in contact: the very first call for a contact state (plans not cached)."""
    from helpers.strategies import random_scene, random_wrench

    ts = []
    for _ in range(5):
        stats.BATCH_PLANS.clear()
        stats.PLAN_CODES.clear()
        from wrenchcone_ros.core import constraints

        constraints._PLANS.clear()
        data = random_scene(rng, n_fixels=6, n_contact=6).data
        s = load_scene(data)
        t0 = time.perf_counter()
        consistent_modes(s, random_wrench(rng, s.length_scale))
        ts.append(time.perf_counter() - t0)
    return fmt_time(median(ts))


# --- 4. contains_many ---------------------------------------------------------------------------
def many_table(rng, reps: int) -> list[str]:
    from helpers.strategies import random_scene, random_wrench

    rows = []
    s = load_scene(random_scene(rng, n_fixels=3, n_contact=3).data)
    for mode in ("nnn", "sls", "*" * 3):
        c = wrench_cone(s, mode)
        G = np.array([random_wrench(rng, s.length_scale) for _ in range(10_000)])
        tl, tv = [], []
        for _ in range(reps):
            t0 = time.perf_counter()
            loop = [c.contains(g) for g in G]
            t1 = time.perf_counter()
            vec = c.contains_many(G)
            t2 = time.perf_counter()
            assert vec.tolist() == loop
            tl.append(t1 - t0)
            tv.append(t2 - t1)
        t0 = time.perf_counter()
        c.margin_many(G)
        tm = time.perf_counter() - t0
        kind = "WrenchSet" if mode.startswith("*") else "Cone"
        rows.append(f"| {kind} {mode} | {fmt_time(median(tl))} | {fmt_time(median(tv))} | "
                    f"{fmt_ratio(median(tl) / median(tv))} | {fmt_time(tm)} |")
        print(rows[-1], flush=True)
    return rows


# --- 5. start-up ---------------------------------------------------------------------------------
def _py(code: str, env: dict) -> float:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, **env}, timeout=1800, cwd=str(harness.ROOT))
    if out.returncode:
        raise RuntimeError(out.stderr)
    return float(out.stdout.strip().splitlines()[-1])


def startup_rows() -> list[str]:
    t_core = ("import time; t=time.perf_counter(); import wrenchcone_ros.core; "
              "print(time.perf_counter()-t)")
    t_numba = "import time; t=time.perf_counter(); import numba; print(time.perf_counter()-t)"
    t_first = ("import time; from wrenchcone_ros.core import batch; "
               "t=time.perf_counter(); batch.warm_up(); print(time.perf_counter()-t)")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        env = {"NUMBA_CACHE_DIR": tmp}
        core = median([_py(t_core, env) for _ in range(3)])
        nb = median([_py(t_numba, env) for _ in range(3)])
        compile_s = _py(t_first, env)
        cached = median([_py(t_first, env) for _ in range(3)])
    rows.append(f"| import wrenchcone_ros.core (numba not imported) | {fmt_time(core)} |")
    rows.append(f"| import numba | {fmt_time(nb)} |")
    rows.append(f"| first batch, empty cache: numba import + JIT compile | {fmt_time(compile_s)} |")
    rows.append(f"| first batch, cache filled: numba import + cache load | {fmt_time(cached)} |")
    for r in rows:
        print(r, flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--no-startup", action="store_true", help="skip the compile timing")
    ap.add_argument("--seed", type=int, default=8)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    if engines.resolve_engine() != "kernel":
        raise SystemExit("the kernel engine is not available: "
                         + str(engines.kernel_unavailable()))
    batch.warm_up()
    facts = machine_facts()
    cases, reps = (3, 15) if args.quick else (8, 40)
    print("one cone")
    one = one_cone_table(rng, cases, reps)
    print("pose to F")
    pose = pose_to_f_table(rng, 40 if args.quick else 200)
    print("consistent_modes")
    cls = classify_table(rng, 2 if args.quick else 6)
    first = classify_first_call(rng)
    print("contains_many")
    many = many_table(rng, 3 if args.quick else 7)
    fb = dict(stats.PLANAR_FALLBACKS)
    ks = dict(stats.KERNEL_STATS)
    start = [] if args.no_startup else startup_rows()
    load_end = harness.loadavg()
    import numba

    text = "\n".join([
        BEGIN,
        f"Command: `python benchmarks/performance.py{' --quick' if args.quick else ''}`; "
        f"numba {numba.__version__}.",
        "",
        facts_markdown(facts, load_end),
        "",
        "### 1. One cone on a fresh Scene against one cddlib conversion",
        "",
        f"Per n and family: {cases} random (scene, mode) cases, each timed {reps} times on "
        "freshly loaded Scenes (nothing cached), interleaved with one pycddlib float "
        "V-to-H conversion of that cone's own generators (rays and lines; the closure's "
        "for an infeasible mode). Times: medians over cases of per-case medians (wall). "
        "Ratio: median over cases of (cone / cdd). Target: ratio <= 2.",
        "",
        "| family | n | `wrench_cone` | cdd V-to-H | ratio | <= 2 |",
        "| --- | --- | --- | --- | --- | --- |",
        *one,
        "",
        "### 2. Pose to F",
        "",
        "New pose: `Scene.with_pose` (a new Scene: validation, contact frames) timed "
        "separately, then the SI F arrays of k monitored modes with `wrench_cones` on that "
        "new Scene (kernel engine; J, plans per pose and mode computed inside), against "
        "the sum of those k cones' cddlib conversions (timed right after, same loop), and "
        "against the numpy reference engine (fewer repeats; wrench_cones + F only). "
        "Medians. Targets: 16 modes <= 1 ms and <= the cddlib sum.",
        "",
        "| scene | modes | new Scene | wrench_cones + F | both | sum of cdd V-to-H "
        "| cdd / wrench_cones | numpy engine | numpy / kernel |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        *pose,
        "",
        "### 3. consistent_modes, cold",
        "",
        f"{2 if args.quick else 6} random scenes per n (half with every fixel in contact, "
        "half with n-2..n in contact), 3 random wrenches each, each call on a new Scene "
        "(no cones cached; the pose-independent plans of the contact state cached, as for "
        "every pose after the first). numpy: the reference depth-first search on the numpy "
        "engine (n <= 7). Target: n = 6 <= 1 ms.",
        "",
        "| n | kernel engine | numpy engine | numpy / kernel |",
        "| --- | --- | --- | --- |",
        *cls,
        "",
        f"First call ever for a contact state (n = 6, all in contact; plan caches "
        f"cleared): {first} median.",
        "",
        "### 4. contains_many on 10,000 wrenches",
        "",
        "A Python loop of `contains()` against one `contains_many()` call on the same "
        "10,000 random wrenches (results asserted equal); last column one `margin_many`. "
        "Target: >= 100x.",
        "",
        "| cone | loop of contains | contains_many | speed-up | margin_many |",
        "| --- | --- | --- | --- | --- |",
        *many,
        "",
        "### 5. Start-up",
        "",
        "Each in a fresh process, `NUMBA_CACHE_DIR` a new empty directory (medians of 3, "
        "compile once).",
        "",
        "| step | wall time |",
        "| --- | --- |",
        *(start or ["| (skipped: --no-startup) | - |"]),
        "",
        f"Counters over the whole run: kernel cones {ks['kernel_cones']}, declined by the "
        f"kernel {ks['declined']}; stats.PLANAR_FALLBACKS {fb}.",
        END,
    ])
    harness.publish_generated(text, OUT, "performance.py", "Performance", facts,
                              {"one_cone": one, "pose_to_F": pose, "consistent_modes": cls,
                               "contains_many": many, "startup": start}, not args.no_write)


if __name__ == "__main__":
    main()
