#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans for a box of start poses: the region certified, its cost, and sampled starts.

    python benchmarks/plan_region.py     # writes benchmarks/results/plan_region.json

For each task (the pawl of examples/pawl_seating.yaml, +-2 mm x +-2 mm x +-5 deg; the
disc of examples/disc_nest.yaml, +-1 mm x +-1 mm x +-5 deg; the pawl again, +-6 mm x
+-10 mm x +-10 deg, a box its plan does not hold from; every fixel's mu in [0.2, 0.4]): ``plan_seating(..., start_region=...)`` with the default cover and
bisections, on 2 worker processes, no sampled runs (wall time, and CPU time of the
planning process and of its worker processes); then 1,000 starts drawn uniformly in the
certified box (``sample_starts``, seed 0), each with its own sampled model
(``sample_models``, seed 0), run in the engine: how many seat, and why the others do
not; then the same in the box twice the certified one per axis (dtheta at most pi):
how many fail there, and for a box that was shrunk, in the asked box too (the
certification is not vacuous when some do).

    python benchmarks/plan_region.py --verify           # benchmarks/results/plan_region_verify.json
    python benchmarks/plan_region.py --verify --quick   # the arrival family's first 6 tasks
    python benchmarks/plan_region.py --verify --task tbar --no-write

``--verify``: the verification across tasks, with a box a gripper's placement error
could be (the asked box per task: VERIFY_BOXES), on 2 worker processes: the pawl, the
T-bar of
examples/tbar_swing.yaml and the disc of examples/disc_nest.yaml (every fixel's mu in
[0.2, 0.4]; family ``example``), and the seeded arrival family of
test/helpers/arrival_family.py (seed 0, ARRIVAL_TASKS tasks, ``--quick`` the first
QUICK_ARRIVAL_TASKS; every fixel's mu in the task's mu +- 0.1 (at least 0), as in
benchmarks/plan_arrival.py; families ``disc``, ``pivot``, ``bounce``). Per task: the
single-start plan (``plan_seating`` without a region) and the region plan
(``start_region=`` the asked box, the default cover and bisections), whether the region
plan exists for at least the single start (a certified box, which holds the start
pose); for each region plan, VERIFY_STARTS starts drawn uniformly in the CERTIFIED box
by this script's own generator (``numpy.random.default_rng``; a pose at which a fixel
overlaps the part drawn again, as the scene decides), each with every fixel's mu drawn
uniformly in its interval, run in the engine (``execute``): how many seat, and every
failure with its start offset, its friction and the run's reason; then boxes enlarged
past the certified one (per axis the larger of 2 ** k times the certified and
2 ** (k - 1) times the asked half-width, k = 1, 2, 3, dtheta at most pi), ENLARGED_STARTS
starts each, until one shows failures (the certification is not vacuous there). Then
each segment funnel of the region plan (core/plan/segment_funnels.py): VERIFY_STARTS
states (pose and velocity) drawn in its entry region by this script's own generator (an
entry state uniformly, then a state uniformly in the box around it), each under the model of
the run behind its entry state, the plan run from that segment on
(``trace(..., start_segment=, twist=)``): how many seat, every failure; then the region
with boxes 2 ** k times as wide (k = 1 .. FUNNEL_ENLARGE_STEPS), ENLARGED_STARTS states
each, until one shows failures. Then each cone slice of the certificate
(core/plan/region_cones.py): CONE_POSES of its cover poses, each under every corner
model of the plan's friction box, the cones' margin for that model alone against the
engine from rest there (a moving segment's slice: does the part move in the segment's
mode, the engine's own mode letters; a hold's slice: does it end seated), pairs within
CONE_BAND of 0 left out, and a hold's slice where the margin is negative (nothing is
claimed there). The pawl
of examples/pawl_seating.yaml (+-2 mm x +-2 mm x +-5 deg, target 1 2 3) is a task too:
its region planning time is the performance figure. The median certified box per family
(its fraction of the asked volume and its half-widths).

    python benchmarks/plan_region.py --candidates   # benchmarks/results/plan_region_candidates.json

