# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The wrenchcone node as ``python -m wrenchcone_ros.node`` runs it, with its public
timing hooks recorded: what in the node could hold up its replies or its published F.

Written to $WRENCHCONE_INSTRUMENT_FILE (JSON, rewritten every ``DUMP_PERIOD_S``), each
entry stamped so that it can be matched with other processes' records:

* ``requests``: every reply computed in Python (the node's ``on_request`` hook):
  [service, start, end] on ``time.perf_counter`` (CLOCK_MONOTONIC: comparable across
  processes of one machine);
* ``slow_steps``: publishing-worker steps (the ``on_step`` hook: a snapshot's cones,
  every topic's message) longer than ``STEP_MS``: [wall s, ms];
* ``idle``: intervals longer than ``IDLE_MS`` between the end of one worker step and the
  start of the next, stamped at their start: [wall s, ms];
* ``pauses``: a Python thread that sleeps 5 ms at a time woke more than 50 ms late
  (``watch.watch_pauses``: the GIL held that long, or the process not scheduled), with
  the stacks of every thread just after: [wall s, ms, stacks];
* ``gc``: garbage collections longer than 5 ms (``watch.watch_gc``): [wall s, generation, ms].

Run by ``harness.ros.NodeProcess(..., instrument=FILE)`` (node_stream.py ``--watch`` and
``--decompose``). Benchmark tooling only: it sets the two hooks (``node.worker.on_step``,
``node.on_request``, through ``wrenchcone_node.run(configure=...)``) and adds two daemon
threads (the watchdog costs about 1 % of a core); the node is otherwise the program.
"""

from __future__ import annotations

import os
import sys
import threading
import traceback

# run as a script (``python -P``, see harness.ros.PYTHON): benchmarks/ on the path
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from harness.watch import dump_every, watch_gc, watch_pauses  # noqa: E402

from wrenchcone_ros.node import wrenchcone_node  # noqa: E402

OUT = os.environ["WRENCHCONE_INSTRUMENT_FILE"]
STEP_MS = 15.0  # ms: a worker step this long is recorded
IDLE_MS = 50.0  # ms: the worker idle this long between two steps is recorded
DUMP_PERIOD_S = 0.2
RECORD: dict[str, list] = {"requests": [], "slow_steps": [], "idle": [], "pauses": [],
                           "gc": []}
_last_end = [0.0, 0.0]  # perf_counter and wall clock at the end of the last step


def on_request(t) -> None:
    RECORD["requests"].append((t.service, t.started, t.started + t.duration_s))


def on_step(t) -> None:
    if _last_end[0] and (t.started - _last_end[0]) * 1e3 > IDLE_MS:
        RECORD["idle"].append((_last_end[1], (t.started - _last_end[0]) * 1e3))
    _last_end[:] = [t.started + t.duration_s, t.started_wall + t.duration_s]
    if t.duration_s * 1e3 > STEP_MS:
        RECORD["slow_steps"].append((t.started_wall, t.duration_s * 1e3))


def configure(node) -> None:
    """Set the node's public timing hooks (called once it is built, before it serves)."""
    node.worker.on_step = on_step
    node.on_request = on_request


def _stacks() -> dict[str, str]:
    """Every thread's stack, by thread name."""
    names = {t.ident: t.name for t in threading.enumerate()}
    return {names.get(ident, str(ident)): "".join(traceback.format_stack(f, limit=6))
            for ident, f in sys._current_frames().items()}


if __name__ == "__main__":
    watch_gc(RECORD["gc"])
    watch_pauses(RECORD["pauses"], _stacks)
    dump_every(OUT, RECORD, DUMP_PERIOD_S)
    wrenchcone_node.run(configure=configure)
