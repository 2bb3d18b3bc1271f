# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The closed loop's tests run the tray, the node and the controller over DDS: on a ROS
domain of their own (leased for the run) and localhost-only discovery, set before rclpy
is imported (helpers.ros_session)."""

import pytest
from helpers import ros_session


# its own fixtures around the helper's bodies, not the helper's (test/ros/conftest.py
# imports those): helpers.ros_session says why
@pytest.fixture(scope="session")
def ros_context():
    yield from ros_session.session_context()


@pytest.fixture
def harness_factory(ros_context):
    yield from ros_session.harness_maker(ros_context)
