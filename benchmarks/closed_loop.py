#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Closed loop over real DDS against open loop in the engine, on the same sampled models.

    source install/setup.bash
    python benchmarks/closed_loop.py --tasks pawl_seating   # (the two were run at once)
    python benchmarks/closed_loop.py --tasks pawl_wedged
    # each writes benchmarks/results/closed_loop_lockstep_<task>.json (lockstep, the
    # default; with --real-time: closed_loop_<task>.json); --models 10 --no-write: a try
    python benchmarks/closed_loop.py --family seating --family-tasks 8 --models 13
    python benchmarks/closed_loop.py --family arrival --family-tasks 10 --models 10
    # each writes benchmarks/results/closed_loop_lockstep_family_<family>.json
    # (with --real-time: closed_loop_family_<family>.json)

Tasks (each fixel's mu in [0.2, 0.4]; the models every fixel's mu drawn uniformly in its
interval, ``sample_models`` seed 0, the planner's own sampler):

* ``pawl_seating``: examples/pawl_seating.yaml, target 1 2 3 (a guaranteed plan);
* ``pawl_wedged``: examples/pawl_polygon.yaml, target 1 2 3 (a plan that is not
  guaranteed: the pawl may wedge against the stop and pin 2).

Families (``--family``): the planner's test families, the first ``--family-tasks`` of
each, ``--models`` models per task (so the family's total is tasks x models):
``seating`` (test/helpers/seating_family.py: the pawl with its pins, com, stop and
start offset varied, mu in [0.2, 0.4]) and ``arrival`` (test/helpers/arrival_family.py:
discs, pivots and sliding L parts that reach their last pin moving, each fixel's mu in
the task's mu +- 0.1, as benchmarks/plan_arrival.py) and ``users``
(test/helpers/user_fixtures.py: the families' and the examples' parts and two new shapes
on pins of unequal radii, 1.5 to 5 mm, the fixture frame turned and half of them
mirrored, each fixel's mu in the task's mu +- 0.1). Tasks without a plan are counted and
skipped (no loop to close).

Open loop: the core's plan (``plan_seating``, the same goal) executed in the engine for
each model (``execute``: the plan's directions switched on the engine's contact events).
Closed loop: ``wrenchcone_ros.sim.loop.Loop``: tray_sim (pymunk), the wrenchcone node and
tilt_controller in one process, three DDS participants, in lockstep (the tray advances
once the controller has answered its last pose: the same results on any machine; a run
ends TIMEOUT after the Loop's ``sim_timeout`` of sim time), or with ``--real-time`` the
tray against the wall clock (real time: what the latency below means against T is
measured there; a run ends TIMEOUT after ``--timeout`` wall s); per model the
tray is reset to the start pose with that model, the controller reuses its first plan
for the same start (``reuse_plan``) and asks the node again for every replan. Seated: the
tray's truth (every target fixel within the engine's contact band, the part at rest).
Latency: wall time from the tray publishing a pose to the tray receiving the command
stamped with that pose (one control step: force_directions and classify_wrench round
trips), and the motion's time scale T = sqrt(m L / |F|) beside it; the wall time of each
of the controller's calls to the node, by service (where a step's time goes); the runs
whose tray was reset while the previous run's controller had not ended.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.core.plan import execute, plan_seating, sample_models  # noqa: E402
from wrenchcone_ros.core.simulate import Actuator, time_scale  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TASKS = {"pawl_seating": ("examples/pawl_seating.yaml", [1, 2, 3]),
         "pawl_wedged": ("examples/pawl_polygon.yaml", [1, 2, 3])}
FRICTION = (0.2, 0.4)


def family_tasks(family: str, n: int) -> list[tuple[str, object, list[int], tuple]]:
    """(name, scene, target, friction interval) of the first ``n`` tasks of a family."""
    if family == "seating":
        from helpers.seating_family import seating_family

        return [(t.name, load_scene(t.scene), [1, 2, 3], FRICTION)
                for t in seating_family(n)]
    if family == "users":
        from helpers.user_fixtures import user_family

        return [(t.name, load_scene(t.scene), list(t.target), tuple(t.friction))
                for t in user_family(n)]
    from helpers.arrival_family import arrival_family

    out = []
    for t in arrival_family(n):
        scene = load_scene(t.scene)
        mu = scene.friction
        out.append((t.name, scene, list(t.target), (max(0.0, mu - 0.1), mu + 0.1)))
    return out


def run_task(name: str, n: int, seed: int, timeout: float, *, scene=None, target=None,
             friction=FRICTION, lockstep: bool = True) -> dict:
    from wrenchcone_ros.core.plan import PlanError
    from wrenchcone_ros.sim.loop import Loop

    if scene is None:
        path, target = TASKS[name]
        scene = load_scene(ROOT / path)
    else:
        path = name
    U = Uncertainty(friction=tuple(friction))
    models = sample_models(scene, U, n, seed)
    try:
        plan = plan_seating(scene, target, "tilt", uncertainty=tuple(friction), runs=0)
    except PlanError as exc:
        return {"scene": path, "models": n, "no_plan": str(exc).splitlines()[0]}
    if not plan.feasible:
        return {"scene": path, "models": n, "no_plan": "no feasible plan"}
    open_ok = [execute(scene, plan, m).success for m in models]
    closed, lat_wall, lat_sim, states, plans, walls, misses = [], [], [], {}, [], [], []
    calls: dict[str, list[float]] = {}
    not_idle = lockstep_timeouts = 0
    with Loop(scene, target, list(friction), lockstep=lockstep,
              controller_parameters={"reuse_plan": True}) as loop:
        for m in models:
            t0 = time.perf_counter()
            r = loop.run(m, timeout=timeout)
            walls.append(time.perf_counter() - t0)
            closed.append(r.seated)
            if not r.seated or r.state != "SEATED":
                misses.append({"model": len(closed) - 1, "friction": list(m.friction),
                               "seated": r.seated, "state": r.state, "reason": r.reason,
                               "plans": r.plans, "letters": r.letters})
            states[r.state] = states.get(r.state, 0) + 1
            plans.append(r.plans)
            lat_wall += [w for w, _ in r.latencies]
            lat_sim += [s for _, s in r.latencies]
            for service, times in r.calls.items():
                calls.setdefault(service, []).extend(times)
            not_idle += not r.previous_idle
            lockstep_timeouts += r.lockstep_timeouts
        lag = loop.tray.lag
    T = time_scale(scene, Actuator().force_magnitude(scene))
    both = sum(a and b for a, b in zip(open_ok, closed))
    return {
        "scene": path, "target": target, "friction": list(friction), "models": n,
        "seed": seed, "lockstep": lockstep, "lockstep_timeouts": lockstep_timeouts,
        "plan_guaranteed": bool(plan.guaranteed),
        "plan_modes": [s.mode for s in plan.segments],
        "open_loop_seated": sum(open_ok), "closed_loop_seated": sum(closed),
        "seated_by_both": both, "closed_only": sum(b and not a for a, b in zip(open_ok, closed)),
        "open_only": sum(a and not b for a, b in zip(open_ok, closed)),
        "controller_final_states": states, "plans_per_run_median": statistics.median(plans),
        "plans_per_run_max": max(plans),
        "latency_pose_to_command_ms": harness.summary(lat_wall, 1e3),
        "latency_sim_ms": harness.summary(lat_sim, 1e3),
        "controller_calls_ms": {k: harness.summary(v, 1e3) for k, v in sorted(calls.items())},
        "previous_controller_not_idle": not_idle,
        "time_scale_T_ms": T * 1e3, "run_wall_s_median": statistics.median(walls),
        "tray_largest_lag_s": lag, "closed_loop_misses": misses,
        # runs whose controller's verdict (SEATED or not) is not the tray's truth
        "controller_disagrees": sum(x["seated"] != (x["state"] == "SEATED") for x in misses)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tasks", nargs="*", default=list(TASKS), choices=list(TASKS))
    ap.add_argument("--timeout", type=float, default=None,
                    help="wall s per closed-loop run (default 60 in real time; in lockstep "
                    "a guard only, default 600: its runs end by sim time)")
    ap.add_argument("--real-time", action="store_true",
                    help="the tray in real time instead of lockstep (latency against T)")
    ap.add_argument("--json", default=None,
                    help="one file per task ({task} is replaced by its name; default "
                    "benchmarks/results/closed_loop_lockstep_{task}.json in lockstep, "
                    "closed_loop_{task}.json in real time)")
    ap.add_argument("--family", choices=["seating", "arrival", "users"],
                    help="run a test family instead of --tasks")
    ap.add_argument("--family-tasks", type=int, default=8)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    if args.timeout is None:
        args.timeout = 60.0 if args.real_time else 600.0
    if args.json is None:
        args.json = str(ROOT / "benchmarks/results" / (
            "closed_loop_{task}.json" if args.real_time else "closed_loop_lockstep_{task}.json"))
    if args.family:
        return run_family(args)
    for name in args.tasks:
        facts = harness.machine_facts()
        t0 = time.perf_counter()
        r = run_task(name, args.models, args.seed, args.timeout,
                     lockstep=not args.real_time)
        print(f"{name}: open loop {r['open_loop_seated']} of {r['models']} seated, closed loop "
              f"{r['closed_loop_seated']} of {r['models']} (both {r['seated_by_both']}, "
              f"closed only {r['closed_only']}, open only {r['open_only']}); controller "
              f"{r['controller_final_states']}; pose -> command median "
              f"{r['latency_pose_to_command_ms']['median']:.1f} ms, T "
              f"{r['time_scale_T_ms']:.0f} ms ({time.perf_counter() - t0:.0f} s)", flush=True)
        if not args.no_write:
            harness.write_json(args.json.format(task=name), facts, {name: r})
    return 0


def run_family(args) -> int:
    """Every task of ``args.family``, and the family's sums (guaranteed plans and the
    others apart)."""
    facts = harness.machine_facts()
    rows = []
    for name, scene, target, friction in family_tasks(args.family, args.family_tasks):
        t0 = time.perf_counter()
        r = run_task(name, args.models, args.seed, args.timeout, scene=scene,
                     target=target, friction=friction, lockstep=not args.real_time)
        r["name"] = name
        rows.append(r)
        if "no_plan" in r:
            print(f"{name}: no plan ({r['no_plan']})", flush=True)
            continue
        print(f"{name}: {'guaranteed' if r['plan_guaranteed'] else 'not guaranteed'}; open "
              f"{r['open_loop_seated']}, closed {r['closed_loop_seated']} of {r['models']} "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
    sums = {}
    for kind, want in (("guaranteed", True), ("not_guaranteed", False)):
        sel = [r for r in rows if "no_plan" not in r and r["plan_guaranteed"] == want]
        sums[kind] = {"tasks": len(sel), "models": sum(r["models"] for r in sel),
                      "open_loop_seated": sum(r["open_loop_seated"] for r in sel),
                      "closed_loop_seated": sum(r["closed_loop_seated"] for r in sel),
                      "tasks_closed_fewer": sum(r["closed_loop_seated"] < r["open_loop_seated"]
                                                for r in sel)}
    sums["no_plan"] = sum("no_plan" in r for r in rows)
    print(f"{args.family}: {sums}", flush=True)
    if not args.no_write:
        mode = "" if args.real_time else "lockstep_"
        harness.write_json(ROOT / f"benchmarks/results/closed_loop_{mode}family_{args.family}.json",
                           facts, {"family": args.family, "models_per_task": args.models,
                                   "seed": args.seed, "sums": sums, "tasks": rows})
    return 0


if __name__ == "__main__":
    sys.exit(main())
