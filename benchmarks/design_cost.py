#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Fixture design: what each stage costs per candidate and core, the whole design of the
pawl on a 10 mm lattice, 1 against 2 Dask workers, the scheduler's overhead per task.

    python benchmarks/design_cost.py            # writes benchmarks/results/design_cost.json
    python benchmarks/design_cost.py --quick --no-write
    python benchmarks/design_cost.py --region   # writes benchmarks/results/design_region.json

Parts (wall clock, ``time.perf_counter``; the friction of every pin in [0.2, 0.4]):

1. Stage rates on one core (in this process, no Dask), for the pawl
   (examples/pawl_seating.yaml, 6 edges) and a 12-edge cross, on a fine lattice (5 mm
   pitch, pins of 2 mm radius): geometry and location (``Enumerator.placements``) on a
   seeded sample of the lattice's pin triples (triples/s and placements/s); hold
   (``stages.hold``) on located placements (designs/s); funnel and plan
   (``stages.plan``) on holding designs that can be loaded; Monte Carlo (``stages.plan``
   with RUNS models) on one planned design.
2. The whole design of the pawl on examples/plates/plate_10mm.yaml (no fixed pin) with the
   defaults of ``wrenchcone design`` on a LocalCluster of 2 workers: wall time per stage,
   the batches' own times.
3. Stage 1 of that design on the first SPEEDUP_TRIPLES triples (batches of 50): in this
   process (no Dask), on a LocalCluster of 1 worker and of 2; the speed-up 1 -> 2.
4. The scheduler's overhead per task: no-op tasks on a LocalCluster of 2 workers, against
   the median batch time of part 3.
5. The projected time on 64 workers of stage 1 and of the plan stage: the batches of
   part 2 (and stage 1 of the pawl on the 5 mm lattice, from part 1's rates, in batches
   of the default size) spread over 64 workers, longest first, plus the overhead per task
   (a projection, not a measurement).

``--region`` runs part 2 alone with the loading task's start region of ``wrenchcone
design`` (DEFAULT_START_REGION, +-2 mm, +-2 mm, +-5 degrees around the loading start;
the designer's RegionWork counts) and writes design_region.json: the wall time per
stage, each planned design's batch time, its plan and its certified region (size,
half-widths, engine runs), the ranking with the region against the one without it on
the same rows.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time

import harness.source_tree  # noqa: F401  (this checkout's package)
import numpy as np
from harness import RESULTS, machine_facts, write_json

from wrenchcone_ros.core import Uncertainty, load_scene
from wrenchcone_ros.design.enumerate import Enumerator, pin_triples
from wrenchcone_ros.design.pipeline import design_fixtures, warm_up
from wrenchcone_ros.design.problem import (
    DEFAULT_BATCH_TRIPLES,
    DEFAULT_START_REGION,
    DesignProblem,
    Plate,
    RegionWork,
    load_plate,
)
from wrenchcone_ros.design.rank import DEFAULT_RANKING, rank_rows
from wrenchcone_ros.design.stages import hold, plan

OUT = RESULTS / "design_cost.json"
OUT_REGION = RESULTS / "design_region.json"
FRICTION = (0.2, 0.4)
RUNS = 20
SPEEDUP_TRIPLES = 600

CROSS = {"workpiece": {"mass": 0.04, "inertia": 1.2e-5, "com": [0.0, 0.0],
                       "shape": {"type": "polygon", "vertices": [
                           [-0.006, -0.02], [0.006, -0.02], [0.006, -0.006], [0.02, -0.006],
                           [0.02, 0.006], [0.006, 0.006], [0.006, 0.02], [-0.006, 0.02],
                           [-0.006, 0.006], [-0.02, 0.006], [-0.02, -0.006],
                           [-0.006, -0.006]]}},
         "friction": 0.3, "fixels": [[1.0, 1.0]]}


