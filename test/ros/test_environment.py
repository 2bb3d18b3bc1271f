# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Without ``source install/setup.bash``: one line saying what to source, exit status 2
(wrenchcone_ros/ros/environment.py), for the client command and the node program. Before,
both died with two chained ImportError tracebacks."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

#: A shell that has not sourced the workspace: no PYTHONPATH, AMENT_PREFIX_PATH, ... (the
#: venv's own packages, rclpy's wheels among them, are still importable).
UNSOURCED = {k: os.environ[k] for k in ("PATH", "HOME") if k in os.environ}


@pytest.mark.parametrize("module,args", [
    ("wrenchcone_ros.ros.client", ["check", "na", "1", "0", "0"]),
    ("wrenchcone_ros.node", []),
])
def test_unsourced_programs_say_what_to_source_in_one_line(tmp_path, module, args):
    out = subprocess.run([sys.executable, "-m", module, *args], cwd=tmp_path,
                         env=UNSOURCED, capture_output=True, text=True, timeout=120,
                         check=False)
    lines = out.stderr.strip().splitlines()
    assert out.returncode == 2, out.stderr
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    assert "source install/setup.bash" in lines[0]


def test_a_library_caller_can_still_catch_it(tmp_path):
    code = ("try:\n    import wrenchcone_ros.ros.client\nexcept ImportError as exc:\n"
            "    print('caught:', exc)\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=UNSOURCED,
                         capture_output=True, text=True, timeout=120, check=False)
    assert out.returncode == 0 and out.stdout.startswith("caught: "), out.stderr
    assert "source install/setup.bash" in out.stdout


def test_the_sourced_environment_has_no_problem():
    from wrenchcone_ros.ros import environment

    assert environment.problem() is None
