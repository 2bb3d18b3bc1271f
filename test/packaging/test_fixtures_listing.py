# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``pytest --fixtures`` in the repository's root lists the fixtures. Before, it ended in
an INTERNALERROR: test/ros and test/sim (paths of one length) registered the same fixture
functions of helpers.ros_session, and pytest's sort of the fixtures compared two equal
keys' FixtureDef objects."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_pytest_fixtures_in_the_root_lists_them():
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    out = subprocess.run([sys.executable, "-m", "pytest", "--fixtures", "-q",
                          "-p", "no:cacheprovider", "-p", "no:xdist"], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=600, check=False)
    assert "INTERNALERROR" not in out.stdout + out.stderr, out.stdout[-3000:] + out.stderr
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr
    assert "ros_context [session scope]" in out.stdout and "wrenchcone_client" in out.stdout
