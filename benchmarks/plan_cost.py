#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans checked in simulation: what they cost, how often they succeed, and how well the
engine agrees with the cones.

    python benchmarks/plan_cost.py               # writes benchmarks/results/plan_cost.json
    python benchmarks/plan_cost.py --quick --no-write

Four parts, one run (wall clock, ``time.perf_counter``):

1. The pawl's plan (examples/pawl_seating.yaml, every pin's mu in [0.2, 0.4]) with 100
   simulated models, in 2 worker processes and in 1 (the baseline, same run,
   interleaved), ``REPEATS`` times each; and the plan alone (no Monte Carlo). One plan
   is made untimed first (the cone kernel is loaded, or compiled, then).
2. The simulation's cost per simulated second: steps of ``Simulation`` (pymunk step +
   the applied force) with and without the per-step readout, for the pawl, the paper's
   disc and random non-convex scenes with 1, 3 and 5 fixels; the real-time factor is
   wall time / simulated time.
3. Agreement of the engine's letters at t = 0 (``initial_mode``) with ``consistent_modes``
   on random scenes (test/strategies.random_scene, a random pull at the com), where
   exactly one mode is consistent with margin >= each threshold; every disagreement is
   listed.
4. Success rates (100 sampled models, seed 0) and contradicted events of the plans of
   the examples: pawl_seating, pawl_tipped, pawl_polygon (its own pose, 4 mm from the
   stop), pawl_seating pulled by a spring at the top of its upright, and tbar_swing.
5. The wedge of pawl_polygon: for every sampled model whose run does not seat the part,
   its final pose in the engine, and the cones at that pose (the seated part turned
   about the stop and pin 2 until pin 3's gap is the engine's, core.plan.lifted_scene):
   whether nns (stuck against the stop and pin 2, off pin 3) is consistent for that
   model, and for the friction set (possible / certain, core.robust).
6. The acceptance point on a seeded family of seating tasks (test/helpers/seating_family.py,
   ``--family`` variants, seed ``--family-seed``): per plan feasible, guaranteed (every
   segment's margin > 0), the success rate over 100 sampled models, the contact events
   (each segment's simulated event against the predicted one, and the sampled runs whose
   events differ from the plan's); the smallest success rate of the guaranteed plans.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402
import harness.source_tree  # noqa: E402,F401  (this checkout's package first)
from harness import median  # noqa: E402

from helpers.seating_family import SEAT_X, seating_family  # noqa: E402
from helpers.strategies import random_scene  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    Uncertainty,
    consistent_modes,
    default_scene,
    load_scene,
)
from wrenchcone_ros.core.plan import lifted_scene, plan_seating  # noqa: E402
from wrenchcone_ros.core.simulate import Actuator, Simulation, initial_mode  # noqa: E402
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND  # noqa: E402

OUT = harness.RESULTS / "plan_cost.json"
EX = harness.ROOT / "examples"
REPEATS = 3
THRESHOLDS = (0.01, 0.05, 0.1)


def part_plan_time(runs: int) -> dict:
    scene = load_scene(EX / "pawl_seating.yaml")
    out = {"runs": runs, "workers_2_s": [], "workers_1_s": [], "plan_only_s": []}
    # untimed: load (or compile) the cone kernel and warm the caches first
    plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), simulate_runs=False)
    for _ in range(REPEATS):
        for key, kw in (("workers_2_s", {"workers": 2}), ("workers_1_s", {"workers": 1}),
                        ("plan_only_s", {"simulate_runs": False})):
            t0 = time.perf_counter()
            plan = plan_seating(scene, [1, 2, 3], uncertainty=(0.2, 0.4), runs=runs, **kw)
            out[key].append(time.perf_counter() - t0)
            assert plan.feasible
    out["median"] = {k: median(v) for k, v in out.items() if isinstance(v, list)}
    out["speedup_2_workers"] = median(a / b for a, b in zip(out["workers_1_s"],
                                                            out["workers_2_s"]))
    print(f"pawl plan with {runs} models: 2 workers {out['median']['workers_2_s']:.2f} s, "
          f"1 worker {out['median']['workers_1_s']:.2f} s (x{out['speedup_2_workers']:.2f}), "
          f"plan only {out['median']['plan_only_s']:.2f} s", flush=True)
    return out


