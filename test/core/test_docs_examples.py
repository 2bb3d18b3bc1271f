# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Every example in README.md and docs/*.md runs as shown (the core and CLI ones).

``$ wrenchcone ...`` commands of ```console blocks run through ``wrenchcone_ros.cli.main``
(the code behind the ``wrenchcone`` script) and must print what the docs show (standard
output and error together); ```pycon blocks are doctests. Both run in a scratch
directory that holds ``examples/`` (the repository's) and an empty ``docs/``, so the
documented relative paths work and a documented ``-o docs/...`` writes nothing into the
repository. Numbers compare to a relative 1e-6 (test/helpers/docs_examples.py). The node's
examples (``python -m wrenchcone_ros.ros.client``, the Python client) run against a node in
test/node/test_docs_node.py.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex

import pytest
from helpers.docs_examples import ROOT, blocks, commands, doc_files, run_doctest, same_output

CORE_COMMAND = "wrenchcone "
NODE_COMMAND = "python -m wrenchcone_ros.ros.client "

ALL_COMMANDS = [c for p in doc_files() for c in commands(p)]
CLI_COMMANDS = [c for c in ALL_COMMANDS if c.command.startswith(CORE_COMMAND)]
PYCON = [b for p in doc_files() for b in blocks(p) if b.lang == "pycon"]


@pytest.fixture
def scratch(tmp_path):
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "docs").mkdir()
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        yield tmp_path
    finally:
        os.chdir(old)


def run_cli(command: str) -> str:
    from wrenchcone_ros import cli

    argv = shlex.split(command)
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        try:
            cli.main(argv[1:])
        except SystemExit:  # argparse's errors exit 2 after printing their line
            pass
    return out.getvalue()


def test_the_docs_have_their_examples():
    """The extraction finds what the docs show, so an emptied block cannot pass silently."""
    names = {c.path.name for c in CLI_COMMANDS}
    assert {"README.md", "theory.md"} <= names, names
    assert len(CLI_COMMANDS) >= 7 and len(PYCON) >= 4
    assert {b.path.name for b in PYCON} >= {"README.md", "theory.md", "performance.md"}


def test_every_console_command_is_run_by_a_test():
    """A console block holds only commands that this test or the node's test runs."""
    for c in ALL_COMMANDS:
        assert c.command.startswith((CORE_COMMAND, NODE_COMMAND)), (
            f"{c}: not a command the docs tests run; show it in a plain indented block "
            "if it has no output to check")


#: Commands that draw a figure (matplotlib): slow, left out of `make test-fast`.
DRAWS = ("wrenchcone plot ",)


@pytest.mark.parametrize("example", [
    pytest.param(c, marks=pytest.mark.slow) if c.command.startswith(DRAWS) else c
    for c in CLI_COMMANDS], ids=str)
def test_command_prints_what_the_docs_show(example, scratch):
    got = run_cli(example.command)
    assert same_output(example.output, got), (
        f"{example}\n--- documented ---\n{example.output}\n--- printed ---\n{got}")


@pytest.mark.parametrize("block", PYCON, ids=lambda b: f"{b.path.name}:{b.line}")
def test_python_example_runs_as_shown(block, scratch):
    failed, report = run_doctest(block)
    assert failed == 0, report


def test_a_changed_output_fails():
    """The comparison is strict where it must be: text, count and value of numbers."""
    doc = "arr  margin 0.0768186\n[ 0.680414,  0,  0.707107]"
    assert same_output(doc, "arr margin 0.07681860001\n[ 0.680414, 0, 0.707107]")
    assert not same_output(doc, "arr  margin 0.0768\n[ 0.680414,  0,  0.707107]")
    assert not same_output(doc, "arrr margin 0.0768186\n[ 0.680414,  0,  0.707107]")
    assert not same_output(doc, "arr  margin 0.0768186\n[ 0.680414,  0]")
    assert not same_output("True", "False")


def test_the_readme_scene_file_example_is_a_valid_scene():
    import yaml

    from wrenchcone_ros.core import load_scene, wrench_cone

    (block,) = [b for b in blocks(ROOT / "README.md") if b.lang == "yaml"]
    scene = load_scene(yaml.safe_load(block.text))
    assert scene.modes == ("na",) and wrench_cone(scene, "na").feasible


def test_the_node_figures_are_those_of_the_results_files():
    """docs/node.md quotes the current results files, not figures typed by hand."""
    from helpers.docs_examples import node_figures

    text = (ROOT / "docs" / "node.md").read_text()
    assert node_figures() in text, (
        "docs/node.md 'Current figures' differ from benchmarks/results/; paste the output of "
        "`.venv/bin/python test/helpers/docs_examples.py`")


def test_the_plan_figures_are_those_of_the_results_files():
    """docs/planning.md quotes the current plan_arrival.json, not figures typed by hand
    (compared with the whitespace normalised: the docs may wrap the sentences)."""
    from helpers.docs_examples import plan_arrival_figures

    text = " ".join((ROOT / "docs" / "planning.md").read_text().split())
    blocks = [" ".join(b.split()) for b in plan_arrival_figures().split("\n\n")]
    perf = " ".join((ROOT / "docs" / "performance.md").read_text().split())
    assert blocks[1] in perf, "docs/performance.md's planning figures differ from the JSON"
    assert all(b in text for b in blocks), (
        "docs/planning.md section 7 differs from benchmarks/results/plan_arrival.json; "
        "paste the output of `.venv/bin/python test/helpers/docs_examples.py`")


