# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""tools/busy.py: the busy processes end with it, however it ends (a killed loaded run
must not leave them behind, slowing everything after it)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

BUSY = Path(__file__).resolve().parents[2] / "tools" / "busy.py"


def children(pid: int) -> set[int]:
    """The pids whose parent is ``pid`` (Linux /proc)."""
    out = set()
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                out.add(int(entry))
    return out


def alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def wait_for(predicate, limit: float = 30.0) -> bool:
    end = time.monotonic() + limit
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return predicate()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL])
def test_the_busy_processes_end_when_busy_is_stopped_and_the_command_on_sigterm(how):
    proc = subprocess.Popen([sys.executable, str(BUSY), "--per-core", "1", "--kind", "spin",
                             "--", sys.executable, "-c", "import time; time.sleep(120)"],
                            stderr=subprocess.PIPE, text=True)
    try:
        # the busy processes, then the command: one per core plus one
        cores = len(os.sched_getaffinity(0))
        assert wait_for(lambda: len(children(proc.pid)) == cores + 1), children(proc.pid)
        kids = children(proc.pid)
        if how == signal.SIGKILL:  # no handler runs: the kernel ends the busy processes;
            kids = {k for k in kids if "time.sleep" not in  # the command lives on
                    Path(f"/proc/{k}/cmdline").read_text()}
            assert len(kids) == cores
        os.kill(proc.pid, how)
        proc.wait(30)
        assert wait_for(lambda: not any(alive(k) for k in kids)), \
            f"left behind after {signal.Signals(how).name}: " \
            f"{[k for k in kids if alive(k)]}"
    finally:  # what the code under test left behind, killed here
        for k in kids if "kids" in locals() else children(proc.pid):
            if alive(k):
                os.kill(k, signal.SIGKILL)
        proc.kill()
        proc.wait()
