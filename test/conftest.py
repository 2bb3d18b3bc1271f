# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Shared test set-up: make ``test/`` importable, so that the helper package
``helpers`` (test/helpers/) is (``from helpers.strategies import random_scene``).

Test modules are imported with pytest's ``importlib`` mode (pyproject.toml): they are
not on ``sys.path``, so no test module can import another, and two test modules may
share a name in different directories (test/core/test_plot.py, test/cli/test_plot.py).
"""

from __future__ import annotations

import os
import sys

import pytest

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)

#: Fixtures that start rclpy contexts and nodes over DDS (test/helpers/ros_session.py and
#: the test kit's): a test that uses one (directly or through another fixture) is slow.
DDS_FIXTURES = {"ros_context", "wrenchcone_context", "wrenchcone_node_factory"}


def pytest_collection_modifyitems(config, items):
    """Mark every DDS test and every heavy one slow (the ``slow`` marker of pyproject.toml): ``make test-fast``
    (``-m "not slow"``) leaves them out, ``make test`` runs them. The tests marked
    ``heavy`` (a minute or more of CPU) run first, so that pytest-xdist's workers share
    them and end together instead of one worker finishing a long test alone."""
    for item in items:
        if (DDS_FIXTURES & set(getattr(item, "fixturenames", ()))
                or item.get_closest_marker("heavy") is not None):
            item.add_marker(pytest.mark.slow)
    items.sort(key=lambda item: item.get_closest_marker("heavy") is None)  # stable