The default run and ``--verify`` certify the search's first plan alone
(``region_candidates=1``, as the planner did before the region search), so that their
recorded results stay what their commands give. ``--candidates``: the region search
(``region_candidates``, core/plan/search.py) against the first plan alone, on the disc
of examples/disc_nest.yaml (+-1 mm x +-1 mm x +-5 deg) and the T-bar of
examples/tbar_swing.yaml (+-2 mm x +-2 mm x +-5 deg), every fixel's mu in [0.2, 0.4],
the default cover, bisections and draws, on 2 worker processes of the planner's own (so
that their CPU time is counted): ``region_candidates`` = 1 and REGION_CANDIDATES, and
the T-bar with goal "seated" too (its search has no guaranteed candidate, so under the
default goal there is nothing to compare). Per run: the plan, the certified box and its
fractions, every plan compared with its box, boxes checked and engine runs in all, wall
time and CPU time (planning process, worker processes); then VERIFY_STARTS starts drawn
uniformly in the certified box by ``--verify``'s generator (seed 101), each with every
fixel's mu drawn in [0.2, 0.4], run in the engine: how many seat. ``--task`` picks runs
by name (disc_1, disc_N, tbar_1, tbar_N, tbar_seated_N).
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)

from helpers.arrival_family import arrival_family  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.geometry import SceneError  # noqa: E402
from wrenchcone_ros.core.plan import (  # noqa: E402
    REGION_CANDIDATES,
    StartRegion,
    exclusive_margin,
    execute,
    slice_cover,
    plan_seating,
    trace,
    run_starts,
    sample_models,
    sample_starts,
)
from wrenchcone_ros.core.plan.region import as_planned  # noqa: E402
from wrenchcone_ros.core.scene_yaml import scene_from_dict  # noqa: E402
from wrenchcone_ros.core.uncertainty import as_uncertainty  # noqa: E402

OUT = harness.RESULTS / "plan_region.json"
STARTS = 1000
WORKERS = 2
TASKS = (
    ("pawl", "pawl_seating.yaml", [1, 2, 3], (0.002, 0.002, math.radians(5.0))),
    ("disc", "disc_nest.yaml", [1, 2], (0.001, 0.001, math.radians(5.0))),
    ("pawl_large", "pawl_seating.yaml", [1, 2, 3], (0.006, 0.01, math.radians(10.0))),
)


def sampled(scene, plan, box: StartRegion, unc, seed: int) -> dict:
    """STARTS starts uniform in ``box``, each with a sampled model, run in the engine."""
    starts = sample_starts(scene, box, STARTS, seed)
    runs = run_starts(scene, plan, starts, sample_models(scene, unc, len(starts), seed),
                      workers=WORKERS)
    fails = [r for r in runs if not r.success]
    reasons: dict[str, int] = {}
    for r in fails:
        key = r.reason.split(" (")[0]
        reasons[key] = reasons.get(key, 0) + 1
    return {"box": box.to_dict(), "starts": len(runs),
            "seated": sum(r.success for r in runs),
            "as_planned": sum(r.matches for r in runs),
            "failure_reasons": reasons,
            "failures": [{"start": list(r.start), "friction": list(r.friction),
                          "reason": r.reason} for r in fails[:10]]}


VERIFY_OUT = harness.RESULTS / "plan_region_verify.json"
VERIFY_STARTS = 1000
ENLARGED_STARTS = 500
ENLARGE_STEPS = 3
FUNNEL_ENLARGE_STEPS = 12
#: cover poses of each cone slice run in the engine (evenly spaced in the cover), each
#: under every corner model of the friction box
CONE_POSES = 6
#: dimensionless: a margin within this of 0 may go either way in the engine (its step and
#: collision slop), so such pose-model pairs are not compared
CONE_BAND = 0.01
#: recorded frames (one every CONE_RECORD steps) in which the engine's mode letters are
#: read after the start
CONE_FRAMES, CONE_RECORD = 5, 5
ARRIVAL_TASKS = 30
QUICK_ARRIVAL_TASKS = 6
MM, DEG = 1e-3, math.radians(1.0)
#: The box asked per task (half-widths m, m, rad): a gripper's placement error; the
#: discs, whose every translation off their pin lifts them, the smaller one.
VERIFY_BOXES = {"example_pawl": (2 * MM, 2 * MM, 5 * DEG),
                "example_tbar": (2 * MM, 2 * MM, 5 * DEG),
                "example_disc": (1 * MM, 1 * MM, 5 * DEG),
                "disc": (1 * MM, 1 * MM, 5 * DEG),
                "pivot": (2 * MM, 2 * MM, 5 * DEG),
                "bounce": (2 * MM, 2 * MM, 5 * DEG)}


