# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The publishing worker (node/worker.py) and the services' timing hooks, over DDS: each
worker step reported to ``node.worker.on_step``, each reply computed in Python to
``node.on_request``, with times that bracket the real events; a hook that raises costs
no reply."""

from __future__ import annotations

import threading
import time

from helpers.node_harness import DEADLINE_S

from wrenchcone_ros.node.services import RequestTiming
from wrenchcone_ros.node.worker import StepTiming


def _wait(predicate, what: str) -> None:
    deadline = time.monotonic() + DEADLINE_S
    while not predicate():
        assert time.monotonic() < deadline, what
        threading.Event().wait(0.01)


def test_on_step_reports_each_step_of_a_new_snapshot(harness):
    h = harness
    steps: list[StepTiming] = []
    h.node.worker.on_step = steps.append
    v0 = h.get_cone("na").inputs_version
    t0, wall0 = time.perf_counter(), time.time()
    h.publish_pose(0.0, 0.0, 0.02)
    v1 = h.wait_version_above(v0)
    _wait(lambda: any(s.version >= v1 and s.published for s in steps), "a published step")
    step = next(s for s in steps if s.version >= v1 and s.published)
    assert t0 <= step.started <= time.perf_counter() and step.duration_s >= 0.0
    assert wall0 - 1.0 <= step.started_wall <= time.time()
    assert step.modes == 1 and not step.stale
    h.node.worker.on_step = None


def test_on_request_reports_each_python_reply_and_a_failing_hook_costs_nothing(harness):
    h = harness
    seen: list[RequestTiming] = []
    h.node.on_request = seen.append
    t0 = time.perf_counter()
    assert h.get_cone("na").status == 0
    assert h.classify((0.1, -1.0, 0.0)).status == 0
    assert h.get_cone("xx").status != 0
    by = [(r.service, r.status) for r in seen]
    assert ("get_cone", 0) in by and ("classify_wrench", 0) in by
    assert any(s == "get_cone" and st != 0 for s, st in by)
    assert all(t0 <= r.started and r.duration_s >= 0.0 for r in seen)

    def broken(_timing: RequestTiming) -> None:
        raise RuntimeError("a broken hook")

    h.node.on_request = broken
    assert h.get_cone("na").status == 0  # answered as before
    h.node.on_request = None
