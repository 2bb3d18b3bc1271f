# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Tests that talk to a node over DDS: the node's modules. Their isolation (a leased ROS domain,
localhost-only discovery, set before rclpy is imported) and the node harness's fixtures
are helpers.ros_session's."""

from helpers.ros_session import harness, harness_factory, ros_context  # noqa: F401
