# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The wrenchcone CLI as a user runs it: a real subprocess, JSON parsed, exit codes."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from pathlib import Path

from helpers.cli import run
from helpers.paper_example import PAPER_G, same_rays

pytestmark = pytest.mark.slow  # every test runs the command in a subprocess (an interpreter start-up each)


@pytest.mark.parametrize("extra", [[], ["--exact"], ["--method", "paper"]])
def test_cone_json_is_the_papers_cone(extra):
    out = run("cone", "examples/paper_disc.yaml", "--mode", "na", "--json", *extra)
    assert out.returncode == 0, out.stderr
    top = json.loads(out.stdout)
    d = top["cone"]  # the one piece of the set (the same keys with or without uncertainty)
    assert [d] == top["pieces"] and top["guarantee"] == "exact"
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


def test_wildcard_cone_prints_the_union():
    """`wrenchcone cone examples/paper_disc.yaml --mode 'c*'` crashed (AttributeError on
    a union of cones); it prints every piece, each equal to the core's concrete cone."""
    from wrenchcone_ros.core import default_scene, wrench_cone
    from wrenchcone_ros.core.modes import expand_mode

    r = run("cone", "examples/paper_disc.yaml", "--mode", "c*", "--json")
    code, out, err = r.returncode, r.stdout, r.stderr
    assert code == 0 and "Traceback" not in err, err
    d = json.loads(out)
    scene = default_scene()
    concrete = expand_mode("c*", scene.in_contact)
    assert sorted([p["mode"] for p in d["pieces"]] + d["impossible"]) == sorted(concrete)
    for p in d["pieces"]:
        assert np.allclose(np.array(p["F"]).reshape(-1, 3), wrench_cone(scene, p["mode"]).F)
    r = run("cone", "examples/paper_disc.yaml", "--mode", "c*")
    code, out = r.returncode, r.stdout
    assert code == 0 and "union of" in out and out.count("mode '") >= 1 + len(d["pieces"])


def test_check_exit_code_for_scripts():
    ok = ("check", "default", "--mode", "na", "--wrench", "0.1", "-1", "0", "--exit-code")
    assert run(*ok).returncode == 0
    bad = ("check", "default", "--mode", "na", "--wrench", "0", "1", "0", "--exit-code")
    assert run(*bad).returncode == 1
    assert run(*bad[:-1]).returncode == 0  # without the flag: 0 whatever the verdict
    r = run("check", "default", "--mode", "zz", "--wrench", "0", "1", "0", "--exit-code")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert run("check", "default", "--mode", "c*", "--wrench", "0.1", "-1", "0",
               "--exit-code").returncode == 0


@pytest.mark.parametrize("command", ["cone", "check", "classify"])
def test_every_command_has_help(command):
    r = run(command, "--help")
    assert r.returncode == 0 and "usage" in r.stdout


def test_main_in_process_leaves_the_engine_choice_of_the_process_alone(monkeypatch,
                                                                      capsys):
    """The CLI computes with the numpy engine for one-shot commands, but cli.main is
    also called in-process (tests, scripts, notebooks): it used to set
    $WRENCHCONE_ENGINE=numpy for the rest of the process, so every later cone there
    (in CI: the node tests) silently ran on the reference engine."""
    from wrenchcone_ros import cli
    from wrenchcone_ros.core import engines

    environ = dict(os.environ)
    before = engines.resolve_engine()
    made = engines.KERNEL_STATS["kernel_cones"]
    assert cli.main(["check", "default", "--mode", "na", "--wrench", "1", "0", "-1"]) == 0
    assert dict(os.environ) == environ  # the CLI passes the engine, it writes no variable
    assert engines.resolve_engine() == before
    if engines.engine_from_environment() is None:  # the command ran on the numpy engine
        assert engines.KERNEL_STATS["kernel_cones"] == made
    with engines.using_engine("kernel"):
        assert cli.main(["check", "default", "--mode", "na", "--wrench", "1", "0", "-1"]) == 0
        assert engines.default_engine().name == engines.resolve_engine("kernel")
    capsys.readouterr()


