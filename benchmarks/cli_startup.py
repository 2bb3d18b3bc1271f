#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Start-up of the ``wrenchcone`` command against the interpreter's own start-up.

    python benchmarks/cli_startup.py [--runs 15] [--json FILE]

Each run starts, in a new process and in this order, ``python -c pass`` (the floor: the
interpreter and its site-packages, nothing of the package), ``wrenchcone --version`` and
``wrenchcone --help`` (the console script of the interpreter's environment), output
discarded; the three are interleaved run by run so that the machine's load hits them
alike. Each start is timed twice: wall time, and the CPU time (user + system) the process
used, which a loaded machine changes much less (waiting for a core is not counted).
Printed and recorded: the median and the spread of each over the runs, and each
command's median over the floor's. The package imported is this checkout's
(``PYTHONPATH`` puts it first), so the figures are those of the code beside this script.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import harness

#: The package directory whose ``wrenchcone_ros`` the commands import (this checkout's).
PACKAGE = harness.ROOT / "wrenchcone_ros"
#: What is timed, in the order of each run: label -> the command after the interpreter's
#: directory ("python": the interpreter itself).
COMMANDS = {
    "python -c pass": ["python", "-c", "pass"],
    "wrenchcone --version": ["wrenchcone", "--version"],
    "wrenchcone --help": ["wrenchcone", "--help"],
}


def _environment(package: Path) -> dict[str, str]:
    path = os.environ.get("PYTHONPATH", "")
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(package), path) if p)}


def _argv(command: list[str]) -> list[str]:
    if command[0] == "python":
        return [sys.executable, *command[1:]]
    return [str(Path(sys.executable).parent / command[0]), *command[1:]]


def _time_command(argv: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(wall s, CPU s) of one run of ``argv`` to its end (this process starts no other
    child meanwhile, so the children's CPU time it gained is this one's)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(argv, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, timeout=120)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise RuntimeError(f"{' '.join(argv)} exited {out.returncode}: {out.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def startup_samples(runs: int, package: Path = PACKAGE,
                    commands: dict[str, list[str]] | None = None
                    ) -> dict[str, dict[str, list[float]]]:
    """Wall and CPU times (s) of each command, ``runs`` runs interleaved command by
    command.

    Parameters
    ----------
    runs : int
        Runs; each starts every command once, in the order of ``commands``.
    package : Path
        The directory put first on PYTHONPATH (the ``wrenchcone_ros`` imported).
    commands : dict or None
        label -> command (default: COMMANDS); "python" and console scripts are taken
        from this interpreter's directory.

    Returns
    -------
    dict
        label -> {"wall": the ``runs`` wall times, "cpu": their CPU times}, s.
    """
    commands = COMMANDS if commands is None else commands
    env = _environment(package)
    for command in commands.values():  # once, untimed: the file system's caches filled
        _time_command(_argv(command), env)
    samples: dict[str, dict[str, list[float]]] = {
        label: {"wall": [], "cpu": []} for label in commands}
    for _ in range(runs):
        for label, command in commands.items():
            wall, cpu = _time_command(_argv(command), env)
            samples[label]["wall"].append(wall)
            samples[label]["cpu"].append(cpu)
    return samples


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=15, help="runs (default %(default)s)")
    ap.add_argument("--package", type=Path, default=PACKAGE,
                    help="the directory holding the wrenchcone_ros package to import "
                         "(default: this checkout's)")
    ap.add_argument("--json", help="also write the results to this file")
    args = ap.parse_args()
    facts = harness.machine_facts()
    samples = startup_samples(args.runs, args.package.resolve())
    floor = {k: harness.median(samples["python -c pass"][k]) for k in ("wall", "cpu")}
    print(harness.header_line(facts, harness.loadavg(), f"commit {facts['git']}"))
    print()
    print("| command | runs | wall median ms | wall min-max ms | wall / python -c pass "
          "| CPU median ms | CPU / python -c pass |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    results = {}
    for label, times in samples.items():
        wall, cpu = times["wall"], times["cpu"]
        med, cmed = harness.median(wall), harness.median(cpu)
        results[label] = {"runs": len(wall), "median_ms": med * 1e3,
                          "min_ms": min(wall) * 1e3, "max_ms": max(wall) * 1e3,
                          "ratio_to_python": med / floor["wall"],
                          "cpu_median_ms": cmed * 1e3,
                          "cpu_ratio_to_python": cmed / floor["cpu"],
                          "samples_ms": [x * 1e3 for x in wall],
                          "cpu_samples_ms": [x * 1e3 for x in cpu]}
        print(f"| `{label}` | {len(wall)} | {med * 1e3:.0f} | {min(wall) * 1e3:.0f}-"
              f"{max(wall) * 1e3:.0f} | {med / floor['wall']:.2f} | {cmed * 1e3:.0f} | "
              f"{cmed / floor['cpu']:.2f} |")
    package = args.package.resolve()
    if package.is_relative_to(harness.ROOT):  # recorded relative to the repository
        package = package.relative_to(harness.ROOT)
    harness.write_json(args.json, facts, {"package": str(package), "commands": results})
    return 0


if __name__ == "__main__":
    sys.exit(main())