def _scenes(rng) -> list[tuple[str, object, float]]:
    cases = [("pawl_seating", load_scene(EX / "pawl_seating.yaml"), math.radians(-58.5)),
             ("paper_disc", default_scene(), math.radians(-80.0))]
    for n in (1, 3, 5):
        g = random_scene(rng, shape="nonconvex", n_fixels=n)
        cases.append((f"random_nonconvex_{n}_fixels", load_scene(g.data),
                      float(rng.uniform(-math.pi, math.pi))))
    return cases


def part_sim_cost(simulated_T: float) -> list[dict]:
    rng = np.random.default_rng(11)
    rows = []
    for name, scene, phi in _scenes(rng):
        rec = {"scene": name, "fixels": scene.n_fixels}
        for key, readout in (("step_only", False), ("step_and_readout", True)):
            walls, sims = [], []
            for _ in range(REPEATS):
                sim = Simulation(scene, Actuator(), phi)
                steps = int(round(simulated_T * sim.sp.time_scale / sim.dt))
                t0 = time.perf_counter()
                for _ in range(steps):
                    sim.step()
                    if readout:
                        sim.readout()
                walls.append(time.perf_counter() - t0)
                sims.append(sim.t)
            rec[key] = {"steps": steps, "wall_s": median(walls), "simulated_s": sims[0],
                        "wall_per_simulated_s": median(w / s for w, s in zip(walls, sims)),
                        "us_per_step": 1e6 * median(walls) / steps}
        rows.append(rec)
        print(f"{name:<28} {rec['step_only']['us_per_step']:7.1f} us/step, "
              f"{rec['step_and_readout']['us_per_step']:7.1f} us/step with readout; "
              f"wall / simulated time {rec['step_only']['wall_per_simulated_s']:.3f} "
              f"({rec['step_and_readout']['wall_per_simulated_s']:.3f})", flush=True)
    return rows


