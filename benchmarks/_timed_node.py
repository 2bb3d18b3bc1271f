"""The wrenchcone node as ``python -m wrenchcone_ros.node`` runs it, plus the start and end
times (``time.perf_counter``, CLOCK_MONOTONIC: comparable across processes) of every
check_wrench callback, written to $WRENCHCONE_TIMING_FILE (JSON, rewritten every 0.2 s).

Used by ``benchmarks/node_stream.py --decompose`` to split a check_wrench round trip
into its parts. Benchmark tooling only: it wraps the services' registration before the
node starts and changes nothing else. Only requests that reach the Python handler are
timed: with the compiled lane on (parameter fast_check), the monitored modes' requests
never do, so decompose with ``--node-args '-p fast_check:=false'``.
"""

from __future__ import annotations

import os
import time

from _watch import dump_every

from wrenchcone_ros.node import services

OUT = os.environ["WRENCHCONE_TIMING_FILE"]
RECORDS: list[tuple[float, float]] = []
_serve = services._serve


def _timed_serve(node, spec):
    callback = _serve(node, spec)
    if spec.name != "check_wrench":
        return callback

    def timed(req, resp):
        t0 = time.perf_counter()
        try:
            return callback(req, resp)
        finally:
            RECORDS.append((t0, time.perf_counter()))

    return timed


services._serve = _timed_serve
dump_every(OUT, RECORDS, 0.2)

from wrenchcone_ros.node.wrenchcone_node import run  # noqa: E402

run()
