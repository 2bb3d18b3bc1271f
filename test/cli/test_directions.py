# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone directions`` and ``wrenchcone sweep``: end to end as a user runs them (a
subprocess), and the error matrix in-process through ``cli.main`` (same code, no
interpreter start-up per case)."""

import json
import math

import pytest

from helpers.cli import run
from wrenchcone_ros import cli
from wrenchcone_ros.core import force_directions, load_scene, sweep


class Result:
    def __init__(self, returncode, stdout, stderr):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


def main(capsys, *args):
    try:
        code = cli.main(list(args))
    except SystemExit as exc:  # argparse errors
        code = exc.code
    out = capsys.readouterr()
    return Result(code, out.out, out.err)

PAWL = "examples/pawl_polygon.yaml"
POSES = "examples/pawl_slide_poses.yaml"


@pytest.mark.parametrize("extra, kw", [
    (["--exact"], {"exact": True}),
    (["--exclusive", "--point", "0.0075", "0.035"], {"exclusive": True, "point": (0.0075, 0.035)}),
])
@pytest.mark.slow
def test_directions_json_equals_the_core(extra, kw):
    out = run("directions", PAWL, "--mode", "arr", "--json", *extra)
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    core = force_directions(load_scene(PAWL), "arr", **kw)
    assert [(iv["lo"], iv["hi"], iv["best"], iv["margin"]) for iv in d["intervals"]] == [
        (iv.lo, iv.hi, iv.best, iv.margin) for iv in core]
    if kw.get("exact"):
        assert d["intervals"][0]["lo_direction"] == ["1", "-10/3"]


def test_directions_table_in_degrees_and_radians(capsys):
    out = main(capsys, "directions", PAWL, "--mode", "a**")
    assert out.returncode == 0, out.stderr
    assert "lo deg" in out.stdout and "lo rad" in out.stdout
    assert "-73.3008" in out.stdout and "90.0000" in out.stdout


def test_directions_none(capsys):
    out = main(capsys, "directions", PAWL, "--mode", "ann")
    assert out.returncode == 0 and out.stdout.strip().endswith("none")


@pytest.mark.slow
def test_sweep_json_equals_the_core():
    out = run("sweep", PAWL, "--mode", "arr", "--poses", POSES, "--point", "0.0075", "0.035",
              "--json")
    assert out.returncode == 0, out.stderr
    d = json.loads(out.stdout)
    import yaml

    poses = yaml.safe_load(open(POSES))["poses"]
    res = sweep(load_scene(PAWL), poses, "arr", point=(0.0075, 0.035))
    assert d["stop"] == res.stop == 8
    assert [(iv["lo"], iv["hi"]) for iv in d["common"]] == [(iv.lo, iv.hi) for iv in res.common]
    assert [m["mode"] for m in d["after"]] == [m.mode for m in res.after]
    assert d["intervals"][8] is None and len(d["intervals"][0]) == 1


def test_sweep_table(capsys):
    out = main(capsys, "sweep", PAWL, "--mode", "arr", "--poses", POSES)
    assert out.returncode == 0, out.stderr
    assert "stops at pose 8" in out.stdout and "fixel 1 is in contact" in out.stdout
    assert "valid at every pose before that (8)" in out.stdout


@pytest.mark.parametrize("args, needle", [
    (["directions", PAWL, "--mode", "nrr"], "fixel 1 is not in contact"),
    (["directions", "nope.yaml", "--mode", "arr"], "cannot read scene file"),
    (["directions", PAWL, "--mode", "arr", "--point", "0", "nan"], "finite"),
    (["directions", PAWL, "--mode", "arr", "--point", "0"], "--point"),
    (["directions", PAWL], "--mode"),
    (["sweep", PAWL, "--mode", "arr"], "--poses"),
    (["sweep", PAWL, "--mode", "arr", "--poses", "nope.yaml"], "cannot read poses file"),
])
def test_bad_input_exit_2_one_line(capsys, args, needle):
    out = main(capsys, *args)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    lines = [ln for ln in out.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0]


@pytest.mark.parametrize("text, needle", [
    ("- [0.1, 0.2]\n", "pose 0"),
    ("poses: 3\n", "non-empty list"),
    ("other: []\n", "'poses'"),
    ("- [0.1, 0.19, 0.0]\n", "penetrates"),
    ("[", "not valid YAML"),
])
def test_bad_poses_file(capsys, tmp_path, text, needle):
    p = tmp_path / "p.yaml"
    p.write_text(text)
    out = main(capsys, "sweep", PAWL, "--mode", "arr", "--poses", str(p))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    lines = [ln for ln in out.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0], lines


def test_degrees_match_radians(capsys):
    d = json.loads(main(capsys, "directions", PAWL, "--mode", "arr", "--json").stdout)
    iv = d["intervals"][0]
    assert iv["lo_deg"] == pytest.approx(math.degrees(iv["lo"]))