def _subparsers(parser):
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action.choices
    return {}


def test_every_option_of_every_command_has_a_help_text():
    """`wrenchcone check --help` listed --mode without any text: every option and
    positional of every subcommand says what it is."""
    from wrenchcone_ros import cli

    missing = [f"{name} {'/'.join(a.option_strings) or a.dest}"
               for name, sp in _subparsers(cli.build_parser()).items()
               for a in sp._actions if not a.help]
    assert missing == []


@pytest.mark.parametrize("wrench", [
    ["0.5", "-1e-3", "0"],  # a negative exponent: refused by argparse
    ["0.5", "-1E+3", "0"],
    ["-.5", "-1", "0"],
    ["-1e-3", "1e3", "-0.0"],
    ["1", "-2.5e-1", "-3."],
])
def test_wrench_accepts_every_float_literal(wrench):
    """`--wrench 0.5 -1e-3 0` was refused by argparse ("expected 3 arguments"): a
    negative number with an exponent (or '-.5') looked like an option to it. The values
    reach the computation as written: the verdict is the core's for that wrench."""
    from wrenchcone_ros.core import default_scene, wrench_cone

    out = run("check", "default", "--mode", "na", "--wrench", *wrench)
    assert out.returncode == 0, out.stderr
    g = [float(v) for v in wrench]
    verdict = "consistent" if wrench_cone(default_scene(), "na").contains(g) else \
        "NOT consistent"
    assert f"wrench {g} is {verdict} with mode 'na'" in out.stdout, out.stdout


@pytest.mark.parametrize("bad", ["-inf", "inf", "nan", "-nan", "-Infinity"])
def test_non_finite_wrench_is_refused_with_a_clear_message(bad):
    out = run("check", "default", "--mode", "na", "--wrench", "1", bad, "0")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "--wrench must be three finite numbers" in out.stderr, out.stderr


def test_huge_wrench_is_rescaled_like_the_node():
    """`--wrench 1e200 -1 -1` said "must be finite" (the squares overflow): the wrench is
    rescaled by a power of two as the node does (a cone is a cone), and the verdict and
    margin are those of the same direction at an ordinary size."""
    import math

    big = run("check", "default", "--mode", "na", "--wrench", "1e200", "-1", "-1", "--json")
    assert big.returncode == 0, big.stderr
    small = run("check", "default", "--mode", "na", "--wrench", "1", "-1e-200", "-1e-200",
                "--json")
    b, s = json.loads(big.stdout), json.loads(small.stdout)
    assert b["consistent"] == s["consistent"] and math.isclose(b["margin"], s["margin"])
    tiny = run("check", "default", "--mode", "na", "--wrench", "1e-300", "-1e-300", "-1e-300",
               "--json")
    unit = run("check", "default", "--mode", "na", "--wrench", "1", "-1", "-1", "--json")
    t, u = json.loads(tiny.stdout), json.loads(unit.stdout)
    assert tiny.returncode == 0 and t["consistent"] == u["consistent"] is True
    assert math.isclose(t["margin"], u["margin"])
    out = run("classify", "default", "--wrench", "1e200", "-1e200", "-1e200", "--json")
    assert out.returncode == 0 and "na" in {m["mode"] for m in json.loads(out.stdout)["modes"]}


def test_margin_on_the_boundary_prints_zero_not_minus_zero():
    out = run("check", "default", "--mode", "na", "--wrench", "1", "0", "-1")
    assert out.returncode == 0 and out.stdout.rstrip().endswith("margin 0"), out.stdout
    out = run("check", "default", "--mode", "na", "--wrench", "1", "0", "-1", "--json")
    assert '"margin": 0.0' in out.stdout, out.stdout


LAZY = r"""
import sys
{body}
heavy = sorted(m for m in ("scipy", "numba", "matplotlib", "rclpy") if m in sys.modules)
print("HEAVY", heavy)
"""


