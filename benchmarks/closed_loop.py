#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Closed loop over real DDS against open loop in the engine, on the same sampled models.

    source install/setup.bash
    python benchmarks/closed_loop.py --tasks pawl_seating   # (the two were run at once)
    python benchmarks/closed_loop.py --tasks pawl_wedged
    # each writes benchmarks/results/closed_loop_<task>.json; --models 10 --no-write: a try

Tasks (each fixel's mu in [0.2, 0.4]; the models every fixel's mu drawn uniformly in its
interval, ``sample_models`` seed 0, the planner's own sampler):

* ``pawl_seating``: examples/pawl_seating.yaml, target 1 2 3 (a guaranteed plan);
* ``pawl_wedged``: examples/pawl_polygon.yaml, target 1 2 3 (a plan that is not
  guaranteed: the pawl may wedge against the stop and pin 2).

Open loop: the core's plan (``plan_seating``, the same goal) executed in the engine for
each model (``execute``: the plan's directions switched on the engine's contact events).
Closed loop: ``wrenchcone_ros.sim.loop.Loop``: tray_sim (pymunk, real time), the
wrenchcone node and tilt_controller in one process, three DDS participants; per model the
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


def run_task(name: str, n: int, seed: int, timeout: float) -> dict:
    from wrenchcone_ros.sim.loop import Loop

    path, target = TASKS[name]
    scene = load_scene(ROOT / path)
    U = Uncertainty(friction=FRICTION)
    models = sample_models(scene, U, n, seed)
    plan = plan_seating(scene, target, "tilt", uncertainty=FRICTION, runs=0)
    open_ok = [execute(scene, plan, m).success for m in models]
    closed, lat_wall, lat_sim, states, plans, walls, misses = [], [], [], {}, [], [], []
    calls: dict[str, list[float]] = {}
    not_idle = 0
    with Loop(ROOT / path, target, FRICTION,
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
        lag = loop.tray.lag
    T = time_scale(scene, Actuator().force_magnitude(scene))
    both = sum(a and b for a, b in zip(open_ok, closed))
    return {
        "scene": path, "target": target, "friction": list(FRICTION), "models": n,
        "seed": seed, "plan_guaranteed": bool(plan.guaranteed),
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
        "tray_largest_lag_s": lag, "closed_loop_misses": misses}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tasks", nargs="*", default=list(TASKS), choices=list(TASKS))
    ap.add_argument("--timeout", type=float, default=60.0, help="wall s per closed-loop run")
    ap.add_argument("--json", default=str(ROOT / "benchmarks/results/closed_loop_{task}.json"),
                    help="one file per task ({task} is replaced by its name)")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    for name in args.tasks:
        facts = harness.machine_facts()
        t0 = time.perf_counter()
        r = run_task(name, args.models, args.seed, args.timeout)
        print(f"{name}: open loop {r['open_loop_seated']} of {r['models']} seated, closed loop "
              f"{r['closed_loop_seated']} of {r['models']} (both {r['seated_by_both']}, "
              f"closed only {r['closed_only']}, open only {r['open_only']}); controller "
              f"{r['controller_final_states']}; pose -> command median "
              f"{r['latency_pose_to_command_ms']['median']:.1f} ms, T "
              f"{r['time_scale_T_ms']:.0f} ms ({time.perf_counter() - t0:.0f} s)", flush=True)
        if not args.no_write:
            harness.write_json(args.json.format(task=name), facts, {name: r})
    return 0


if __name__ == "__main__":
    sys.exit(main())
