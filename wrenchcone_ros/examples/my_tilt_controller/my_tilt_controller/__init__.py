# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A minimal controller that checks its wrench with the wrenchcone node."""
