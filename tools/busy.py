#!/usr/bin/env python3
# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Run a command on a busy machine: N busy processes per core beside it.

    python tools/busy.py [--per-core N] [--kind spin|memory] -- COMMAND [ARG ...]

Starts ``N`` busy processes pinned to each core this process may run on (``spin``: a
pure-Python loop; ``memory``: a loop copying a 32 MiB array, a neighbour on the caches
and the memory bus; default: one of each per core for N = 2), runs COMMAND, stops them
and exits with COMMAND's status. The load average at the start and at the end and
COMMAND's wall time are printed on stderr. ``make test-loaded`` runs the test suite
this way (docs/testing.md): a suite that passes here does not depend on the machine's
speed.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time

SPIN = "while True:\n    pass"
MEMORY = ("import numpy as np\na = np.ones(1 << 22)\nwhile True:\n    b = a.copy()\n"
          "    a += 1e-9 * b")


def main(argv: list[str] | None = None) -> int:
    """Parse the options, run the command beside the busy processes; its exit status.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The command's exit status (2 for a bad option).
    """
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-core", type=int, default=2, metavar="N",
                    help="busy processes per core (default %(default)s)")
    ap.add_argument("--kind", choices=("mixed", "spin", "memory"), default="mixed",
                    help="what they do (default %(default)s: alternately spin and memory)")
    ap.add_argument("command", nargs=argparse.REMAINDER, help="-- COMMAND [ARG ...]")
    args = ap.parse_args(argv)
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        ap.error("give the command to run after --")
    if args.per_core < 0:
        ap.error(f"--per-core must be >= 0, got {args.per_core}")
    cores = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else [None]
    hogs = []
    try:
        for core in cores:
            for k in range(args.per_core):
                kind = args.kind if args.kind != "mixed" else ("spin", "memory")[k % 2]
                h = subprocess.Popen([sys.executable, "-c", SPIN if kind == "spin" else MEMORY],
                                     stdin=subprocess.DEVNULL)
                if core is not None:
                    os.sched_setaffinity(h.pid, {core})
                hogs.append(h)
        time.sleep(1.0)
        print(f"busy: {len(hogs)} busy processes on {len(cores)} core(s); load average "
              f"at the start {os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
        t0 = time.monotonic()
        status = subprocess.call(command)
        print(f"busy: {' '.join(command)} exited {status} after "
              f"{time.monotonic() - t0:.0f} s; load average at the end "
              f"{os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
        return status
    finally:
        for h in hogs:
            h.kill()
            h.wait()


if __name__ == "__main__":
    sys.exit(main())
