# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The fixture the user has, over real DDS: pins of unequal radii (and per-fixel friction)
published on the fixture topic reach the node as they are; the node's contacts, radii and
cones equal the core's for the same scene, computed independently from the scene file."""

from __future__ import annotations

import pytest
import yaml
from helpers.node_harness import same_rows
from visualization_msgs.msg import MarkerArray

from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_ros.node import CONE_QOS
from wrenchcone_ros.ros import conversions as conv
from wrenchcone_msgs.msg import Fixels, Status

S = Status
#: The pawl of examples/pawl_seating.yaml seated on a 3 mm stop (pin 1) and two 4 mm
#: pins under its foot (pins 2 and 3): the foot's underside (y = 0 in the workpiece
#: frame) at y = 0.197 + 0.004, its right edge (x = 0.06) at 0.167 - 0.003.
SEATED_POSE = (0.104, 0.201, 0.0)
RADII = (0.003, 0.004, 0.004)


def pawl_file(tmp_path, radii=RADII, frictions=(None, None, None), pose=SEATED_POSE):
    """examples/pawl_seating.yaml with the given pin radii, friction and pose."""
    d = yaml.safe_load(open("examples/pawl_seating.yaml"))
    d["workpiece"]["pose"] = list(pose)
    for f, r, mu in zip(d["fixels"], radii, frictions):
        f["radius"] = r
        if mu is not None:
            f["friction"] = mu
    path = tmp_path / "pawl.yaml"
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


def test_unequal_pins_published_reach_the_node_as_they_are(harness_factory, tmp_path):
    """The pawl on a 3 mm and two 4 mm pins: a node that gave every pin one radius saw the
    part 1 mm above pins 2 and 3 (no contact there, every cone for another fixture)."""
    path = pawl_file(tmp_path)
    truth = load_scene(str(path))
    assert truth.in_contact == (True, True, True)  # the scene the test is about
    # the node starts from the scene file's workpiece and waits for the user's fixture
    h = harness_factory(scene_file=str(path), wait_for_inputs=True)
    v = h.get_cone("").inputs_version
    h.publish_pose(*SEATED_POSE, stamp=(1, 0))
    h.publish_fixels([f.position for f in truth.fixels], radii=[f.radius for f in truth.fixels],
                     stamp=(2, 0))
    v = h.wait_version_above(v)
    while h.get_cone("").fixels_stamp.sec != 2:
        v = h.wait_version_above(v)
    assert node_contacts(h, 3) == list(truth.in_contact)
    assert node_radii(h, v) == pytest.approx(RADII, abs=1e-12)
    assert_cones_equal_core(h, truth, ("nnn", "rnn", "snn", "nss", "lnn", "srr"))


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
    v = h.get_cone("").inputs_version
    while h.get_cone("").fixels_stamp.sec != stamp:
        v = h.wait_version_above(v)


def test_a_volatile_publisher_is_heard_as_well_as_a_latched_one(harness_factory, tmp_path):
    """The common default publisher (reliable, volatile: `ros2 topic pub`, most code)
    matches the node's second subscription of the topic; the latched one (the harness's,
    a fixture description) its first. The same latched message heard by both is one
    fixture: no change is counted."""
    from rclpy.qos import QoSProfile

    path = pawl_file(tmp_path)
    truth = load_scene(str(path))
    h = harness_factory(scene_file=str(path))
    volatile = h.tester.create_publisher(Fixels, "fixels", QoSProfile(depth=10))
    positions = [f.position for f in truth.fixels]
    # volatile: a message published before the match is lost, so publish until heard
    for k in range(1, 400):
        h.publish_fixels(positions, radii=[0.003, 0.004, 0.003], stamp=(k, 0),
                         publisher=volatile)
        if h.get_cone("").fixels_stamp.sec == k:
            break
    assert h.get_cone("").fixels_stamp.sec == k and k < 399
    assert node_contacts(h, 3) == [True, True, False]  # pin 3 now 3 mm: 1 mm below the foot
    h.publish_fixels(positions, radii=list(RADII), stamp=(1000, 0))  # latched
    wait_for_fixels(h, 1000)
    assert node_contacts(h, 3) == list(truth.in_contact)
    snap = h.node.snapshot
    # scene file (3, 4, 4 mm) -> 3, 4, 3 mm -> 3, 4, 4 mm: two new fixtures, not three
    assert snap.fixture_changes == 2, snap.fixture
    assert "radii [0.003, 0.004, 0.004] m" in snap.fixture and "from fixels" in snap.fixture
