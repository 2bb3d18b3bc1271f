"""The node's examples in README.md and docs/node.md run as shown, against the node program.

The node is started as ``make run`` starts it: the installed program, the default scene,
the node name ``/wrenchcone`` (in this test run's own ROS domain, test/node/conftest.py).
Then, each as a program of its own, exactly as the docs write them: every
``$ python -m wrenchcone_ros.ros.client ...`` line of a ```console block, and the Python
client example of docs/node.md (a ```python block followed by the ```text block of what it
prints). Each must print what the docs show (numbers to a relative 1e-6,
test/docs_examples.py).
"""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys
import threading

import pytest
from rclpy.parameter import Parameter
from docs_examples import ROOT, commands, programs, same_output
from node_harness import DEADLINE_S, installed_program

NODE_COMMAND = "python -m wrenchcone_ros.ros.client "
DOCS = [ROOT / "README.md", ROOT / "docs" / "node.md"]
CLIENT_COMMANDS = [c for p in DOCS for c in commands(p) if c.command.startswith(NODE_COMMAND)]
PROGRAMS = programs(ROOT / "docs" / "node.md")


@pytest.fixture(scope="module")
def node_program():
    """The node as `make run` starts it; stopped with SIGINT (as Ctrl-C) at the end."""
    proc = subprocess.Popen([str(installed_program("wrenchcone_node"))],
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


@pytest.mark.parametrize("example", CLIENT_COMMANDS, ids=str)
def test_client_command_prints_what_the_docs_show(example, node_program):
    argv = shlex.split(example.command)
    got = run([sys.executable, *argv[1:]])
    assert same_output(example.output, got), (
        f"{example}\n--- documented ---\n{example.output}\n--- printed ---\n{got}")


@pytest.mark.parametrize("pair", PROGRAMS, ids=lambda p: f"node.md:{p[0].line}")
def test_client_example_prints_what_the_docs_show(pair, node_program, tmp_path):
    program, printed = pair
    script = tmp_path / "client_example.py"
    script.write_text(program.text)
    got = run([sys.executable, str(script)])
    assert same_output(printed.text, got), (
        f"--- documented ---\n{printed.text}\n--- printed ---\n{got}")


def parameters_table() -> dict[str, tuple[str, str]]:
    """docs/node.md's parameters table: name -> (type, default), checked to be one table."""
    text = (ROOT / "docs" / "node.md").read_text()
    lines = text[text.index("## Parameters"):].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| name |"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip("|").split("|")])
    return {r[0].strip("`"): (r[1], r[2].strip("`")) for r in rows}


def documented_value(text: str):
    if text in ("true", "false"):
        return text == "true"
    if text == '""':
        return ""
    if text.startswith("["):
        items = [t.strip() for t in text.strip("[]").split(",")]
        return [float(t) if t[0].isdigit() or t[0] == "-" else t for t in items]
    try:
        return float(text)
    except ValueError:
        return text


def test_the_parameters_table_is_whole_and_says_every_default(harness_factory):
    """One table (a paragraph used to split it), one row per declared parameter, and the
    default each row gives is the one the node declares."""
    from wrenchcone_ros.node.parameters import FAST_CHECK_ENV, PARAMETERS

    table = parameters_table()
    assert sorted(table) == sorted(PARAMETERS)
    node = harness_factory(cli_args=[]).node  # no overrides: the declared defaults
    for name, (type_, default) in table.items():
        if name == "fast_check" and os.environ.get(FAST_CHECK_ENV):
            continue  # its default comes from the environment (documented in its row)
        if default == "unset":
            assert not node.has_parameter(name) or node.get_parameter_or(name).type_ == \
                Parameter.Type.NOT_SET, name
            continue
        param = node.get_parameter(name)
        value = param.value
        value = list(value) if isinstance(value, (list, tuple)) or hasattr(value, "tolist") \
            else value
        assert documented_value(default) == value, (name, default, value)
        assert type_.split("[")[0] in ("string", "double", "int", "bool"), (name, type_)
