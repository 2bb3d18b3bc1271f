# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The fixture the user has, over real DDS: pins of unequal radii (and per-fixel friction)
published on the fixture topic reach the node as they are; the node's contacts, radii and
cones equal the core's for the same scene, computed independently from the scene file."""

from __future__ import annotations

import pytest
import yaml
from helpers.fixture_scenes import (
    FRICTIONS,
    RADII,
    SEATED_POSE,
    SLIDING,
    S,
    assert_cones_equal_core,
    node_contacts,
    node_radii,
    pawl_file,
    rosout,
    wait_for_fixels,
    wait_for_line,
)
from helpers.node_harness import same_rows

from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_msgs.msg import Fixels


def test_unequal_pins_published_reach_the_node_as_they_are(harness_factory, tmp_path):
    """The pawl on a 3 mm and two 4 mm pins: a node that gave every pin one radius saw the
    part 1 mm above pins 2 and 3 (no contact there, every cone for another fixture)."""
    path = pawl_file(tmp_path)
    truth = load_scene(str(path))
    assert truth.in_contact == (True, True, True)  # the scene the test is about
    # the node starts from the scene file's workpiece and waits for the user's fixture
    h = harness_factory(scene_file=str(path), wait_for_inputs=True)
    h.publish_pose(*SEATED_POSE, stamp=(1, 0))
    h.publish_fixels([f.position for f in truth.fixels], radii=[f.radius for f in truth.fixels],
                     stamp=(2, 0))
    wait_for_fixels(h, 2)
    v = h.get_cone("").inputs_version
    assert node_contacts(h, 3) == list(truth.in_contact)
    assert node_radii(h, v) == pytest.approx(RADII, abs=1e-12)
    assert_cones_equal_core(h, truth, ("nnn", "rnn", "snn", "nss", "lnn", "srr"))


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


def test_a_pose_array_needs_fixel_radius_and_is_never_given_the_files_radii(
        harness_factory, tmp_path):
    """On fixel_poses, positions only: without fixel_radius the message is refused (the
    node keeps waiting for a fixture, NO_INPUTS; one log line says what to do); with one
    radius per fixel, or one for all, it is the fixture; a count that does not fit is a
    SCENE_ERROR naming fixel_radius, and a PoseArray that does not fit it is refused."""
    path = pawl_file(tmp_path)
    truth = load_scene(str(path))
    positions = [f.position for f in truth.fixels]
    h = harness_factory(scene_file=str(path), wait_for_inputs=True)
    logs = rosout(h)
    h.publish_pose(*SEATED_POSE, stamp=(1, 0))
    h.publish_fixel_poses(positions, stamp=(2, 0))
    refusal = "PoseArray carries fixel positions only and parameter fixel_radius is not set"
    assert len(wait_for_line(logs, refusal)) == 1
    r = h.get_cone("nnn")
    assert r.status == S.NO_INPUTS and "no input yet on fixels" in r.message, r.message
    assert "refused: fixel_poses: a PoseArray carries fixel positions only" in r.message
    [res] = h.set_parameters(fixel_radius=list(RADII))
    assert res.successful, res.reason
    h.publish_fixel_poses(positions, stamp=(3, 0))
    wait_for_fixels(h, 3)
    assert node_contacts(h, 3) == list(truth.in_contact)
    assert_cones_equal_core(h, truth, ("nnn", "rnn", "snn", "nss", "lnn", "srr"))
    # one radius for all (3 mm): pins 2 and 3 are 1 mm below the foot, as the core says
    # of the same scene with 3 mm pins
    [res] = h.set_parameters(fixel_radius=[0.003])
    assert res.successful, res.reason
    small = load_scene(str(pawl_file(tmp_path, radii=(0.003,) * 3, name="small.yaml")))
    assert small.in_contact == (True, False, False)
    assert node_contacts(h, 3) == list(small.in_contact)
    # two radii for three positions: no scene, the reason named; a new PoseArray refused
    [res] = h.set_parameters(fixel_radius=[0.003, 0.004])
    assert res.successful, res.reason
    r = h.get_cone("nnn")
    assert r.status == S.SCENE_ERROR and "fixel_radius gives 2 radii" in r.message, r.message
    h.publish_fixel_poses(positions, stamp=(5, 0))
    wait_for_line(logs, "fixel_radius gives 2 radii for a PoseArray of 3 fixel(s)")
    assert h.get_cone("").fixels_stamp.sec == 3