def verify_tasks(quick: bool) -> list[dict]:
    """The tasks of ``--verify``: name, family, scene, target, friction interval, box."""
    out = [{"name": "pawl", "family": "example", "source": "examples/pawl_seating.yaml",
            "scene": load_scene(harness.ROOT / "examples" / "pawl_seating.yaml"),
            "target": [1, 2, 3], "friction": (0.2, 0.4), "box": VERIFY_BOXES["example_pawl"]},
           {"name": "tbar", "family": "example", "source": "examples/tbar_swing.yaml",
            "scene": load_scene(harness.ROOT / "examples" / "tbar_swing.yaml"),
            "target": [1, 2], "friction": (0.2, 0.4), "box": VERIFY_BOXES["example_tbar"]},
           {"name": "disc_nest", "family": "example", "source": "examples/disc_nest.yaml",
            "scene": load_scene(harness.ROOT / "examples" / "disc_nest.yaml"),
            "target": [1, 2], "friction": (0.2, 0.4), "box": VERIFY_BOXES["example_disc"]}]
    for t in arrival_family(QUICK_ARRIVAL_TASKS if quick else ARRIVAL_TASKS, seed=0):
        scene = scene_from_dict(t.scene)
        mu = scene.friction
        out.append({"name": t.name, "family": t.kind, "source": "arrival_family(seed 0)",
                    "scene": scene, "target": list(t.target),
                    "friction": (max(0.0, mu - 0.1), mu + 0.1), "box": VERIFY_BOXES[t.kind]})
    return out


def _verify_job(args):
    scene_dict, plan, offset, mu = args
    scene = scene_from_dict(scene_dict)
    x, y, th = scene.pose
    r = execute(scene.with_pose(x + offset[0], y + offset[1], th + offset[2]), plan, mu)
    return offset, mu, r


def drawn(scene, box: StartRegion, friction, count: int, seed: int):
    """``count`` (offset, friction) pairs: offsets uniform in ``box`` (this script's own
    generator; an offset at which the scene says a fixel overlaps the part drawn again,
    at most 100 times ``count`` draws), every fixel's mu uniform in ``friction``."""
    rng = np.random.default_rng(seed)
    h = np.array(box.half_widths)
    x, y, th = scene.pose
    out = []
    for _ in range(100 * count):
        if len(out) >= count:
            break
        off = tuple(float(v) for v in h * rng.uniform(-1.0, 1.0, 3))
        try:
            scene.with_pose(x + off[0], y + off[1], th + off[2])
        except SceneError:
            continue
        out.append((off, tuple(float(v) for v in rng.uniform(*friction, scene.n_fixels))))
    return out


def verify_box(pool, scene, plan, box: StartRegion, friction, count: int, seed: int) -> dict:
    """``count`` starts drawn in ``box`` (:func:`drawn`), run in the engine: how many
    seat (the run's own test), how many as planned, and every failure explained."""
    pairs = drawn(scene, box, friction, count, seed)
    contacts = {i + 1 for i, c in enumerate(scene.in_contact) if c}
    d = scene.to_dict()
    res = list(pool.map(_verify_job, [(d, plan, off, mu) for off, mu in pairs],
                        chunksize=8))
    fails = [{"offset_mm_mm_deg": [off[0] / MM, off[1] / MM, off[2] / DEG],
              "friction": list(mu), "reason": r.reason,
              "final_pose": list(r.final_pose), "events": list(r.events)}
             for off, mu, r in res if not r.success]
    return {"box": box.to_dict(), "starts": len(res),
            "seated": sum(r.success for _, _, r in res),
            "as_planned": sum(as_planned(plan, contacts, r) for _, _, r in res),
            "failures": fails}


