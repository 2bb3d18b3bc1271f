# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Closed loop over ROS 2: a simulated tilting tray and a reference tilt controller.

* :mod:`.tray`: the simulated tray without ROS (a scene's workpiece in pymunk, through
  :mod:`wrenchcone_ros.core.simulate`), its commands and their validation;
* :mod:`.tray_sim`: the ``tray_sim`` node (poses, fixels, ``/clock``, contact letters;
  the tilt command; reset and sample services);
* :mod:`.tilt_controller`: the ``tilt_controller`` node, which executes the wrenchcone
  node's plans with feedback;
* :mod:`.controller_states`: the controller's states without ROS (the open-loop rule,
  the diagnostic levels);
* :mod:`.recorder`: runs written as rosbag2 MCAP files.

docs/closed_loop.md is the tutorial. Nothing is imported here: the ROS modules need the
colcon install tree sourced.
"""
