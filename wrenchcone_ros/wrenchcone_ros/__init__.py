# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_ros: wrench cones of planar augmented contact modes (core, CLI, ROS 2 node).

This file must not import ROS: ``wrenchcone_ros.core`` and the CLI work without it. The
colcon build installs it over the empty ``__init__.py`` that rosidl generates.
"""

from ._version import __version__

__all__ = ["__version__"]