def _funnel_job(args):
    scene_dict, plan, segment, state, mu = args
    scene = scene_from_dict(scene_dict)
    r, _ = trace(scene.with_pose(*state[:3]), plan, mu, record_every=0,
                 start_segment=segment, twist=state[3:])
    return state, mu, r


def drawn_states(scene, entries, half_widths, count: int, seed: int):
    """``count`` (entry index, state) pairs: an entry state drawn uniformly, then a state
    uniformly in the box of ``half_widths`` around it (this script's own generator; a
    pose at which the scene says a fixel overlaps the part drawn again, at most 100 times
    ``count`` draws)."""
    rng = np.random.default_rng(seed)
    e, h = np.asarray(entries, dtype=float), np.asarray(half_widths, dtype=float)
    out = []
    for _ in range(100 * count):
        if len(out) >= count:
            break
        i = int(rng.integers(len(e)))
        state = tuple(float(v) for v in rng.uniform(e[i] - h, e[i] + h))
        try:
            scene.with_pose(*state[:3])
        except SceneError:
            continue
        out.append((i, state))
    return out


def verify_funnel_region(pool, scene, plan, funnel, half_widths, count: int,
                         seed: int) -> dict:
    """``count`` states drawn in the funnel's region with boxes of ``half_widths``
    (:func:`drawn_states`), the plan run from its segment on from each, under the model
    of the run behind the entry state it was drawn around: how many seat (the run's own
    test), every failure."""
    picked = drawn_states(scene, funnel.entries, half_widths, count, seed)
    d = scene.to_dict()
    lean = replace(plan, region=None)
    res = list(pool.map(_funnel_job, [(d, lean, funnel.segment, st, funnel.models[i])
                                      for i, st in picked], chunksize=8))
    fails = [{"state": list(st), "friction": list(r.friction), "reason": r.reason,
              "final_pose": list(r.final_pose), "events": list(r.events)}
             for st, _, r in res if not r.success]
    return {"half_widths": list(half_widths), "states": len(res),
            "seated": sum(r.success for _, _, r in res), "failures": fails}


def verify_funnels(pool, scene, plan, friction) -> list[dict]:
    """Each segment funnel of the plan's certificate: VERIFY_STARTS states drawn in its
    entry region, then in the region with boxes 2 ** k times as wide around the entry
    states (k = 1 .. FUNNEL_ENLARGE_STEPS), ENLARGED_STARTS states each, until one shows
    failures."""
    out = []
    for f in plan.region.segment_funnels:
        row = {"segment": f.segment, "holds": f.holds, "observed": f.observed,
               "tube": f.tube, "planner_draws": f.draws, "planner_passed": f.passed}
        if f.entries:
            h = np.asarray(f.half_widths)
            row["region"] = verify_funnel_region(pool, scene, plan, f, h, VERIFY_STARTS,
                                                 seed=301 + f.segment)
            row["enlarged"] = []
            for k in range(1, FUNNEL_ENLARGE_STEPS + 1):
                v = verify_funnel_region(pool, scene, plan, f, 2 ** k * h,
                                         ENLARGED_STARTS, seed=400 + 10 * f.segment + k)
                v["factor"] = 2 ** k
                row["enlarged"].append(v)
                if v["seated"] < v["states"]:
                    break
        out.append(row)
    return out


def enlarged(certified: StartRegion, asked: StartRegion, k: int) -> StartRegion:
    """The k-th box past the certified one (module docstring)."""
    h = [max(2 ** k * c, 2 ** (k - 1) * a)
         for c, a in zip(certified.half_widths, asked.half_widths)]
    return StartRegion(h[0], h[1], min(math.pi, h[2]))


