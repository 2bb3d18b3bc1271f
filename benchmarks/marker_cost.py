# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Per-snapshot cost of the node's published messages: ~/markers vs the monitored cones.

In-process, no DDS: for 1, 4 and 16 monitored modes of the node-latency scene (a square
on two pins with three free fixels), each of ``--snapshots`` fresh snapshots computes the
monitored cones (``answers.monitored_answers``, what every snapshot costs anyway), then
builds the MarkerArray (``markers.scene_markers``) and the WrenchCone messages. Medians
of the same run; the ratio markers / cones is the figure to quote (docs/node.md, "RViz
markers").

Usage (install/setup.bash sourced): python benchmarks/marker_cost.py [--snapshots N]
"""

from __future__ import annotations

import argparse
import os
import time

from harness import median
from harness.ros import SQUARE, conv, feasible_modes

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.node.markers import scene_markers
from wrenchcone_ros.node.answers import monitored_answers
from wrenchcone_ros.node.store import Snapshot


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--snapshots", type=int, default=100)
    args = ap.parse_args()
    scene = load_scene(SQUARE)
    feasible = feasible_modes(SQUARE)
    print(f"load average at start: {os.getloadavg()}")
    print("| monitored modes | markers | cones median ms | markers median ms | "
          "WrenchCone msgs median ms | markers / cones |")
    print("| --- | --- | --- | --- | --- | --- |")
    for k in (1, 4, 16):
        modes = feasible[:k]
        cones, markers, msgs, n = [], [], [], 0
        for i in range(args.snapshots):
            snap = Snapshot(i + 1, scene, 0, "", "world", (i, 0), None)
            t0 = time.perf_counter()
            answers = monitored_answers(snap, modes)
            t1 = time.perf_counter()
            n = len(scene_markers(snap, modes, answers).markers)
            t2 = time.perf_counter()
            for m, a in answers.items():
                conv.cone_message(m, a.status, a.message, a.cone, frame_id="world",
                                  stamp=(i, 0), inputs_version=i + 1)
            t3 = time.perf_counter()
            cones.append(t1 - t0)
            markers.append(t2 - t1)
            msgs.append(t3 - t2)
        c, m, w = median(cones), median(markers), median(msgs)
        print(f"| {k} | {n} | {1e3 * c:.2f} | {1e3 * m:.2f} | {1e3 * w:.2f} | {m / c:.2f} |")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
