# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""`wrenchcone plot` and `wrenchcone --version` as a user runs them (real subprocesses),
and the README's picture: its documented command reproduces the committed file."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from wrenchcone_ros import __version__

ROOT = Path(__file__).resolve().parents[2]


def run(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", *args],
                          capture_output=True, text=True, cwd=cwd)


@pytest.mark.slow
def test_version():
    out = run("--version")
    assert out.returncode == 0
    assert out.stdout.strip() == f"wrenchcone {__version__}"


@pytest.mark.slow
@pytest.mark.parametrize("ext, magic", [("png", b"\x89PNG"), ("svg", b"<?xml")])
def test_plot_writes_the_file(tmp_path, ext, magic):
    path = tmp_path / f"disc.{ext}"
    out = run("plot", "default", "--mode", "na", "--wrench", "1", "-1", "-1",
              "--point", "0", "0.3", "-o", str(path))
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == f"wrote {path}"
    assert path.read_bytes().startswith(magic)


@pytest.mark.parametrize("args, needle", [
    (["--mode", "nnn"], "fixel 1 is not in contact"),
    (["--mode", "a*r"], "wildcards"),
    (["--mode", "arr", "--point", "nan", "0"], "--point must be two finite numbers"),
    (["--mode", "arr", "--wrench", "1", "inf", "0"], "--wrench must be three finite"),
    (["--mode", "arr", "-o", "x.jpg"], "unknown format 'jpg'"),
    (["--mode", "arr", "-o", "/nonexistent-dir/x.png"], "cannot write"),
    (["--mode", "arr", "--wrench", "1"], "expected 3 arguments"),
])
@pytest.mark.slow
def test_bad_input_exit_2_one_line(tmp_path, args, needle):
    if "-o" not in args:
        args = [*args, "-o", str(tmp_path / "x.png")]
    out = run("plot", "examples/pawl_polygon.yaml", *args)
    assert out.returncode == 2
    assert out.stdout == ""
    assert len(out.stderr.strip().splitlines()) == 1 and needle in out.stderr, out.stderr


@pytest.mark.slow
def test_readme_picture_is_made_by_the_documented_command(tmp_path):
    import matplotlib.image

    readme = (ROOT / "README.md").read_text()
    (command,) = re.findall(r"^\s*\$ (wrenchcone plot .*)$", readme, re.M)
    args = shlex.split(command)[1:]
    committed = ROOT / args[args.index("-o") + 1]
    assert f"]({committed.relative_to(ROOT)})" in readme  # the README shows that file
    args[args.index("-o") + 1] = str(tmp_path / committed.name)
    out = run(*args)
    assert out.returncode == 0, out.stderr
    a = matplotlib.image.imread(committed)
    b = matplotlib.image.imread(tmp_path / committed.name)
    assert a.shape == b.shape
    # the same picture: at most 0.2 % of the pixels differ (another matplotlib version
    # may move a little antialiasing; the wrench drawn reversed changes 0.75 %)
    assert np.mean(np.any(np.abs(a - b) > 0.1, axis=-1)) < 0.002
