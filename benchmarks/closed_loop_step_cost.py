#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What one control step of tilt_controller costs the core, without ROS: the computation
behind its two calls to the node, at poses of the pawl's slide.

    python benchmarks/closed_loop_step_cost.py   # writes closed_loop_step_cost.json

At each of ``--poses`` poses of the nominal pawl's slide (examples/pawl_seating.yaml,
the plan's first segment simulated in the engine) under the loop's contact tolerance
(the engine's contact band) and uncertainty (every fixel's mu in [0.2, 0.4]), once per
pose (a new pose is a new question: nothing cached): ``force_directions`` of the
segment's mode, exclusive, for every model (what the node computes for the controller's
force_directions call), and the robust classification of the commanded pull
(``consistent_modes`` with the uncertainty: its classify_wrench call); the nominal ones beside them.
Medians over the poses; compare with the controller's call times in
closed_loop_<task>.json (the round trip over DDS in the loaded loop process).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import harness  # noqa: E402

from wrenchcone_ros.core import (  # noqa: E402
    Uncertainty,
    consistent_modes,
    load_scene,
    plan_seating,
)
from wrenchcone_ros.core.directions import force_directions  # noqa: E402
from wrenchcone_ros.core.simulate import simulate  # noqa: E402
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FRICTION = (0.2, 0.4)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=30)
    ap.add_argument("--json", default=str(ROOT / "benchmarks/results/closed_loop_step_cost.json"))
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    facts = harness.machine_facts()
    scene = load_scene(ROOT / "examples/pawl_seating.yaml")
    scene = replace(scene, contact_tolerance=SIM_CONTACT_BAND * scene.length_scale)
    plan = plan_seating(scene, [1, 2, 3], "tilt", uncertainty=FRICTION, runs=0)
    seg = plan.segments[0]
    trace = simulate(scene, seg.direction, duration=seg.duration)
    frames = [f for f in trace.frames if f.letters == seg.mode]
    picked = frames[:: max(1, len(frames) // args.poses)][: args.poses]
    U = Uncertainty(friction=FRICTION)
    f_pull = plan.actuator.force_magnitude(scene) * seg.scale  # N
    g = (f_pull * math.cos(seg.direction), f_pull * math.sin(seg.direction), 0.0)
    times: dict[str, list[float]] = {k: [] for k in (
        "force_directions_robust", "classify_robust", "force_directions_nominal",
        "classify_nominal")}
    force_directions(scene.with_pose(*picked[0].pose), seg.mode, exclusive=True)  # warm
    for f in picked:
        s = scene.with_pose(*f.pose)
        for key, fn in (
                ("force_directions_robust",
                 lambda s=s: force_directions(s, seg.mode, exclusive=True, uncertainty=U)),
                ("classify_robust", lambda s=s: consistent_modes(s, g, uncertainty=U)),
                ("force_directions_nominal",
                 lambda s=s: force_directions(s, seg.mode, exclusive=True)),
                ("classify_nominal", lambda s=s: consistent_modes(s, g))):
            t0 = time.perf_counter()
            fn()
            times[key].append(time.perf_counter() - t0)
    out = {"scene": "examples/pawl_seating.yaml", "mode": seg.mode,
           "poses": len(picked), "friction": list(FRICTION),
           "contact_tolerance_m": scene.contact_tolerance,
           "ms": {k: harness.summary(v, 1e3) for k, v in times.items()}}
    for k, v in out["ms"].items():
        print(f"{k}: median {v['median']:.1f} ms (90th percentile {v['p90']:.1f} ms, "
              f"{v['n']} poses)")
    if not args.no_write:
        harness.write_json(args.json, facts, {"closed_loop_step_cost": out})
    return 0


if __name__ == "__main__":
    sys.exit(main())
