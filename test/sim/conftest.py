# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The closed loop's tests run the tray, the node and the controller over DDS: on a ROS
domain of their own (leased for the run) and localhost-only discovery, set before rclpy
is imported (helpers.ros_session)."""

from helpers.ros_session import harness_factory, ros_context  # noqa: F401
