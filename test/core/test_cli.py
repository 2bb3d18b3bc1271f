"""The wrenchcone CLI as a user runs it: a real subprocess, JSON parsed, exit codes."""

import json
import subprocess
import sys

import numpy as np
import pytest

from test_paper import PAPER_G, same_rays


def run(*args):
    return subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", *args],
                          capture_output=True, text=True)


@pytest.mark.parametrize("extra", [[], ["--exact"], ["--method", "paper"]])
def test_cone_json_is_the_papers_cone(extra):
    out = run("cone", "examples/paper_disc.yaml", "--mode", "na", "--json", *extra)
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    assert {"mode", "F", "equalities", "G"} <= set(d)
    assert d["mode"] == "na" and d["equalities"] == []
    assert same_rays(d["G"], PAPER_G)
    F = np.array(d["F"])
    assert F.shape == (3, 3) and np.all(F @ np.array(PAPER_G).T <= 1e-12)


def test_cone_table():
    out = run("cone", "default", "--mode", "na")
    assert out.returncode == 0 and "F (3 rows)" in out.stdout and "G (generators)" in out.stdout


def test_check_json():
    out = run("check", "examples/paper_disc.yaml", "--mode", "na", "--wrench", "1", "-1", "-1",
              "--json")
    d = json.loads(out.stdout)
    assert d["consistent"] is True and d["margin"] > 0
    out = run("check", "default", "--mode", "na", "--wrench", "-1", "1", "1", "--json")
    d = json.loads(out.stdout)
    assert d["consistent"] is False and d["margin"] < 0


def test_check_text():
    out = run("check", "default", "--mode", "na", "--wrench", "1", "-1", "-1")
    assert out.returncode == 0 and "is consistent" in out.stdout


@pytest.mark.parametrize("args, needle", [
    (["cone", "nope.yaml", "--mode", "na"], "cannot read scene file"),
    (["cone", "default", "--mode", "nn"], "fixel 2 is not in contact"),
    (["cone", "default", "--mode", "naa"], "3 letter"),
    (["cone", "default"], "--mode"),
    (["check", "default", "--mode", "na", "--wrench", "1", "2"], "--wrench"),
    (["check", "default", "--mode", "na", "--wrench", "1", "x", "2"], "invalid float"),
    (["check", "default", "--mode", "na", "--wrench", "nan", "0", "0"], "finite"),
    (["cone", "default", "--mode", "na", "--method", "magic"], "invalid choice"),
    (["frobnicate"], "invalid choice"),
    ([], "required"),
])
def test_bad_input_exit_2_one_line(args, needle):
    out = run(*args)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    lines = [ln for ln in out.stderr.splitlines() if ln.strip()]
    assert needle in lines[-1]
    assert lines[-1].startswith("wrenchcone: error:") or "usage" in out.stderr


def test_bad_scene_file(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text("workpiece: {mass: -1}\n")
    out = run("cone", str(p), "--mode", "n")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "mass must be > 0" in out.stderr or "missing required key" in out.stderr


def test_classify_json_and_text():
    out = run("classify", "default", "--wrench", "1", "-1", "-1", "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    modes = {m["mode"] for m in d["modes"]}
    assert "na" in modes and all(m["margin"] >= 0 for m in d["modes"])
    out = run("classify", "examples/paper_disc.yaml", "--wrench", "1", "-1", "-1")
    assert out.returncode == 0 and "na" in out.stdout