def stage_rates(name: str, part, plate: Plate, sample: int, holds: int, plans: int,
                seed: int) -> dict:
    prob = DesignProblem(load_scene(part), plate, Uncertainty(friction=FRICTION))
    triples = pin_triples(prob)
    rng = np.random.default_rng(seed)
    pick = sorted(rng.choice(len(triples), size=min(sample, len(triples)), replace=False))
    en = Enumerator(prob)
    t0 = time.perf_counter()
    found = []
    for k in pick:
        found += en.placements(triples[k])[0]
    t_geo = time.perf_counter() - t0
    located = [p for p in found if p.located][:holds]
    t0 = time.perf_counter()
    held = [(p, hold(prob, p.positions, p.pose)) for p in located]
    t_hold = time.perf_counter() - t0
    loadable = [p for p, h in held if "reason" not in h and not h["enclosed"]]
    loadable.sort(key=lambda p: p.design_id)
    t0 = time.perf_counter()
    planned = [(p, plan(prob, p.positions, p.pose)) for p in loadable[:plans]]
    t_plan = time.perf_counter() - t0
    feasible = [p for p, r in planned if r.get("plan_feasible")]
    mc = None
    if feasible:
        p = feasible[0]
        t0 = time.perf_counter()
        r = plan(prob, p.positions, p.pose, runs=RUNS, seed=0)
        mc = {"seconds": time.perf_counter() - t0, "runs": RUNS,
              "success_rate": r.get("success_rate")}
    out = {"part": name, "edges": len(prob.vertices), "pitch": plate.pitch,
           "pin_radius": plate.pin_radius, "extent": list(plate.extent),
           "triples_on_lattice": len(triples), "triples_timed": len(pick),
           "placements": len(found), "located": sum(p.located for p in found),
           "geometry_seconds": t_geo, "triples_per_s": len(pick) / t_geo,
           "placements_per_s": len(found) / t_geo,
           "hold_designs": len(located), "hold_seconds": t_hold,
           "hold_per_s": len(located) / t_hold if t_hold else None,
           "plan_designs": len(planned), "plan_seconds": t_plan,
           "plan_per_s": len(planned) / t_plan if t_plan else None,
           "plans_feasible": len(feasible), "monte_carlo": mc}
    print(f"{name}: {out['triples_per_s']:.1f} triples/s ({out['placements_per_s']:.1f} "
          f"placements/s), hold {out['hold_per_s']:.1f}/s, plan "
          f"{out['plan_per_s'] or 0:.2f}/s, mc {mc}", flush=True)
    return out


def whole_design(plate_file: str, workers: int) -> dict:
    t0 = time.perf_counter()
    res = design_fixtures("examples/pawl_seating.yaml", plate_file, FRICTION, workers=workers)
    wall = time.perf_counter() - t0
    rows = res.rows
    out = {"wall_seconds": wall, "workers": workers, "rows": len(rows),
           "located": sum(bool(r["located"]) for r in rows),
           "holding": sum(r["hold_margin"] is not None for r in rows),
           "guaranteed": sum(bool(r["plan_guaranteed"]) for r in rows),
           "stages": [s.to_dict() for s in res.stats],
           "top": [{k: r[k] for k in ("design_id", "features", "locating_accuracy",
                                      "hold_margin", "funnel_margin", "plan_guaranteed",
                                      "success_rate")} for r in rows[:5]]}
    print(f"whole design: {wall:.1f} s, {len(rows)} rows, stages "
          f"{[(s.name, round(s.wall, 1), s.batches) for s in res.stats]}", flush=True)
    return out


def whole_design_region(plate_file: str, workers: int) -> dict:
    """The whole design of the pawl with the default start region (module docstring)."""
    t0 = time.perf_counter()
    res = design_fixtures("examples/pawl_seating.yaml", plate_file, FRICTION, workers=workers,
                          start_region=DEFAULT_START_REGION)
    wall = time.perf_counter() - t0
    rows = res.rows
    planned = [r for r in rows if r["stage"] in ("plan", "monte_carlo")]
    keys = ("design_id", "features", "locating_accuracy", "hold_margin", "plan_feasible",
            "plan_guaranteed", "plan_modes", "region_size", "region_fraction", "region_dx",
            "region_dy", "region_dtheta", "region_runs", "region_failure", "success_rate")
    without = [r["design_id"] for r in rank_rows([dict(r) for r in rows], DEFAULT_RANKING)]
    plan_stage = next(s for s in res.stats if s.name == "plan")
    out = {"wall_seconds": wall, "workers": workers, "rows": len(rows),
           "start_region": list(DEFAULT_START_REGION),
           "region_work": RegionWork().to_dict(), "ranking": list(res.ranking),
           "located": sum(bool(r["located"]) for r in rows),
           "holding": sum(r["hold_margin"] is not None for r in rows),
           "planned": len(planned),
           "guaranteed": sum(bool(r["plan_guaranteed"]) for r in rows),
           "region_runs_total": sum(r["region_runs"] or 0 for r in rows),
           "region_whole": sum(r["region_size"] == 1.0 for r in planned),
           "region_sizes": sorted((r["region_size"] for r in planned
                                   if r["region_size"] is not None), reverse=True),
           "plan_stage_cpu_seconds": sum(plan_stage.batch_seconds),
           "stages": [s.to_dict() for s in res.stats],
           "planned_designs": [{k: r[k] for k in keys} | {"rank": r["rank"],
                               "rank_without_region": without.index(r["design_id"]) + 1}
                               for r in planned]}
    print(f"whole design with regions: {wall:.1f} s, {len(rows)} rows, stages "
          f"{[(s.name, round(s.wall, 1), s.batches) for s in res.stats]}, region sizes "
          f"{[round(v, 3) for v in out['region_sizes']]}", flush=True)
    return out


