# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``wrenchcone`` command as a user runs it: a real subprocess of this interpreter."""

import subprocess
import sys


def run(*args):
    return subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", *args],
                          capture_output=True, text=True)
