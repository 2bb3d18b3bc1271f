# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The pawl of examples/pawl_seating.yaml on pins of unequal radii (and per-fixel friction),
and how a test reads what a harnessed node sees of it over DDS (test_node_fixels.py,
test/sim/test_sim_tray_fixels.py)."""

from __future__ import annotations

import time
from pathlib import Path

import yaml
from helpers.node_harness import DEADLINE_S, same_rows
from visualization_msgs.msg import MarkerArray

from wrenchcone_ros.core import wrench_cone
from wrenchcone_ros.node import CONE_QOS
from wrenchcone_ros.ros import conversions as conv
from wrenchcone_msgs.msg import Status

S = Status
#: The pawl of examples/pawl_seating.yaml seated on a 3 mm stop (pin 1) and two 4 mm
#: pins under its foot (pins 2 and 3): the foot's underside (y = 0 in the workpiece
#: frame) at y = 0.197 + 0.004, its right edge (x = 0.06) at 0.167 - 0.003.
SEATED_POSE = (0.104, 0.201, 0.0)
RADII = (0.003, 0.004, 0.004)
PAWL_SEATING = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"


def pawl_file(tmp_path, radii=RADII, frictions=(None, None, None), pose=SEATED_POSE,
              name="pawl.yaml"):
    """examples/pawl_seating.yaml with the given pin radii, friction and pose."""
    d = yaml.safe_load(open(PAWL_SEATING))
    d["workpiece"]["pose"] = list(pose)
    for f, r, mu in zip(d["fixels"], radii, frictions):
        f["radius"] = r
        if mu is not None:
            f["friction"] = mu
    path = tmp_path / name
    path.write_text(yaml.safe_dump(d))
    return path


def node_contacts(h, n):
    """Which fixels the node sees in contact, over DDS: a rolling letter at fixel i
    (separating elsewhere) is MODE_NOT_ALLOWED exactly when fixel i has a gap."""
    out = []
    for i in range(n):
        r = h.get_cone("s" * i + "n" + "s" * (n - i - 1))
        assert r.status in (S.OK, S.MODE_INFEASIBLE, S.MODE_NOT_ALLOWED), r.message
        out.append(r.status != S.MODE_NOT_ALLOWED)
    return out


def node_radii(h, version):
    """The pin radii the node draws in ~/markers (a cylinder of diameter 2 r per fixel)
    for an input snapshot at least ``version``."""
    col = h.subscribe(MarkerArray, "wrenchcone/markers", CONE_QOS)
    msg = col.wait_for(lambda m: len(m.markers) > 1 and any(
        k.ns == "fixels" for k in m.markers) and h.get_cone("").inputs_version >= version,
        "markers with the fixels")
    pins = sorted((k.id, k.scale.x / 2) for k in msg.markers if k.ns == "fixels")
    return [r for _, r in pins]


FRICTIONS = (0.2, 0.5, None)  # pin 3: none of its own, the node's friction (0.3)
SLIDING = ("rnn", "lnn", "nrn", "nnl", "rrs", "srr", "nnn")


def assert_cones_equal_core(h, truth, modes):
    """The node's cone of every mode equals the core's for ``truth`` (some feasible)."""
    feasible = 0
    for mode in modes:
        cone = wrench_cone(truth, mode)
        r = h.get_cone(mode)
        assert r.status == (S.OK if cone.feasible else S.MODE_INFEASIBLE), (mode, r.message)
        if cone.feasible:
            feasible += 1
            assert same_rows(conv.rows_from_flat(r.inequalities), cone.F), mode
            assert same_rows(conv.rows_from_flat(r.equalities), cone.equalities), mode
    assert feasible >= 2  # the comparison is not vacuous


def wait_for_fixels(h, stamp):
    """Wait until the node answers from the fixture stamped ``stamp`` (sec)."""
    deadline = time.monotonic() + DEADLINE_S
    while h.get_cone("").fixels_stamp.sec != stamp:
        assert time.monotonic() < deadline, f"the fixels stamped {stamp} s never used"
        time.sleep(0.01)


def rosout(h):
    """The node's /rosout lines, as they arrive (a list that grows)."""
    from rcl_interfaces.msg import Log
    from rclpy.qos import DurabilityPolicy, QoSProfile

    lines: list[str] = []
    me = h.node.get_logger().name
    h.tester.create_subscription(
        Log, "/rosout", lambda m: lines.append(m.msg) if m.name == me else None,
        QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL))
    return lines


def wait_for_line(lines, text):
    """The lines containing ``text``, once there is one (a guard against a hang only)."""
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline and not any(text in m for m in lines):
        time.sleep(0.02)
    found = [m for m in lines if text in m]
    assert found, (text, lines)
    return found