def verify_one(pool, task: dict) -> dict:
    scene, target, friction = task["scene"], task["target"], task["friction"]
    asked = StartRegion.of(task["box"])
    row = {"family": task["family"], "source": task["source"], "target": target,
           "friction": list(friction), "asked": asked.to_dict()}
    t0 = time.perf_counter()
    single = plan_seating(scene, target, uncertainty=friction, simulate_runs=False)
    row["single"] = {"feasible": single.feasible, "guaranteed": single.guaranteed,
                     "nominal_seated": bool(single.nominal and single.nominal.success),
                     "modes": [s.mode for s in single.segments],
                     "planning_wall_s": time.perf_counter() - t0}
    if not single.feasible:
        row["region"] = None
        row["solved_by_single"] = False
        return row
    # solved: guaranteed (its capture test passed at the start, which the region's first
    # box reruns); a plan that is not guaranteed is reported beside it
    row["solved_by_single"] = single.guaranteed
    t0 = time.perf_counter()
    plan = plan_seating(scene, target, uncertainty=friction, simulate_runs=False,
                        workers=WORKERS, pool=pool, start_region=asked,
                        region_candidates=1)
    cert = plan.region
    row["region"] = cert.to_dict()
    row["region_planning_wall_s"] = time.perf_counter() - t0
    row["same_plan_as_single"] = [(s.mode, s.direction, s.scale) for s in plan.segments] \
        == [(s.mode, s.direction, s.scale) for s in single.segments]
    row["region_plan_covers_the_single_start"] = plan.start_region is not None
    if plan.start_region is None:
        return row
    t0 = time.perf_counter()
    row["certified_box"] = verify_box(pool, scene, plan, plan.start_region, friction,
                                      VERIFY_STARTS, seed=101)
    row["enlarged"] = []
    for k in range(1, ENLARGE_STEPS + 1):
        big = enlarged(plan.start_region, asked, k)
        v = verify_box(pool, scene, plan, big, friction, ENLARGED_STARTS, seed=200 + k)
        row["enlarged"].append(v)
        if v["seated"] < v["starts"]:
            break
    row["funnels"] = verify_funnels(pool, scene, plan, friction)
    row["cones"] = verify_cones(scene, plan, row["region"])
    row["verification_wall_s"] = time.perf_counter() - t0
    return row


def _engine_moves(scene, plan, piece, pose, model) -> bool:
    """The engine's answer at a cover pose (no cone involved): from rest there under
    ``model``, the plan run from the slice's segment on. A moving segment's slice: does
    the part move in the segment's mode in the first recorded frames (the engine's own
    mode letters)? A hold's slice, lifted off a fixel by micrometres (inside the
    engine's contact band, where its letters say contact): does the part end seated?"""
    run, frames = trace(scene.with_pose(*pose), plan, model, record_every=CONE_RECORD,
                        start_segment=piece["segment"])
    if piece["lifted"]:
        return bool(run.success)
    mode = plan.segments[piece["segment"] - 1].mode
    return any(f.readout.letters == mode for f in frames[:CONE_FRAMES])


def verify_cones(scene, plan, cert: dict) -> list[dict]:
    """Each cone slice of the certificate against the engine: CONE_POSES of its cover
    poses, each under every corner model of the plan's friction box; the cones' margin
    for that model alone (> 0: the requirement holds) against what the engine does
    there (:func:`_engine_moves`); pairs within CONE_BAND of 0 are not compared, nor a
    hold's slice where the margin is negative (nothing is claimed there)."""
    out = []
    corners = list(itertools.product(*[(lo, hi) for lo, hi in plan.friction]))
    for piece in cert.get("cone_slices", []):
        row = {"segment": piece["segment"], "lifted": piece["lifted"],
               "holds": piece["holds"], "points": piece["points"],
               "compared": 0, "agree": 0, "within_band": 0, "not_claimed": 0,
               "disagreements": []}
        if piece["points"]:
            seg = plan.segments[piece["segment"] - 1]
            c = np.asarray(scene.pose)
            if piece["segment"] == 1:
                h = np.asarray(plan.start_region.half_widths)
                lo, hi = c - h, c + h
            else:
                f = next(f for f in plan.region.segment_funnels
                         if f.segment == piece["segment"])
                lo, hi = f.pose_bounds
            kept = [i - 1 for i in piece["contacts"]]
            poses, _ = slice_cover(scene, seg.start_pose, kept, lo, hi)
            pick = [poses[int(k)] for k in
                    np.unique(np.linspace(0, len(poses) - 1, CONE_POSES).round())]
            def allowed(mode: str, m: int = piece["lifted"] - 1, want: str = seg.mode
                        ) -> bool:
                return mode[m] == "a" if m >= 0 else mode == want
            for pose in pick:
                for model in corners:
                    u = as_uncertainty([(v, v) for v in model])
                    margin = exclusive_margin(scene.with_pose(*pose), allowed,
                                              plan.actuator.directions_point, u)[0](
                        seg.direction)
                    if abs(margin) < CONE_BAND:
                        row["within_band"] += 1
                        continue
                    if piece["lifted"] and margin < 0:
                        # only modes approaching it is not claimed: a part may still
                        # approach in a mode that is not the only one
                        row["not_claimed"] += 1
                        continue
                    moves = _engine_moves(scene, plan, piece, pose, model)
                    row["compared"] += 1
                    if moves == (margin > 0):
                        row["agree"] += 1
                    else:
                        row["disagreements"].append({"pose": list(pose), "mu": list(model),
                                                     "margin": margin, "engine": moves})
        out.append(row)
    return out


