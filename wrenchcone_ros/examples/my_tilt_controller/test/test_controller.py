# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The controller against the real wrenchcone node, with the wrenchcone pytest kit.

One wrenchcone node for the module (``wrenchcone_node_module`` on the paper's disc, an
example scene installed with wrenchcone_ros); each test spins its own controller beside
it (``wrenchcone_spin``), in the module's context, and the controller is destroyed after
the test.
"""

from pathlib import Path

import pytest
from ament_index_python.packages import get_package_share_directory
from rclpy.parameter import Parameter

from my_tilt_controller.controller import TiltController

TIMEOUT_S = 60.0  # only a guard against a hang


@pytest.fixture(scope="module")
def wrenchcone_scene():
    # the unit disc on two fixels: rolling on fixel 1, approaching fixel 2 is mode 'na'
    return Path(get_package_share_directory("wrenchcone_ros")) / "examples" / "paper_disc.yaml"


@pytest.fixture
def controller(wrenchcone_node_module, wrenchcone_context_module, wrenchcone_spin):
    def start(mode, wrench):
        node = TiltController(context=wrenchcone_context_module, parameter_overrides=[
            Parameter("mode", value=mode), Parameter("wrench", value=list(wrench)),
            Parameter("server", value=wrenchcone_node_module.get_fully_qualified_name())])
        wrenchcone_spin(node)
        assert node.answered.wait(TIMEOUT_S), "the wrenchcone node never answered"
        return node
    return start


def test_approves_a_wrench_inside_the_cone(controller):
    assert controller("na", (0.1, -1.0, 0.0)).approved is True


def test_refuses_a_wrench_outside_the_cone(controller):
    assert controller("na", (0.5, -1.0, 0.0)).approved is False  # it would roll on 1 and slide


def test_refuses_a_mode_the_contacts_do_not_allow(controller):
    assert controller("nn", (0.1, -1.0, 0.0)).approved is False  # fixel 2 is not touching