@pytest.mark.parametrize("body", [
    "import wrenchcone_ros.core",
    "from wrenchcone_ros import cli\ntry:\n    cli.main(['--version'])\nexcept SystemExit:\n"
    "    pass",
    "from wrenchcone_ros import cli\ntry:\n    cli.main(['--help'])\nexcept SystemExit:\n"
    "    pass",
    "from wrenchcone_ros import cli\ntry:\n    cli.main(['check', '--help'])\nexcept SystemExit:\n"
    "    pass",
])
def test_import_and_help_do_not_import_scipy_or_numba(body):
    """`import wrenchcone_ros.core` took 0.9 s, 0.6 s of it scipy.optimize imported by
    cones.py at module level, and `wrenchcone --version` paid it: scipy (and numba, and
    matplotlib) are imported where they are used, so --help and --version do not load
    them. (The wall time is measured, not asserted: see the report of this change.)"""
    out = subprocess.run([sys.executable, "-c", LAZY.format(body=body)], capture_output=True,
                         text=True)
    assert out.returncode == 0, out.stderr
    assert "HEAVY []" in out.stdout, out.stdout


LOADED = r"""
import sys
from wrenchcone_ros import cli
try:
    cli.main({argv!r})
except SystemExit:
    pass
print("LOADED", sorted(m for m in {names!r} if m in sys.modules))
"""

#: What a subcommand's work needs and --version or --help does not: numpy, pycddlib, the
#: core, the planner (pymunk), the fixture designer (Dask) and every subcommand's module.
HEAVY = ("numpy", "cdd", "numba", "pymunk", "dask", "wrenchcone_ros.core",
         "wrenchcone_ros.core.plan", "wrenchcone_ros.design",
         *(f"wrenchcone_ros.cli.{name}" for name in ("cone", "check", "classify",
                                                     "directions", "sweep", "plot", "plan",
                                                     "design", "replay")))


@pytest.mark.parametrize("argv, allowed", [
    (["--version"], ()),
    (["--help"], ()),
    # a subcommand's --help imports that subcommand's module and what it needs, not the
    # planner's, the designer's or the other subcommands'
    (["check", "--help"], ("numpy", "cdd", "wrenchcone_ros.core", "wrenchcone_ros.cli.check")),
    (["cone", "--help"], ("numpy", "cdd", "wrenchcone_ros.core", "wrenchcone_ros.cli.cone")),
])
def test_version_and_help_import_only_what_they_need(argv, allowed):
    """`wrenchcone --version` took 0.5-0.7 s on a 2-core machine: the CLI imported every
    subcommand, the planner and the fixture designer included, before it read its
    arguments. The parser is built from the command table and only the subcommand that
    runs has its module imported. (What is asserted is what is imported, not a time:
    docs/performance.md quotes the measured start-up.)"""
    out = subprocess.run([sys.executable, "-c", LOADED.format(argv=argv, names=HEAVY)],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    loaded = out.stdout.split("LOADED", 1)[1].strip()
    assert loaded == repr(sorted(allowed)), (argv, loaded)


def test_the_complete_parser_and_the_one_main_builds_agree():
    """main() builds only the named subcommand's options: each subcommand's help from the
    one-command parser is the complete parser's, and --help lists every subcommand."""
    from wrenchcone_ros import cli

    full = _subparsers(cli.build_parser())
    assert list(full) == list(cli.COMMANDS)
    for name in cli.COMMANDS:
        one = _subparsers(cli.build_parser([name]))
        assert one[name].format_help() == full[name].format_help(), name
        assert all(not sp._actions[1:] for other, sp in one.items() if other != name)
    assert cli.build_parser([]).format_help() == cli.build_parser().format_help()


def test_a_scene_outside_the_verified_range_gets_one_warning_line(tmp_path, capsys):
    """The CLI prints the core's UnverifiedRangeWarning as one line on stderr (no source
    line, no traceback) and still answers."""
    from wrenchcone_ros.cli import main

    text = (Path(__file__).resolve().parents[2] / "examples" / "pawl_polygon.yaml").read_text()
    heavy = tmp_path / "heavy.yaml"
    heavy.write_text(text.replace("mass: 0.05 ", "mass: 1.0e3"))
    assert main(["cone", str(heavy), "--mode", "snn"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("wrenchcone: warning: I/(m L^2) = 1.15e-05")