def summary(rows: dict) -> dict:
    """Per family: tasks, solved by the single-start planner (a guaranteed plan) and how
    many of those have a region plan certified for at least the single start, the
    feasible plans that are not guaranteed and how many of those have a certified box,
    the median certified box over the tasks with one, the verification's totals."""
    out = {}
    for fam in sorted({r["family"] for r in rows.values()}):
        rs = [r for r in rows.values() if r["family"] == fam]
        solved = [r for r in rs if r["solved_by_single"]]
        others = [r for r in rs if r["single"]["feasible"] and not r["solved_by_single"]]
        # every task with a certified box, the guaranteed ones and the others
        certs = [r for r in solved + others if r.get("region_plan_covers_the_single_start")]
        boxes = [r["region"]["certified"] for r in certs]
        ver = [r["certified_box"] for r in certs]
        out[fam] = {
            "tasks": len(rs), "solved_by_single": len(solved),
            "solved_with_a_region_plan_for_at_least_the_single_start": sum(
                bool(r.get("region_plan_covers_the_single_start")) for r in solved),
            "feasible_not_guaranteed": len(others),
            "feasible_not_guaranteed_with_a_certified_box": sum(
                bool(r.get("region_plan_covers_the_single_start")) for r in others),
            "tasks_with_a_certified_box": len(certs),
            "median_fraction_of_asked": statistics.median(
                [r["region"]["fraction"] for r in certs]) if certs else None,
            "median_certified_mm_mm_deg": [
                statistics.median([b["dx"] / MM for b in boxes]),
                statistics.median([b["dy"] / MM for b in boxes]),
                statistics.median([b["dtheta_deg"] for b in boxes])] if boxes else None,
            "whole_box_certified": sum(r["region"]["whole"] for r in certs),
            "verified_starts": sum(v["starts"] for v in ver),
            "verified_seated": sum(v["seated"] for v in ver),
            "smallest_seated_fraction": min((v["seated"] / v["starts"] for v in ver
                                             if v["starts"]), default=None),
            "enlarged_with_failures": sum(
                any(e["seated"] < e["starts"] for e in r["enlarged"]) for r in certs),
            "segment_funnels": sum(len(r.get("funnels", [])) for r in certs),
            "segment_funnels_holding": sum(f["holds"] for r in certs
                                           for f in r.get("funnels", [])),
            "funnel_states_verified": sum(f["region"]["states"] for r in certs
                                          for f in r.get("funnels", []) if "region" in f),
            "funnel_states_seated": sum(f["region"]["seated"] for r in certs
                                        for f in r.get("funnels", []) if "region" in f),
            "cone_slices": sum(len(r.get("cones", [])) for r in certs),
            "cone_slices_holding": sum(c["holds"] for r in certs
                                       for c in r.get("cones", [])),
            "cone_slice_poses": sum(c["points"] for r in certs for c in r.get("cones", [])),
            "cone_engine_compared": sum(c["compared"] for r in certs
                                        for c in r.get("cones", [])),
            "cone_engine_agree": sum(c["agree"] for r in certs for c in r.get("cones", [])),
            "funnels_enlarged_with_failures": sum(
                any(e["seated"] < e["states"] for e in f.get("enlarged", []))
                for r in certs for f in r.get("funnels", []))}
    return out