def test_per_fixel_friction_of_the_message_is_the_scene_files(harness_factory, tmp_path):
    """A Fixels message with per-fixel friction makes the scene the file with the same
    values makes: every cone equals the core's of that file (and differs from the cones
    with one friction for all, so the comparison says something)."""
    path = pawl_file(tmp_path)
    truth = load_scene(str(pawl_file(tmp_path, frictions=FRICTIONS, name="truth.yaml")))
    assert [truth.mu(i) for i in range(3)] == [0.2, 0.5, 0.3]
    plain = load_scene(str(path))
    assert any(not same_rows(wrench_cone(truth, m).F, wrench_cone(plain, m).F)
               for m in SLIDING if wrench_cone(plain, m).feasible)
    h = harness_factory(scene_file=str(path))
    h.publish_fixels([f.position for f in truth.fixels], radii=list(RADII),
                     frictions=list(FRICTIONS), stamp=(7, 0))
    wait_for_fixels(h, 7)
    assert_cones_equal_core(h, truth, SLIDING)
    assert "friction [0.2, 0.5, 0.3]" in h.node.snapshot.fixture


def test_per_fixel_friction_intervals_must_name_the_fixtures_fixels(harness_factory,
                                                                    tmp_path):
    """uncertainty.friction, one [lo, hi] per fixel: zero-width intervals are those mu,
    so the robust cones equal the core's nominal cones of the file with those values. A
    fixture of another count is not answered for: SCENE_ERROR naming the parameter, one
    log line; the right count again answers again."""
    path = pawl_file(tmp_path)
    truth = load_scene(str(pawl_file(tmp_path, frictions=(0.2, 0.5, 0.3), name="truth.yaml")))
    h = harness_factory(scene_file=str(path),
                        **{"uncertainty.friction": [0.2, 0.2, 0.5, 0.5, 0.3, 0.3]})
    logs = rosout(h)
    positions = [f.position for f in truth.fixels]
    h.publish_fixels(positions, radii=list(RADII), stamp=(7, 0))
    wait_for_fixels(h, 7)
    assert_cones_equal_core(h, truth, SLIDING)
    h.publish_fixels(positions[1:], radii=list(RADII[1:]), stamp=(8, 0))
    wait_for_fixels(h, 8)
    r = h.get_cone("nn")
    assert r.status == S.SCENE_ERROR, r.message
    assert "uncertainty.friction gives 3 per-fixel interval(s)" in r.message
    assert "fixture has 2 fixel(s)" in r.message
    assert len(wait_for_line(logs, "uncertainty.friction gives 3 per-fixel")) == 1
    h.publish_fixels(positions, radii=list(RADII), stamp=(9, 0))
    wait_for_fixels(h, 9)
    assert_cones_equal_core(h, truth, SLIDING)
    # an odd count is refused when set, saying what is allowed
    [res] = h.set_parameters(**{"uncertainty__friction": [0.2, 0.3, 0.4]})
    assert not res.successful and "an even count" in res.reason, res.reason


def test_a_scene_files_per_fixel_intervals_are_the_nodes(harness_factory, tmp_path):
    d = yaml.safe_load(pawl_file(tmp_path).read_text())
    d["uncertainty"] = {"friction": [[0.2, 0.25], None, [0.4, 0.5]]}
    path = tmp_path / "pawl_u.yaml"
    path.write_text(yaml.safe_dump(d))
    h = harness_factory(scene_file=str(path))
    got = list(h.node.get_parameter("uncertainty.friction").value)
    assert got == [0.2, 0.25, 0.3, 0.3, 0.4, 0.5]  # null: the file's friction, 0.3


def test_a_fixture_whose_count_or_radii_change_is_a_new_fixture(harness_factory, tmp_path):
    """Count or radius changed: /diagnostics says so (message and values) and the log
    once; a fixture moved without such a change (pins re-measured) is not counted."""
    from diagnostic_msgs.msg import DiagnosticArray
    from rclpy.qos import QoSProfile

    path = pawl_file(tmp_path)
    truth = load_scene(str(path))
    h = harness_factory(scene_file=str(path), diagnostics_rate=20.0)
    logs = rosout(h)
    diagnostics = h.subscribe(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))
    name = h.node.get_fully_qualified_name()

    def inputs(msg):
        return next((s for s in msg.status if s.name == f"{name}: inputs"), None)

    positions = [f.position for f in truth.fixels]
    h.publish_fixels([(x, y - 1e-4) for x, y in positions], radii=list(RADII),
                     stamp=(5, 0))  # moved, same count and radii; the part now free
    wait_for_fixels(h, 5)
    h.publish_fixels(positions[:2], radii=[0.003, 0.0035], stamp=(6, 0))
    wait_for_fixels(h, 6)
    msg = diagnostics.wait_for(lambda m: inputs(m) is not None and "new fixture"
                               in inputs(m).message, "a new fixture in /diagnostics")
    values = {kv.key: kv.value for kv in inputs(msg).values}
    assert values["fixture changes"] == "1"
    assert values["fixture"] == ("2 fixel(s), radii [0.003, 0.0035] m, friction [0.3, 0.3] "
                                 "(from fixels)")
    lines = wait_for_line(logs, "new fixture")
    assert lines == ["new fixture (3 -> 2 fixel(s), radii changed): 2 fixel(s), radii "
                     "[0.003, 0.0035] m, friction [0.3, 0.3] (from fixels)"]
