"""The wrenchcone node as ``python -m wrenchcone_ros.node`` runs it, watched from inside:
what in the node could hold up its replies or its published F. Written to
$WRENCHCONE_WATCH_FILE (JSON, rewritten every 0.5 s), each entry stamped with the wall
clock (time.time(), s) so that it can be matched with other processes' records:

* ``pauses``: a Python thread that sleeps 5 ms at a time woke more than 50 ms late
  (``_watch.watch_pauses``) (the GIL held that long, or the process not scheduled), with the
  stacks of every thread just after;
* ``slow_steps``: publishing-worker steps (``WrenchConeNode._publish_step``: a
  snapshot's cones, the lane's offer, every topic's message) longer than ``STEP_MS``;
* ``gc``: garbage collections longer than 5 ms (``_watch.watch_gc``: generation, ms);
* ``idle``: intervals longer than ``IDLE_MS`` between the end of one worker step and
  the start of the next (stamped at their start): the worker waiting, e.g. for a pose,
  or not woken when one came.

Used by ``benchmarks/node_stream.py --watch``. Benchmark tooling only: it wraps one
method and adds two daemon threads (the watchdog costs about 1 % of a core).
"""

from __future__ import annotations

import os
import sys
import threading
import time
import traceback

from _watch import dump_every, watch_gc, watch_pauses

from wrenchcone_ros.node import wrenchcone_node

OUT = os.environ["WRENCHCONE_WATCH_FILE"]
STEP_MS = 15.0  # ms: a worker step this long is recorded
IDLE_MS = 50.0  # ms: the worker idle this long between two steps is recorded
RECORD: dict[str, list] = {"pauses": [], "slow_steps": [], "gc": [], "idle": []}
_step = wrenchcone_node.WrenchConeNode._publish_step
_last_end = [0.0, 0.0]  # perf_counter and wall clock at the end of the last step


def _timed_step(self, last):
    t0, wall = time.perf_counter(), time.time()
    if _last_end[0] and (t0 - _last_end[0]) * 1e3 > IDLE_MS:
        RECORD["idle"].append((_last_end[1], (t0 - _last_end[0]) * 1e3))
    try:
        return _step(self, last)
    finally:
        end = time.perf_counter()
        _last_end[:] = [end, time.time()]
        ms = (end - t0) * 1e3
        if ms > STEP_MS:
            RECORD["slow_steps"].append((wall, ms))


def _stacks() -> dict[str, str]:
    """Every thread's stack, by thread name."""
    names = {t.ident: t.name for t in threading.enumerate()}
    return {names.get(ident, str(ident)): "".join(traceback.format_stack(f, limit=6))
            for ident, f in sys._current_frames().items()}


wrenchcone_node.WrenchConeNode._publish_step = _timed_step
watch_gc(RECORD["gc"])
watch_pauses(RECORD["pauses"], _stacks)
dump_every(OUT, RECORD, 0.5)
wrenchcone_node.run()