def test_the_design_figures_are_those_of_the_results_files():
    """docs/performance.md quotes the current design_cost.json: each block of
    design_figures() (tables, sentences), whitespace normalised, prose between them."""
    from helpers.docs_examples import design_figures

    text = " ".join((ROOT / "docs" / "performance.md").read_text().split())
    blocks = [" ".join(b.split()) for b in design_figures().split("\n\n")]
    assert all(b in text for b in blocks), (
        "docs/performance.md's fixture-design figures differ from "
        "benchmarks/results/design_cost.json; paste the output of "
        "`.venv/bin/python test/helpers/docs_examples.py`")


# --- what a reader pastes: quoted wildcards, outputs without round-off noise ------------
EVERY_DOC = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
EVERY_COMMAND = [c for p in EVERY_DOC for c in commands(p)]
_GLOB = set("*?[")
#: a printed number that is -0 or round-off: -0, -0.000, or a magnitude below 1e-12
_NOISE = re.compile(r"(?<![\w.])(-0(?:\.0*)?(?![\d.eE])|[-+]?\d(?:\.\d*)?[eE]-(?:1[2-9]|[2-9]\d|\d{3}))")


def test_every_wildcard_in_a_documented_command_is_quoted():
    """A shell expands an unquoted ``a**`` (to ``action/`` in the repository): every
    token of a ``$`` line with a glob character is in quotes, in every doc, tutorials
    included."""
    assert len(EVERY_COMMAND) > len(ALL_COMMANDS)  # the tutorials are included
    bad = []
    for c in EVERY_COMMAND:
        lexer = shlex.shlex(c.command, posix=False)
        lexer.whitespace_split = True
        bad += [f"{c}: {tok}" for tok in lexer if _GLOB & set(tok) and tok[0] not in "'\""]
    assert not bad, "quote these for the shell:\n" + "\n".join(bad)


@pytest.mark.parametrize("cmd", [c for c in EVERY_COMMAND if c.command.startswith(CORE_COMMAND)
                                 and "--json" not in c.command], ids=str)
def test_documented_outputs_print_no_round_off_noise(cmd):
    """The CLI prints no -0 and no 1e-16 in its rows (the indented lines: cone rows,
    interval and plan tables; cli/render.py), so neither do the docs that quote it
    (``--json`` carries the unrounded values and is left out)."""
    rows = "\n".join(line for line in cmd.output.splitlines() if line.startswith("  "))
    noise = [m.group(0) for m in _NOISE.finditer(rows)]
    assert not noise, f"{cmd}: {noise}"


@pytest.mark.parametrize("scene, mode", [("examples/pawl_polygon.yaml", "arr"),
                                         ("examples/pawl_polygon.yaml", "a**"),
                                         ("examples/paper_disc.yaml", "c*"),
                                         ("default", "ss")])
def test_cone_prints_its_rows_rounded_without_noise(scene, mode):
    """``wrenchcone cone`` against the cone's own arrays read independently of the
    printer: each printed row equals the computed one to 6 significant digits, with the
    entries below 1e-12 in the unit-row metric printed as 0, and no noise token."""
    import numpy as np

    from wrenchcone_ros.core import default_scene, load_scene, wrench_cone
    from wrenchcone_ros.core.modes import expand_mode

    with contextlib.chdir(ROOT):
        text = run_cli(f"wrenchcone cone {scene} --mode '{mode}'")
        sc = default_scene() if scene == "default" else load_scene(scene)
    cones = [wrench_cone(sc, m) for m in expand_mode(mode, sc.in_contact)]
    if len(cones) > 1:  # a wildcard prints its feasible modes' cones
        cones = [c for c in cones if c.feasible]
    assert not _NOISE.findall(text), text
    printed = [np.array([float(v) for v in line.strip()[1:-1].split(",")])
               for line in text.splitlines() if line.startswith("  [")]
    expected = []
    for cone in cones:
        for rows, unit in ((cone.F, cone.F_hat), (cone.equalities, cone.E_hat),
                           (cone.G, cone.G_hat), (cone.lineality, cone.L_hat)):
            expected += [np.where(np.abs(u) < 1e-12, 0.0, r) for r, u in zip(rows, unit)]
    assert len(printed) == len(expected) > 0
    for p, e in zip(printed, expected):
        assert np.allclose(p, e, rtol=5e-6, atol=0.0), (p, e)


def test_the_planner_speed_figures_are_those_of_the_results_file():
    """docs/performance.md quotes the current plan_speed.json (its table and sentence,
    whitespace normalised), and that run found every plan identical in both trees."""
    import json

    from helpers.docs_examples import RESULTS, plan_speed_figures

    assert json.loads((RESULTS / "plan_speed.json").read_text())["summary"]["digests_equal"]
    text = " ".join((ROOT / "docs" / "performance.md").read_text().split())
    blocks = [" ".join(b.split()) for b in plan_speed_figures().split("\n\n")]
    assert all(b in text for b in blocks), (
        "docs/performance.md's planner figures differ from "
        "benchmarks/results/plan_speed.json; paste the output of "
        "`.venv/bin/python test/helpers/docs_examples.py`")
