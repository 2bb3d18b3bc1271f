# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_ros/cmake/install_metadata.py, the build-time helper of CMakeLists.txt: the
dist-info it writes from setup.py, and the interpreter directory the environment hook
puts on PATH (none for the system's Python, as on a ROS installation from Debian
packages)."""

from __future__ import annotations

import configparser
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "wrenchcone_ros"
SCRIPT = PKG / "cmake" / "install_metadata.py"
SYSTEM_PYTHON = "/usr/bin/python3"


def helper(python: str, *args: str) -> str:
    out = subprocess.run([python, "-I", str(SCRIPT), *args], capture_output=True, text=True,
                         timeout=120, check=True)
    return out.stdout


def test_the_dist_info_has_setup_pys_entry_points(tmp_path):
    from wrenchcone_ros import __version__

    scripts = helper(sys.executable, "dist-info", str(PKG / "setup.py"), str(tmp_path))
    assert set(scripts.split(";")) == {
        "wrenchcone=wrenchcone_ros.cli:main", "wrenchcone_node=wrenchcone_ros.node:run",
        "tray_sim=wrenchcone_ros.sim.tray_sim:run",
        "tilt_controller=wrenchcone_ros.sim.tilt_controller:run"}
    (dist,) = tmp_path.iterdir()
    assert dist.name == f"wrenchcone_ros-{__version__}.dist-info"
    meta = dist.joinpath("METADATA").read_text().splitlines()
    assert "Name: wrenchcone_ros" in meta and f"Version: {__version__}" in meta
    entry_points = configparser.ConfigParser()
    entry_points.read(dist / "entry_points.txt")
    assert dict(entry_points["pytest11"]) == {"wrenchcone": "wrenchcone_ros.testing.plugin"}


@pytest.mark.skipif(sys.prefix == sys.base_prefix, reason="this run is not in a venv")
def test_a_venv_puts_its_bin_on_path():
    assert helper(sys.executable, "scripts-dir") == sysconfig.get_path("scripts")


@pytest.mark.skipif(not os.path.exists(SYSTEM_PYTHON), reason="no /usr/bin/python3 here")
def test_the_systems_python_adds_nothing():
    out = subprocess.run([SYSTEM_PYTHON, "-I", "-c", "import sys; print(sys.prefix)"],
                         capture_output=True, text=True, timeout=60, check=True)
    if out.stdout.strip() != "/usr":
        pytest.skip(f"{SYSTEM_PYTHON} is not a Debian system Python ({out.stdout.strip()})")
    assert helper(SYSTEM_PYTHON, "scripts-dir") == ""
