# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Watchers inside a benchmark's processes (node_stream.py, its pose publisher and
listener, and the instrumented node ``harness/instrumented_node.py``).

* :func:`watch_pauses` starts a daemon thread that sleeps ``PAUSE_POLL_S`` at a time and
  records when it woke more than ``PAUSE_MS`` late: the process was held up (its GIL
  held by another thread, or not scheduled), so whatever it timed then includes that.
* :func:`watch_gc` records the process's garbage collections longer than ``GC_MS``.
* :func:`dump_every` starts a daemon thread that rewrites a JSON file with ``record``
  every ``period_s`` (write, then rename: a reader never sees half a file).
"""

from __future__ import annotations

import gc
import json
import os
import threading
import time
from collections.abc import Callable
from typing import Any

PAUSE_POLL_S = 0.005  # s: the watchdog's sleep
PAUSE_MS = 50.0  # ms: a wake-up this late is recorded
GC_MS = 5.0  # ms: a garbage collection this long is recorded


def watch_pauses(record: list, detail: Callable[[], Any] | None = None) -> None:
    """Append (wall clock s, ms late) to ``record`` for every late wake-up, plus
    ``detail()`` (e.g. every thread's stack) when given."""

    def run() -> None:
        last = time.perf_counter()
        while True:
            time.sleep(PAUSE_POLL_S)
            now = time.perf_counter()
            late_ms = (now - last) * 1e3
            if late_ms > PAUSE_MS:
                record.append((time.time(), late_ms) if detail is None
                              else (time.time(), late_ms, detail()))
            last = now

    threading.Thread(target=run, name="watchdog", daemon=True).start()


def watch_gc(record: list) -> None:
    """Append (wall clock s at its end, generation, ms) to ``record`` for every garbage
    collection longer than ``GC_MS``."""
    start = [0.0]

    def on_gc(phase: str, info: dict) -> None:
        if phase == "start":
            start[0] = time.perf_counter()
            return
        ms = (time.perf_counter() - start[0]) * 1e3
        if ms > GC_MS:
            record.append((time.time(), info["generation"], ms))

    gc.callbacks.append(on_gc)


def dump_every(path: str, record: Any, period_s: float) -> None:
    """Rewrite ``path`` with ``record`` (JSON) every ``period_s`` seconds."""

    def run() -> None:
        while True:
            time.sleep(period_s)
            with open(path + ".tmp", "w") as f:
                json.dump(record, f)
            os.replace(path + ".tmp", path)

    threading.Thread(target=run, name="watch-dump", daemon=True).start()