def verify(args) -> int:
    facts = harness.machine_facts()
    tasks = verify_tasks(args.quick)
    if args.task:
        unknown = sorted(set(args.task) - {t["name"] for t in tasks})
        if unknown:
            print(f"unknown task(s) {unknown}; known: {[t['name'] for t in tasks]}",
                  file=sys.stderr)
            return 2
        tasks = [t for t in tasks if t["name"] in args.task]
    rows = {}
    t_all = time.perf_counter()
    with ProcessPoolExecutor(max_workers=WORKERS) as pool:
        for task in tasks:
            t0 = time.perf_counter()
            row = verify_one(pool, task)
            row["wall_s"] = time.perf_counter() - t0
            rows[task["name"]] = row
            cb = row.get("certified_box")
            print(task["name"], row["family"], "single feasible",
                  row["single"]["feasible"], "certified",
                  None if not row.get("region") else row["region"]["certified"],
                  "verified", None if cb is None else (cb["seated"], cb["starts"]),
                  "enlarged", [(e["seated"], e["starts"]) for e in row.get("enlarged", [])],
                  "funnels", [(f["segment"], f["holds"], f.get("region", {}).get("seated"),
                               f.get("region", {}).get("states"),
                               [(e["factor"], e["seated"], e["states"])
                                for e in f.get("enlarged", [])])
                              for f in row.get("funnels", [])],
                  "cones", [(c["segment"], c["lifted"], c["holds"], c["agree"], c["compared"])
                            for c in row.get("cones", [])],
                  f"{row['wall_s']:.0f} s", flush=True)
    harness.write_json(None if args.no_write else VERIFY_OUT, facts, {
        "quick": args.quick, "tasks_run": list(rows), "starts": VERIFY_STARTS,
        "enlarged_starts": ENLARGED_STARTS, "workers": WORKERS,
        "total_wall_s": time.perf_counter() - t_all, "summary": summary(rows),
        "tasks": rows})
    return 0


CANDIDATES_OUT = harness.RESULTS / "plan_region_candidates.json"


def candidate_runs() -> list[dict]:
    """The runs of ``--candidates`` (module docstring), in the order run."""
    n = REGION_CANDIDATES
    disc = ("disc_nest.yaml", VERIFY_BOXES["example_disc"])
    tbar = ("tbar_swing.yaml", VERIFY_BOXES["example_tbar"])
    return [{"name": "disc_1", "task": disc, "goal": "guaranteed", "candidates": 1},
            {"name": "disc_N", "task": disc, "goal": "guaranteed", "candidates": n},
            {"name": "tbar_1", "task": tbar, "goal": "guaranteed", "candidates": 1},
            {"name": "tbar_seated_N", "task": tbar, "goal": "seated", "candidates": n},
            {"name": "tbar_N", "task": tbar, "goal": "guaranteed", "candidates": n}]


