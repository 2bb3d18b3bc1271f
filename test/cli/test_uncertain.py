# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The CLI's uncertainty options (cli/uncertain.py) as a user runs them: JSON against the
nominal answers at the friction box's corners (an independent route), the scene file's
uncertainty block, worded errors with exit status 2."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import subprocess
import sys

import pytest

from wrenchcone_ros.core import Fixel, force_directions, load_scene, wrench_cone

PAWL = "examples/pawl_polygon.yaml"


def run(*args):
    return subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", *args],
                          capture_output=True, text=True)


def corners():
    scene = load_scene(PAWL)
    return [dataclasses.replace(scene, fixels=tuple(
        Fixel(f.position, f.radius, mu) for f, mu in zip(scene.fixels, mus)))
        for mus in itertools.product((0.2, 0.4), repeat=3)]


@pytest.mark.slow
def test_check_every_and_some_model():
    g = (math.cos(math.radians(-68.71)), math.sin(math.radians(-68.71)), 0.0)
    out = run("check", PAWL, "--mode", "arr", "--wrench", *map(str, g), "--friction", "0.2",
              "0.4", "--json", "--exit-code")
    d = json.loads(out.stdout)
    at = [wrench_cone(s, "arr").contains(g) for s in corners()]
    assert d["consistent_every_model"] is all(at) is False
    assert d["consistent_some_model"] is any(at) is True
    assert d["guarantee"] == "exact" and out.returncode == 1


@pytest.mark.slow
def test_directions_json_is_the_intersection_of_the_corners():
    out = run("directions", PAWL, "--mode", "arr", "--friction", "0.2", "0.4", "--json")
    assert out.returncode == 0, out.stderr
    (iv,) = json.loads(out.stdout)["intervals"]
    nominal = [force_directions(s, "arr")[0] for s in corners()]
    assert iv["lo"] == pytest.approx(max(n.lo for n in nominal), abs=1e-9)
    assert iv["hi"] == pytest.approx(min(n.hi for n in nominal), abs=1e-9)
    assert iv["guarantee"] == "exact"


@pytest.mark.slow
def test_classify_flags_and_cone_any(tmp_path):
    g = ["0.362", "-0.932", "0"]
    out = run("classify", PAWL, "--wrench", *g, "--friction", "0.2", "0.4", "--json")
    modes = {m["mode"]: m for m in json.loads(out.stdout)["modes"]}
    assert set(modes) == {"arr", "snn"} and not any(m["certain"] for m in modes.values())
    out = run("cone", PAWL, "--mode", "arr", "--friction", "0.2", "0.4", "--quantifier", "any")
    assert out.returncode == 0 and "for some model of: friction [0.2, 0.4]" in out.stdout


@pytest.mark.slow
def test_the_scene_files_block_applies_and_options_override_it(tmp_path):
    path = tmp_path / "pawl.yaml"
    path.write_text(open(PAWL).read() + "uncertainty:\n  friction: [0.2, 0.4]\n")
    out = run("directions", str(path), "--mode", "arr", "--json")
    (iv,) = json.loads(out.stdout)["intervals"]
    assert math.degrees(iv["lo"]) == pytest.approx(-68.1986, abs=1e-4)
    out = run("directions", str(path), "--mode", "arr", "--json", "--friction", "0.3", "0.3")
    (iv,) = json.loads(out.stdout)["intervals"]
    assert math.degrees(iv["lo"]) == pytest.approx(-73.3008, abs=1e-4)


@pytest.mark.slow
@pytest.mark.parametrize("args, message", [
    (["--friction", "0.4", "0.2"], "lo must be <= hi"),
    (["--com-radius", "-1"], "com_radius must be >= 0"),
    (["--friction", "0.2", "0.4", "--com-radius", "0.001", "--exact"], "friction intervals only"),
])
def test_bad_uncertainty_is_refused_in_one_line(args, message):
    out = run("cone", PAWL, "--mode", "arr", *args)
    assert out.returncode == 2 and message in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


@pytest.mark.slow
def test_plot_with_uncertainty_draws_nominal_and_robust_side_by_side(tmp_path):
    pytest.importorskip("matplotlib")
    from wrenchcone_ros.core import Uncertainty, plot, robust_cone

    out = run("plot", PAWL, "--mode", "arr", "-o", str(tmp_path / "r.png"), "--friction",
              "0.2", "0.4")
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "r.png").stat().st_size > 10_000
    scene = load_scene(PAWL)
    rc = robust_cone(scene, "arr", Uncertainty(friction=(0.2, 0.4)))
    fig = plot.robust_figure(scene, "arr", wrench_cone(scene, "arr"), rc.cone, "friction")
    assert len(fig.axes) == 3 and "every model of friction" in fig.axes[2].get_title()