def part_agreement(n_scenes: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    out = {"scenes": n_scenes, "seed": seed, "by_threshold": {}, "disagreements": []}
    compared = {t: 0 for t in THRESHOLDS}
    agree = {t: 0 for t in THRESHOLDS}
    for k in range(n_scenes):
        g = random_scene(rng)
        scene = load_scene(g.data)
        phi = float(rng.uniform(-math.pi, math.pi))
        ms = consistent_modes(scene, (math.cos(phi), math.sin(phi), 0.0))
        if len(ms) != 1 or ms[0].margin < min(THRESHOLDS):
            continue
        seen = initial_mode(scene, phi)
        for t in THRESHOLDS:
            if ms[0].margin >= t:
                compared[t] += 1
                agree[t] += seen == ms[0].mode
        if seen != ms[0].mode:
            out["disagreements"].append({
                "draw": k, "predicted": ms[0].mode, "margin": ms[0].margin,
                "simulated": seen, "shape": g.shape, "mu": g.notes["mu"],
                "fixels": scene.n_fixels, "in_contact": list(scene.in_contact),
                "pins": list(g.pin_radii), "phi": phi})
    for t in THRESHOLDS:
        out["by_threshold"][str(t)] = {"compared": compared[t], "agree": agree[t],
                                       "rate": agree[t] / max(compared[t], 1)}
        print(f"margin >= {t}: {agree[t]} of {compared[t]} agree "
              f"({100.0 * agree[t] / max(compared[t], 1):.1f} %)", flush=True)
    for d in out["disagreements"]:
        print(f"  draw {d['draw']}: predicted {d['predicted']} (margin {d['margin']:.3f}), "
              f"simulated {d['simulated']}; {d['shape']}, mu {d['mu']:.3g}", flush=True)
    return out


def part_success(runs: int) -> list[dict]:
    cases = [("pawl_seating", "pawl_seating.yaml", "tilt", [1, 2, 3]),
             ("pawl_tipped", "pawl_tipped.yaml", "tilt", [1, 2, 3]),
             ("pawl_polygon", "pawl_polygon.yaml", "tilt", [1, 2, 3]),
             ("pawl_seating_spring", "pawl_seating.yaml", "spring:0.0075,0.035", [1, 2, 3]),
             ("tbar_swing", "tbar_swing.yaml", "tilt", [1, 2])]
    rows = []
    for name, f, act, target in cases:
        t0 = time.perf_counter()
        plan = plan_seating(load_scene(EX / f), target, act, uncertainty=(0.2, 0.4),
                            runs=runs, seed=0)
        wall = time.perf_counter() - t0
        fails: dict[str, int] = {}
        for r in plan.runs:
            if not r.success:
                fails[r.reason] = fails.get(r.reason, 0) + 1
        rows.append({"case": name, "actuator": act, "feasible": plan.feasible,
                     "guaranteed": plan.guaranteed, "reason": plan.reason,
                     "modes": [s.mode for s in plan.segments],
                     "directions_deg": [math.degrees(s.direction) for s in plan.segments],
                     "margins": [s.margin for s in plan.segments],
                     "worst_margin": plan.worst_margin, "success_rate": plan.success_rate,
                     "runs": len(plan.runs), "contradicted": plan.contradicted,
                     "failures": fails, "wall_s": wall,
                     "failed_final_poses": [list(r.final_pose) for r in plan.runs
                                            if not r.success]})
        print(f"{name:<22} {'/'.join(rows[-1]['modes'])}: worst margin "
              f"{plan.worst_margin:.4f}, success {100.0 * plan.success_rate:.1f} % of "
              f"{len(plan.runs)}, contradicted {plan.contradicted}, failures {fails}, "
              f"{wall:.1f} s", flush=True)
    return rows


def _model(scene, mus):
    return load_scene({**scene.to_dict(), "fixels": [
        {"position": list(f.position), "radius": f.radius, "friction": float(m)}
        for f, m in zip(scene.fixels, mus)]})


def part_wedge(runs: int) -> dict:
    scene = load_scene(EX / "pawl_polygon.yaml")
    U = Uncertainty(friction=(0.2, 0.4))
    plan = plan_seating(scene, [1, 2, 3], uncertainty=U, runs=runs, seed=0)
    phi = plan.segments[-1].direction
    g = (math.cos(phi), math.sin(phi), 0.0)
    seated = scene.with_pose(SEAT_X, 0.2, 0.0)
    band_scene = replace(scene, contact_tolerance=SIM_CONTACT_BAND * scene.length_scale)
    rows = []
    for r in plan.runs:
        if r.success:
            continue
        gaps = band_scene.with_pose(*r.final_pose).gaps
        wedge = lifted_scene(seated, 2, [0, 1], gaps[2])
        modes = consistent_modes(_model(wedge, r.friction), g)
        robust = {m.mode: m for m in consistent_modes(wedge, g, uncertainty=U, frame="com")}
        nns = robust.get("nns")
        rows.append({"friction": list(r.friction), "final_pose": list(r.final_pose),
                     "engine_gaps": list(gaps), "cones_pose": list(wedge.pose),
                     "modes": [m.mode for m in modes],
                     "nns_margin": next((m.margin for m in modes if m.mode == "nns"), None),
                     "nns_possible": bool(nns and nns.possible),
                     "nns_certain": bool(nns and nns.certain)})
    hold = plan.segments[-1]
    out = {"direction_deg": math.degrees(phi), "runs": len(plan.runs),
           "failed": len(rows), "guaranteed": plan.guaranteed, "reason": plan.reason,
           "hold_margin": hold.hold_margin, "segment_margin": hold.margin,
           "theta_mrad": [1e3 * w["final_pose"][2] for w in rows],
           "nns_only_mode": sum(w["modes"] == ["nns"] for w in rows),
           "nns_possible_for_the_set": sum(w["nns_possible"] for w in rows),
           "nns_certain_for_the_set": sum(w["nns_certain"] for w in rows),
           "funnel": [c.to_dict() for c in hold.funnel], "wedges": rows}
    th = out["theta_mrad"]
    print(f"pawl_polygon wedge: {len(rows)} of {len(plan.runs)} runs end wedged "
          f"(theta {min(th, default=0):.2f} .. {max(th, default=0):.2f} mrad); nns the only "
          f"consistent mode of the run's model at its wedge in {out['nns_only_mode']}, "
          f"possible for the set in {out['nns_possible_for_the_set']}, certain in "
          f"{out['nns_certain_for_the_set']}; {plan.reason}", flush=True)
    return out


def part_family(n: int, seed: int, runs: int) -> dict:
    rows = []
    for task in seating_family(n, seed):
        t0 = time.perf_counter()
        plan = plan_seating(load_scene(task.scene), [1, 2, 3], uncertainty=(0.2, 0.4),
                            runs=runs, seed=0)
        moving = [s for s in plan.segments if not s.hold]
        rows.append({"name": task.name, "params": task.params, "feasible": plan.feasible,
                     "guaranteed": plan.guaranteed, "reason": plan.reason,
                     "modes": [s.mode for s in plan.segments],
                     "margins": [s.margin for s in plan.segments],
                     "success_rate": plan.success_rate, "runs": len(plan.runs),
                     "events_as_predicted": all(s.event == s.predicted_event for s in moving),
                     "nominal_matches": bool(plan.nominal and plan.nominal.matches),
                     "contradicted": plan.contradicted,
                     "wall_s": time.perf_counter() - t0})
        r = rows[-1]
        print(f"{task.name:<12} {'/'.join(r['modes']) or '-':<16} guaranteed "
              f"{r['guaranteed']!s:<5} success {r['success_rate']} contradicted "
              f"{r['contradicted']} {plan.reason[:80]}", flush=True)
    feasible = [r for r in rows if r["feasible"]]
    sure = [r for r in feasible if r["guaranteed"]]
    other = [r for r in feasible if not r["guaranteed"]]
    out = {"variants": n, "seed": seed, "runs_per_plan": runs, "feasible": len(feasible),
           "guaranteed": len(sure),
           "guaranteed_min_success_rate": min((r["success_rate"] for r in sure),
                                              default=None),
           "guaranteed_below_99": [r["name"] for r in sure if r["success_rate"] < 0.99],
           "not_guaranteed_success_rates": [r["success_rate"] for r in other],
           "segments_with_predicted_event": sum(
               len(r["modes"]) - 1 for r in feasible if r["events_as_predicted"]),
           "segments": sum(len(r["modes"]) - 1 for r in feasible),
           "nominal_events_match": sum(r["nominal_matches"] for r in feasible),
           "sampled_runs": sum(r["runs"] for r in feasible),
           "sampled_runs_contradicted": sum(r["contradicted"] for r in feasible),
           "plans": rows}
    print(f"family: {len(feasible)} of {n} feasible, {len(sure)} guaranteed (smallest success "
          f"rate {out['guaranteed_min_success_rate']}), not guaranteed: "
          f"{out['not_guaranteed_success_rates']}; predicted events "
          f"{out['segments_with_predicted_event']} of {out['segments']} segments; sampled runs "
          f"contradicted {out['sampled_runs_contradicted']} of {out['sampled_runs']}",
          flush=True)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer runs and scenes (smoke)")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--family", type=int, default=40, help="seating tasks of the family")
    ap.add_argument("--family-seed", type=int, default=0)
    args = ap.parse_args()
    facts = harness.machine_facts()
    runs = 20 if args.quick else 100
    results = {
        "plan_time": part_plan_time(runs),
        "simulation_cost": part_sim_cost(2.0 if args.quick else 20.0),
        "agreement": part_agreement(100 if args.quick else 1000, seed=1),
        "success": part_success(runs),
        "wedge": part_wedge(runs),
        "family": part_family(4 if args.quick else args.family, args.family_seed, runs),
    }
    if not args.no_write:
        harness.write_json(OUT, facts, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
