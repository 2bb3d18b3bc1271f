# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Freshness: how old a snapshot's received inputs are, against their timeouts.

Parameters ``input_timeout`` (the pose) and ``fixels_timeout`` (the fixels); an input
never received (the scene's own) is never stale. Plain data, no ROS.
"""

from __future__ import annotations

from dataclasses import dataclass

from wrenchcone_ros.node.store import Snapshot


@dataclass(frozen=True)
class Freshness:
    """How old a snapshot's received inputs are, at one instant of the node clock."""

    age_s: float  # of the oldest received input used (0 when none was received)
    stale: str = ""  # empty when fresh; else says which input is how old


def freshness(snap: Snapshot, now_ns: int, input_timeout: float,
              fixels_timeout: float) -> Freshness:
    """Compare the ages of the snapshot's pose and fixels with their timeouts (s; 0 =
    never stale). An input never received (the scene's own) is never stale."""
    ages, stale = [], []
    for what, received, timeout, param in (
            ("workpiece_pose", snap.pose_received_ns, input_timeout, "input_timeout"),
            ("fixels", snap.fixels_received_ns, fixels_timeout, "fixels_timeout")):
        if received is None:
            continue
        age = max(0.0, (now_ns - received) * 1e-9)
        ages.append(age)
        if timeout > 0 and age > timeout:
            stale.append(f"{what} last received {age:.3f} s ago ({param} {timeout:g} s)")
    return Freshness(max(ages, default=0.0),
                     "inputs are stale: " + "; ".join(stale) if stale else "")
