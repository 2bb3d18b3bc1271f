# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``python -m wrenchcone_ros.node``: run the node (same as ``wrenchcone_node``)."""

from wrenchcone_ros.node.wrenchcone_node import run

run()
