# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's examples in README.md and docs/node.md run as shown, against the node program.

The node is started as ``make run`` starts it: the installed program, the default scene,
the node name ``/wrenchcone`` (in this test run's own ROS domain, test/node/conftest.py).
Then, each as a program of its own, exactly as the docs write them: every
``$ python -m wrenchcone_ros.ros.client ...`` line of a ```console block, and the Python
client example of docs/node.md (a ```python block followed by the ```text block of what it
prints). Each must print what the docs show (numbers to a relative 1e-6,
test/helpers/docs_examples.py).
"""

from __future__ import annotations

import os
from pathlib import Path
import re
import shlex
import signal
import subprocess
import sys
import threading

import pytest
from helpers.docs_examples import ROOT, commands, programs, same_output
from helpers.node_harness import DEADLINE_S, installed_program

NODE_COMMAND = "python -m wrenchcone_ros.ros.client "
DOCS = [ROOT / "README.md", ROOT / "docs" / "node.md"]
CLIENT_COMMANDS = [c for p in DOCS for c in commands(p) if c.command.startswith(NODE_COMMAND)]
PROGRAMS = programs(ROOT / "docs" / "node.md")


#: What `make run` passes (the Makefile's RUN_ARGS): the paper's disc as the scene file.
RUN_ARGS = ["--ros-args", "-p", f"scene_file:={Path(__file__).resolve().parents[2]}"
            "/examples/paper_disc.yaml"]


@pytest.fixture(scope="module")
def node_program():
    """The node as `make run` starts it; stopped with SIGINT (as Ctrl-C) at the end."""
    proc = subprocess.Popen([str(installed_program("wrenchcone_node")), *RUN_ARGS],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ))
    ready, log = threading.Event(), []

    def drain():  # read the log to its end, so the node never blocks on a full pipe
        for line in proc.stderr:
            log.append(line)
            if "ready:" in line:
                ready.set()

    reader = threading.Thread(target=drain, daemon=True)
    reader.start()
    try:
        assert ready.wait(DEADLINE_S * 2), "".join(log)
        yield proc
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(DEADLINE_S)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        reader.join(DEADLINE_S)


def run(argv: list[str]) -> str:
    out = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=dict(os.environ),
                         timeout=DEADLINE_S * 2, check=False)
    return out.stdout + out.stderr


def test_the_docs_have_their_node_examples():
    assert {c.path.name for c in CLIENT_COMMANDS} == {"README.md", "node.md"}
    assert len(CLIENT_COMMANDS) >= 5 and len(PROGRAMS) == 1


@pytest.mark.slow
@pytest.mark.parametrize("example", CLIENT_COMMANDS, ids=str)
def test_client_command_prints_what_the_docs_show(example, node_program):
    argv = shlex.split(example.command)
    got = run([sys.executable, *argv[1:]])
    assert same_output(example.output, got), (
        f"{example}\n--- documented ---\n{example.output}\n--- printed ---\n{got}")


@pytest.mark.slow
@pytest.mark.parametrize("pair", PROGRAMS, ids=lambda p: f"node.md:{p[0].line}")
def test_client_example_prints_what_the_docs_show(pair, node_program, tmp_path):
    program, printed = pair
    script = tmp_path / "client_example.py"
    script.write_text(program.text)
    got = run([sys.executable, str(script)])
    assert same_output(printed.text, got), (
        f"--- documented ---\n{printed.text}\n--- printed ---\n{got}")


def parameters_table() -> dict[str, list[str]]:
    """docs/node_reference.md's parameters table, read as a reader would: name -> its
    cells (type, default, unit, allowed, meaning); checked to be one table."""
    text = (ROOT / "docs" / "node_reference.md").read_text()
    lines = text[text.index("## Parameters"):].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| name |"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip().replace("\\|", "|")
                 for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]
        rows.append(cells)
    return {r[0].strip("`"): r[1:] for r in rows}


def documented_value(text: str):
    """A default cell's value: the part after "else " for a scene-file parameter."""
    text = text.split("else ")[-1].strip("`")
    if text in ("unset", '""', "true", "false"):
        return {"unset": None, '""': "", "true": True, "false": False}[text]
    if text.startswith("["):
        inner = text.strip("[]").strip()
        return [documented_value(t.strip()) for t in inner.split(",")] if inner else []
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def test_the_parameters_table_is_the_generated_one():
    """`python -m wrenchcone_ros.node.parameter_files --write` rewrites it."""
    from wrenchcone_ros.node.parameter_files import doc_table, markdown_table

    doc = (ROOT / "docs" / "node_reference.md").read_text()
    start, end = doc_table(doc)
    assert doc[start:end] == markdown_table()


def test_the_parameters_table_says_every_row_of_the_parameter_table():
    """One table, one row per parameter, each with the type, default, unit, range and
    read-only flag of its row (parsed back from the doc's text)."""
    from wrenchcone_ros.node import parameters as params

    table = parameters_table()
    assert list(table) == list(params.PARAMETERS)
    defaults = params.builtin_defaults()
    for spec in params.SPECS:
        type_, default, unit, allowed, meaning = table[spec.name]
        assert type_ == spec.type, spec.name
        assert documented_value(default) == defaults[spec.name], (spec.name, default)
        assert ("scene_file's" in default) == (spec.default is params.FROM_SCENE)
        assert unit == (spec.unit or "-"), spec.name
        if spec.low is not None:
            low, high = re.findall(r"[-\d.e+]+|pi/2|pi", allowed.split("in ")[-1])[-2:]
            assert float(low) == (spec.low if spec.min_nonzero is None
                                  else spec.min_nonzero), spec.name
            assert high in ("pi/2", "pi") or float(high) == spec.high, spec.name
        assert meaning.startswith("**Read-only**") == spec.read_only, spec.name
        assert spec.description in meaning, spec.name
