# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""tools/fix_wheel_cmake.py: the wheels' exported CMake files get this interpreter's
include directories, without touching a file the venv shares with an installer's cache
(uv hardlinks the files it installs), and a venv installed from a cache that an older
version of the tool had rewritten is put right too."""

from __future__ import annotations

import importlib.util
import os
import sysconfig
from pathlib import Path

import numpy
import pytest

TOOL = Path(__file__).resolve().parents[2] / "tools" / "fix_wheel_cmake.py"
spec = importlib.util.spec_from_file_location("fix_wheel_cmake", TOOL)
fix_wheel_cmake = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fix_wheel_cmake)

WHEEL_LINE = (
    '  INTERFACE_INCLUDE_DIRECTORIES "/opt/python/cp311-cp311/include/python3.11;'
    '/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include"\n')
# what the tool's first version left in uv's cache: another venv's numpy, since deleted
STALE_LINE = (
    '  INTERFACE_INCLUDE_DIRECTORIES "/root/.pyenv/versions/3.11.7/include/python3.11;'
    '/tmp/gone/.venv/lib/python3.11/site-packages/numpy/_core/include"\n')
WANT = (f'  INTERFACE_INCLUDE_DIRECTORIES "{sysconfig.get_paths()["include"]};'
        f'{numpy.get_include()}"\n')


def _venv_with(tmp_path: Path, line: str) -> tuple[Path, Path]:
    """A venv's exported CMake file hardlinked to a cache's copy, as uv installs it."""
    cache = tmp_path / "cache" / "export_x__rosidl_generator_pyExport.cmake"
    cache.parent.mkdir()
    cache.write_text("set_target_properties(x PROPERTIES\n" + line + ")\n")
    venv_file = tmp_path / "venv" / "share" / "x" / "cmake" / cache.name
    venv_file.parent.mkdir(parents=True)
    os.link(cache, venv_file)
    return cache, venv_file


@pytest.mark.parametrize("line", [WHEEL_LINE, STALE_LINE], ids=["wheel", "stale-cache"])
def test_rewrites_the_venv_and_leaves_the_cache_alone(tmp_path, line):
    cache, venv_file = _venv_with(tmp_path, line)
    assert fix_wheel_cmake.main(str(tmp_path / "venv")) == 0
    assert WANT in venv_file.read_text()
    assert line in cache.read_text(), "the installer's cache was rewritten through a hardlink"
    assert not os.path.samefile(cache, venv_file)
    # idempotent: a second run changes nothing
    before = venv_file.stat().st_ino
    assert fix_wheel_cmake.main(str(tmp_path / "venv")) == 0
    assert venv_file.stat().st_ino == before and WANT in venv_file.read_text()


def test_a_missing_include_directory_is_an_error_that_names_it(tmp_path, capsys):
    _, venv_file = _venv_with(tmp_path, '  INTERFACE_INCLUDE_DIRECTORIES "/nowhere/include"\n')
    assert fix_wheel_cmake.main(str(tmp_path / "venv")) == 1
    err = capsys.readouterr().err
    assert "/nowhere/include" in err and str(venv_file) in err
