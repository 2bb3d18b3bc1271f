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