def speedup(plate_file: str, n: int) -> dict:
    prob_triples = pin_triples(DesignProblem(load_scene("examples/pawl_seating.yaml"),
                                             load_plate(plate_file)))[:n]
    out = {}
    for workers in (0, 1, 2):
        t0 = time.perf_counter()
        res = design_fixtures("examples/pawl_seating.yaml", plate_file, FRICTION,
                              workers=workers, plans=0, runs=0, batch_triples=50,
                              triples=prob_triples)
        wall = time.perf_counter() - t0
        geo = res.stats[0]
        out[str(workers)] = {"wall_seconds": wall, "stage_wall": geo.wall,
                             "batches": geo.batches, "batch_seconds": geo.batch_seconds,
                             "rows": len(res.rows)}
        print(f"stage 1, {n} triples, workers={workers}: {wall:.1f} s (stage {geo.wall:.1f} s)",
              flush=True)
    out["speedup_1_to_2"] = out["1"]["stage_wall"] / out["2"]["stage_wall"]
    return out


def _noop(x):
    return x


def overhead(tasks: int) -> dict:
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, silence_logs=40) as cluster, \
            Client(cluster) as client:
        client.gather(client.map(_noop, range(10), pure=False))
        t0 = time.perf_counter()
        client.gather(client.map(_noop, range(tasks), pure=False))
        bulk = (time.perf_counter() - t0) / tasks
        rtt = []
        for k in range(20):
            t0 = time.perf_counter()
            client.submit(_noop, k, pure=False).result()
            rtt.append(time.perf_counter() - t0)
    print(f"overhead: {bulk * 1e3:.2f} ms per task in bulk, round trip "
          f"{statistics.median(rtt) * 1e3:.2f} ms", flush=True)
    return {"tasks": tasks, "bulk_seconds_per_task": bulk,
            "round_trip_seconds_median": statistics.median(rtt)}


def project(batch_seconds: list[float], workers: int, per_task: float) -> float:
    """Greedy longest-first assignment of the batches to ``workers``, each task paying
    ``per_task``: the finishing time of the busiest worker."""
    load = [0.0] * workers
    for b in sorted(batch_seconds, reverse=True):
        k = load.index(min(load))
        load[k] += b + per_task
    return max(load)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small samples, no whole design")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--region", action="store_true",
                    help="the whole design with start regions alone (design_region.json)")
    args = ap.parse_args()
    facts = machine_facts()
    warm_up()
    if args.region:
        region = whole_design_region("examples/plates/plate_10mm.yaml", 2)
        if not args.no_write:
            write_json(OUT_REGION, facts, {"friction": list(FRICTION), "whole_design": region})
        return 0
    sample, holds, plans = (40, 20, 1) if args.quick else (300, 150, 4)
    rates = [stage_rates("pawl", "examples/pawl_seating.yaml", Plate(0.005, (20, 14), 0.002),
                         sample, holds, plans, args.seed),
             stage_rates("cross (12 edges)", CROSS, Plate(0.005, (14, 14), 0.002), sample,
                         holds, plans, args.seed)]
    plate10 = "examples/plates/plate_10mm.yaml"
    whole = None if args.quick else whole_design(plate10, 2)
    sp = speedup(plate10, 100 if args.quick else SPEEDUP_TRIPLES)
    ov = overhead(50 if args.quick else 200)
    per_task = ov["bulk_seconds_per_task"] * 2  # two workers share the bulk figure
    proj = {}
    if whole is not None:
        for key, st in (("pawl_10mm_stage1", whole["stages"][0]),
                        ("pawl_10mm_plans", whole["stages"][1])):
            proj[key] = {
                "batches": st["batches"], "cpu_seconds": sum(st["batch_seconds"]),
                "projected_64_workers_seconds": project(st["batch_seconds"], 64, per_task),
                "measured_2_workers_seconds": st["wall"]}
    pawl = rates[0]
    per_triple = pawl["geometry_seconds"] / pawl["triples_timed"]
    hold_share = pawl["placements"] / pawl["triples_timed"] * (
        pawl["located"] / max(pawl["placements"], 1)) / pawl["hold_per_s"]
    cpu = pawl["triples_on_lattice"] * (per_triple + hold_share)
    n_batches = math.ceil(pawl["triples_on_lattice"] / DEFAULT_BATCH_TRIPLES)
    proj["pawl_5mm_stage1"] = {
        "triples": pawl["triples_on_lattice"], "cpu_seconds_estimated": cpu,
        "batches": n_batches,
        "projected_64_workers_seconds": project([cpu / n_batches] * n_batches, 64, per_task),
        "projected_1_worker_seconds": cpu}
    print(f"projections: {proj}", flush=True)
    if not args.no_write:
        write_json(OUT, facts, {"friction": list(FRICTION), "runs": RUNS, "rates": rates,
                                "whole_design": whole, "speedup": sp, "overhead": ov,
                                "projection": proj})
    return 0


if __name__ == "__main__":
    sys.exit(main())
