# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Seeded fuzz of the live node: a few thousand mixed inputs (parameters,
poses, fixels, requests with wildcards; NaN, inf, 1e200, huge arrays, long strings).
The node never dies, every request gets a reply, every reply has a documented status
and none is INTERNAL_ERROR, and nothing logs a traceback. The longer run (>= 10,000
inputs) is benchmarks/node_fuzz.py."""

from __future__ import annotations

from helpers.node_fuzz import run_fuzz

from wrenchcone_ros.node import INTERNAL_ERROR, STATUS_NAMES
from wrenchcone_msgs.msg import Status

S = Status
STEPS = 2500
SEED = 11


def test_fuzzed_inputs_never_kill_the_node(harness, capfd):
    h = harness
    res = run_fuzz(h, STEPS, SEED)
    assert res.unanswered == 0
    assert res.internal_errors == []
    statuses = {s for (_svc, s) in res.statuses}
    assert statuses <= set(STATUS_NAMES) - {INTERNAL_ERROR}, statuses
    # the run was not vacuous: answers, refusals and accepted parameter sets all happened
    assert sum(res.statuses.values()) > STEPS // 3
    assert {S.OK, S.INVALID_MODE, S.LIMIT_EXCEEDED} <= statuses
    assert res.parameter_sets["accepted"] > 10 and res.parameter_sets["refused"] > 10
    # still alive and serving after all that
    assert h.check("na").status in STATUS_NAMES
    assert h.node.store.current() is not None and h.node.worker.thread.is_alive()
    err = capfd.readouterr().err
    with capfd.disabled():  # the run's summary, shown with pytest -s
        print(f"\nfuzz: {res.steps} steps, statuses {dict(res.statuses)}, parameter sets "
              f"{dict(res.parameter_sets)}, {err.count('refused')} refusal log lines")
    assert "Traceback" not in err
