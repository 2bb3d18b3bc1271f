"""The client example against the real node: as a library and as a command."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from wrenchcone_ros.client import WrenchConeClient
from wrenchcone_ros.core import consistent_modes, default_scene, force_directions, wrench_cone


def test_library_calls(harness):
    client = WrenchConeClient(harness.tester, server=f"{harness.ns}/wrenchcone")
    assert client.wait_for_service(30)
    cone = wrench_cone(default_scene(), "na")
    r = client.check_wrench("na", (0.1, -1.0, 0.0))
    assert r.status == r.OK and r.consistent
    assert r.margin == pytest.approx(cone.margin((0.1, -1.0, 0.0)), abs=1e-12)
    c = client.get_cone("na")
    assert c.feasible and c.F.shape == cone.F.shape
    assert c.contains((0.1, -1.0, 0.0)) and not c.contains((0.0, 1.0, 0.0))
    k = client.classify_wrench((0.1, -1.0, 0.0))
    assert list(k.modes) == [m.mode for m in consistent_modes(default_scene(),
                                                               (0.1, -1.0, 0.0))]
    r = client.check_wrench("na", (0.1, -1.0, 0.0), classify=True)
    assert list(r.other_modes) == [m for m in k.modes if m != "na"]
    for point in (None, (0.0, 0.5)):
        d = client.force_directions("na", point)
        core = force_directions(default_scene(), "na", point=point)
        assert d.status == d.OK and list(zip(d.lo, d.hi)) == [(i.lo, i.hi) for i in core]


def run_cli(harness, *args):
    # a fresh process in the same (isolated) ROS domain; cwd is the repository root, so
    # the source tree shadows the install tree on sys.path: the client must cope
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run(
        [sys.executable, "-m", "wrenchcone_ros.client", *args,
         "--node", f"{harness.ns}/wrenchcone", "--timeout", "30"],
        capture_output=True, text=True, cwd=root, env=dict(os.environ), check=False)
    return out.returncode, json.loads(out.stdout.strip().splitlines()[-1])


def test_command_line(harness):
    code, out = run_cli(harness, "check", "na", "0.1", "-1", "0")
    assert code == 0 and out["consistent"] is True and out["status"] == "OK"
    code, out = run_cli(harness, "cone", "na")
    assert code == 0 and out["feasible"] and len(out["F"]) == 3
    code, out = run_cli(harness, "classify", "0.1", "-1", "0")
    assert code == 0 and "na" in out["modes"]
    code, out = run_cli(harness, "directions", "na")  # at the com
    core = force_directions(default_scene(), "na")
    assert code == 0 and [(i["lo"], i["hi"]) for i in out["intervals"]] == [
        (iv.lo, iv.hi) for iv in core]
    code, out = run_cli(harness, "force_directions", "na", "--point", "0", "0.5",
                        "--exclusive")
    core = force_directions(default_scene(), "na", point=(0.0, 0.5), exclusive=True)
    assert code == 0 and [i["best"] for i in out["intervals"]] == [iv.best for iv in core]
    code, out = run_cli(harness, "check", "nn", "0.1", "-1", "0")
    assert code == 3 and out["status"] == "MODE_NOT_ALLOWED" and out["consistent"] is False


def test_command_line_help():
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.client", "directions",
                          "--help"], capture_output=True, text=True, check=False)
    assert out.returncode == 0 and "--point" in out.stdout and "--exclusive" in out.stdout


@pytest.mark.parametrize("args", [["--help"], ["check", "--help"], ["cone", "--help"],
                                  ["classify", "--help"], ["directions", "--help"]])
def test_client_help(args):
    """`check --help` / `classify --help` raised ValueError (a tuple metavar)."""
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.client", *args],
                         capture_output=True, text=True, check=False, timeout=60)
    assert out.returncode == 0 and "usage" in out.stdout and not out.stderr


@pytest.mark.parametrize("args", [["check", "na", "1", "x", "0"], ["check", "na", "1", "nan", "0"],
                                  ["classify", "1", "2"], ["nope"]])
def test_client_bad_arguments_exit_2_one_line(args):
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.client", *args],
                         capture_output=True, text=True, check=False, timeout=60)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr
