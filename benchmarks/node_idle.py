# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What an idle node costs: the node program started without a scene file, given no
inputs and no requests, beside an empty rclpy node spun by the same executor
(:func:`wrenchcone_ros.node.executors.make_executor`), both in their own process for the
same time.

For each process: CPU time (user + system, from ``/proc/PID/stat``, over the measured
window only: start-up excluded), as a percentage of one core, and the context switches
of all its threads (``/proc/PID/task/*/status``: each voluntary switch is a thread going
to sleep, i.e. about one wake-up). Run after ``make build`` and
``source install/setup.bash``::

    python benchmarks/node_idle.py --seconds 60 --json benchmarks/results/node_idle.json
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import harness  # noqa: E402
from harness.ros import PYTHON, READY_TIMEOUT_S, STOP_TIMEOUT_S  # noqa: E402,F401

#: An empty node spun as the program spins the wrenchcone node.
EMPTY_NODE = """
import rclpy, sys
from rclpy.node import Node
from wrenchcone_ros.node.executors import make_executor
rclpy.init()
node = Node("empty_idle")
executor = make_executor()
executor.add_node(node)
print("ready", flush=True)
try:
    executor.spin()
except KeyboardInterrupt:
    pass
"""


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process so far (s)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def switches(pid: int) -> tuple[int, int]:
    """(voluntary, involuntary) context switches of every thread of a process so far."""
    vol = inv = 0
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            for line in (task / "status").read_text().splitlines():
                if line.startswith("voluntary_ctxt_switches"):
                    vol += int(line.split()[1])
                elif line.startswith("nonvoluntary_ctxt_switches"):
                    inv += int(line.split()[1])
        except OSError:  # a thread that ended meanwhile
            pass
    return vol, inv


def start(argv: list[str], ready: str) -> subprocess.Popen:
    """Start a process and wait until a line of its output contains ``ready``."""
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    deadline = time.monotonic() + READY_TIMEOUT_S
    for line in proc.stdout:
        if ready in line:
            return proc
        if time.monotonic() > deadline:
            break
    proc.kill()
    raise SystemExit(f"{argv[:4]}... did not say {ready!r}")


def stop(proc: subprocess.Popen) -> int:
    proc.send_signal(2)
    try:
        return proc.wait(STOP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        return proc.wait()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="measured window (s)")
    ap.add_argument("--settle", type=float, default=5.0,
                    help="seconds after 'ready' before the window starts")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()
    facts = harness.machine_facts()
    ns = f"/idle{os.getpid()}"
    procs = {
        "wrenchcone_node": start([*PYTHON, "-m", "wrenchcone_ros.node", "--ros-args",
                                  "-r", f"__ns:={ns}"], "ready: active"),
        "empty_node": start([*PYTHON, "-c", EMPTY_NODE, "--ros-args", "-r",
                             f"__ns:={ns}"], "ready"),
    }
    # their output is not read from here on: nothing may block on a full pipe
    for proc in procs.values():
        proc.stdout.close()
    time.sleep(args.settle)
    begin = {k: (time.monotonic(), cpu_seconds(p.pid), switches(p.pid))
             for k, p in procs.items()}
    time.sleep(args.seconds)
    results = {}
    for k, p in procs.items():
        t0, c0, (v0, i0) = begin[k]
        t1, c1, (v1, i1) = time.monotonic(), cpu_seconds(p.pid), switches(p.pid)
        wall = t1 - t0
        results[k] = {"wall_s": round(wall, 3), "cpu_s": round(c1 - c0, 3),
                      "cpu_percent_of_core": round(100.0 * (c1 - c0) / wall, 3),
                      "voluntary_switches_per_s": round((v1 - v0) / wall, 2),
                      "involuntary_switches_per_s": round((i1 - i0) / wall, 2)}
    for k, p in procs.items():
        results[k]["exit_code"] = stop(p)
    results["node_minus_empty_percent"] = round(
        results["wrenchcone_node"]["cpu_percent_of_core"]
        - results["empty_node"]["cpu_percent_of_core"], 3)
    for k in ("wrenchcone_node", "empty_node"):
        r = results[k]
        print(f"{k:16s} {r['cpu_percent_of_core']:7.3f} % of a core "
              f"({r['cpu_s']:.2f} s CPU in {r['wall_s']:.1f} s), "
              f"{r['voluntary_switches_per_s']:.1f} wake-ups/s")
    if args.json:
        harness.write_json(args.json, facts, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