def candidates(args) -> int:
    facts = harness.machine_facts()
    runs = candidate_runs()
    if args.task:
        runs = [r for r in runs if r["name"] in args.task]
    rows = {}
    t_all = time.perf_counter()
    for run in runs:
        path, box = run["task"]
        scene = load_scene(harness.ROOT / "examples" / path)
        asked = StartRegion.of(box)
        t0, c0, k0 = time.perf_counter(), time.process_time(), os.times()
        plan = plan_seating(scene, [1, 2], uncertainty=(0.2, 0.4), simulate_runs=False,
                            workers=WORKERS, start_region=asked, goal=run["goal"],
                            region_candidates=run["candidates"])
        k1 = os.times()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        children = (k1.children_user + k1.children_system
                    - k0.children_user - k0.children_system)
        cert = plan.region
        row = {"scene": f"examples/{path}", "target": [1, 2], "friction": [0.2, 0.4],
               "goal": run["goal"], "region_candidates": run["candidates"],
               "asked": asked.to_dict(), "guaranteed": plan.guaranteed,
               "plan": [{"mode": s.mode, "direction_deg": math.degrees(s.direction),
                         "scale": s.scale} for s in plan.segments],
               "search_candidates": plan.candidates, "search_trials": plan.trials,
               "region": cert.to_dict(),
               "plans_certified": max(1, len(cert.compared)),
               "boxes_checked": cert.compared_boxes, "engine_runs": cert.compared_runs,
               "planning_wall_s": wall, "planning_cpu_s": cpu, "workers_cpu_s": children,
               "tried_region": [t for t in plan.tried if t.startswith("region:")]}
        if plan.start_region is not None:
            with ProcessPoolExecutor(max_workers=WORKERS) as pool:
                t1 = time.perf_counter()
                row["certified_box"] = verify_box(pool, scene, plan, plan.start_region,
                                                  (0.2, 0.4), VERIFY_STARTS, seed=101)
                row["verification_wall_s"] = time.perf_counter() - t1
        rows[run["name"]] = row
        cb = row.get("certified_box")
        print(run["name"], "plans certified", row["plans_certified"], "chosen",
              cert.chosen, "certified", cert.certified, f"{100 * cert.fraction:.1f} %",
              "boxes", row["boxes_checked"], "runs", row["engine_runs"],
              f"wall {wall:.0f} s cpu {cpu + children:.0f} s",
              "verified", None if cb is None else (cb["seated"], cb["starts"]), flush=True)
    harness.write_json(None if args.no_write else CANDIDATES_OUT, facts, {
        "region_candidates_default": REGION_CANDIDATES, "workers": WORKERS,
        "starts": VERIFY_STARTS, "total_wall_s": time.perf_counter() - t_all,
        "runs": rows})
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--verify", action="store_true",
                    help="the verification across tasks (module docstring)")
    ap.add_argument("--quick", action="store_true",
                    help=f"--verify on the arrival family's first {QUICK_ARRIVAL_TASKS} tasks")
    ap.add_argument("--candidates", action="store_true",
                    help="the region search against the first plan alone (module "
                    "docstring)")
    ap.add_argument("--task", action="append",
                    help="--verify or --candidates: only this task (repeatable)")
    ap.add_argument("--no-write", action="store_true", help="print only")
    args = ap.parse_args()
    if args.candidates:
        return candidates(args)
    if args.verify:
        return verify(args)
    facts = harness.machine_facts()
    out = {}
    for name, path, target, box in TASKS:
        scene = load_scene(harness.ROOT / "examples" / path)
        unc = as_uncertainty((0.2, 0.4), scene)
        t0, c0, k0 = time.perf_counter(), time.process_time(), os.times()
        plan = plan_seating(scene, target, uncertainty=unc, simulate_runs=False,
                            workers=WORKERS, start_region=box,
                            region_candidates=1)
        k1 = os.times()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        children = (k1.children_user + k1.children_system
                    - k0.children_user - k0.children_system)
        cert = plan.region
        row = {"scene": f"examples/{path}", "target": target, "friction": [0.2, 0.4],
               "asked": StartRegion.of(box).to_dict(), "guaranteed": plan.guaranteed,
               "segments": [{"mode": s.mode, "direction_deg": math.degrees(s.direction),
                             "scale": s.scale} for s in plan.segments],
               "region": cert.to_dict(), "planning_wall_s": wall,
               "planning_cpu_s": cpu, "workers_cpu_s": children}
        certified = plan.start_region
        if certified is not None:
            row["certified_box"] = sampled(scene, plan, certified, unc, 0)
            twice = StartRegion(2 * certified.dx, 2 * certified.dy,
                                min(math.pi, 2 * certified.dtheta))
            row["twice_the_box"] = sampled(scene, plan, twice, unc, 1)
            if not cert.whole:
                row["asked_box"] = sampled(scene, plan, StartRegion.of(box), unc, 2)
        print(name, row)
        out[name] = row
    harness.write_json(OUT, facts, {"tasks": out, "starts": STARTS, "workers": WORKERS})
    return 0


if __name__ == "__main__":
    sys.exit(main())
