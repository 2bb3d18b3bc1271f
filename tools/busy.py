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
speed. The busy processes end with this process, however it ends (SIGTERM, SIGHUP and
SIGINT stop COMMAND and them; on Linux the kernel kills them when it is killed).
"""

from __future__ import annotations

import argparse
import ctypes
import os
import signal
import subprocess
import sys
import time

SPIN = "while True:\n    pass"
MEMORY = ("import numpy as np\na = np.ones(1 << 22)\nwhile True:\n    b = a.copy()\n"
          "    a += 1e-9 * b")


def _die_with_parent() -> None:
    """In a child, before exec: ask Linux to SIGKILL it when its parent dies
    (prctl PR_SET_PDEATHSIG), so that no busy process outlives a killed run."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1: PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass  # not Linux: the signal handlers below still stop them


def _exit_on_signal(signum: int, _frame) -> None:
    raise SystemExit(128 + signum)


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
    for signum in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, _exit_on_signal)
    child = None
    try:
        for core in cores:
            for k in range(args.per_core):
                kind = args.kind if args.kind != "mixed" else ("spin", "memory")[k % 2]
                h = subprocess.Popen([sys.executable, "-c", SPIN if kind == "spin" else MEMORY],
                                     stdin=subprocess.DEVNULL, preexec_fn=_die_with_parent)
                if core is not None:
                    os.sched_setaffinity(h.pid, {core})
                hogs.append(h)
        time.sleep(1.0)
        print(f"busy: {len(hogs)} busy processes on {len(cores)} core(s); load average "
              f"at the start {os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
        t0 = time.monotonic()
        child = subprocess.Popen(command)
        status = child.wait()
        print(f"busy: {' '.join(command)} exited {status} after "
              f"{time.monotonic() - t0:.0f} s; load average at the end "
              f"{os.getloadavg()[0]:.2f}", file=sys.stderr, flush=True)
        return status
    finally:
        if child is not None and child.poll() is None:
            child.terminate()
            try:
                child.wait(30)
            except subprocess.TimeoutExpired:
                child.kill()
        for h in hogs:
            h.kill()
            h.wait()


if __name__ == "__main__":
    sys.exit(main())
