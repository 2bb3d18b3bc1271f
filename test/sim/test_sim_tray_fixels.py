# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""tray_sim publishes the fixture it simulates as it is built: each pin's radius and, where
the scene file gives one, its friction (wrenchcone_msgs/Fixels); the wrenchcone node that
hears it sees the contacts and cones the core computes from the scene file."""

import time

import pytest

pytest.importorskip("pymunk")

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.sim.tray import TrayPhysics  # noqa: E402
from wrenchcone_ros.sim.tray_sim import TraySimNode  # noqa: E402

from helpers.fixture_scenes import (  # noqa: E402
    RADII,
    SEATED_POSE,
    SLIDING,
    assert_cones_equal_core,
    node_contacts,
    pawl_file,
)
from helpers.node_harness import DEADLINE_S  # noqa: E402


def test_the_tray_publishes_the_true_radii_and_friction(ros_context, harness_factory,
                                                         tmp_path):
    path = pawl_file(tmp_path, frictions=(None, 0.5, None))
    truth = load_scene(str(path))
    assert truth.in_contact == (True, True, True)
    h = harness_factory(scene_file=str(path), wait_for_inputs=True)
    tray = TraySimNode(physics=TrayPhysics(truth), context=ros_context, start=False,
                       namespace=h.ns)
    try:
        h.publish_pose(*SEATED_POSE, stamp=(1, 0))
        deadline = time.monotonic() + DEADLINE_S
        while h.node.snapshot.fixels_stamp is None:  # the tray's (latched) fixture
            assert time.monotonic() < deadline, "the tray's fixels never arrived"
            time.sleep(0.01)
        assert node_contacts(h, 3) == list(truth.in_contact)
        assert_cones_equal_core(h, truth, SLIDING)
        fixture = h.node.snapshot.fixture
        assert fixture == (f"3 fixel(s), radii [{', '.join(f'{r:g}' for r in RADII)}] m, "
                           "friction [0.3, 0.5, 0.3] (from fixels)")
    finally:
        tray.destroy_node()
