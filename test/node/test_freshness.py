# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Freshness (node/freshness.py), without a ROS graph: the age of a snapshot's received
inputs against input_timeout (the pose) and fixels_timeout (the fixels)."""

from __future__ import annotations

import pytest

from wrenchcone_ros.node.freshness import freshness
from wrenchcone_ros.node.status import OK
from wrenchcone_ros.node.store import Snapshot

S = 1_000_000_000  # ns per s


def _snap(pose_ns: int | None, fixels_ns: int | None) -> Snapshot:
    return Snapshot(1, None, OK, "", "world", None, None, pose_ns, fixels_ns)


def test_inputs_never_received_are_never_stale():
    f = freshness(_snap(None, None), 100 * S, 1.0, 1.0)
    assert f.age_s == 0.0 and f.stale == ""


@pytest.mark.parametrize("age_s,timeout,stale", [
    (0.5, 1.0, False), (1.0, 1.0, False), (1.5, 1.0, True), (1e6, 0.0, False)])
def test_the_pose_is_stale_only_past_its_timeout(age_s, timeout, stale):
    now = 10**6 * S
    f = freshness(_snap(now - round(age_s * S), None), now, timeout, 0.0)
    assert f.age_s == pytest.approx(age_s)
    assert bool(f.stale) is stale
    if stale:
        assert "workpiece_pose" in f.stale and f"input_timeout {timeout:g} s" in f.stale


def test_the_oldest_input_gives_the_age_and_each_stale_one_is_named():
    now = 100 * S
    f = freshness(_snap(now - 2 * S, now - 5 * S), now, 1.0, 3.0)
    assert f.age_s == pytest.approx(5.0)
    assert "workpiece_pose" in f.stale and "fixels" in f.stale and "fixels_timeout" in f.stale
    assert not freshness(_snap(now - 2 * S, now - 5 * S), now, 0.0, 0.0).stale


def test_a_clock_behind_the_receive_time_gives_age_zero():
    f = freshness(_snap(10 * S, None), 9 * S, 1.0, 0.0)  # e.g. sim time jumped back
    assert f.age_s == 0.0 and not f.stale
