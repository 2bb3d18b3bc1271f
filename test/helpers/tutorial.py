# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A tutorial's examples, extracted and run: ``$ wrenchcone ...`` lines of its ```console
blocks through ``wrenchcone_ros.cli.main`` (the code behind the ``wrenchcone`` script),
its ```pycon blocks as doctests; and the text with its outputs regenerated."""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex

from helpers.docs_examples import ROOT

FENCE = re.compile(r"```(console|pycon)\n(.*?)```", re.S)


def run_command(line: str) -> str:
    from wrenchcone_ros import cli

    argv = shlex.split(line)
    assert argv[0] == "wrenchcone", line
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = cli.main(argv[1:])
    assert code == 0, line
    return buf.getvalue()


def console_cases(text: str):
    """(command, expected output) for every ``$ wrenchcone`` line."""
    for m in FENCE.finditer(text):
        if m.group(1) != "console":
            continue
        cmd, out = None, []
        for line in m.group(2).splitlines():
            if line.startswith("$ "):
                if cmd:
                    yield cmd, "\n".join(out)
                cmd, out = line[2:], []
            else:
                out.append(line)
        if cmd:
            yield cmd, "\n".join(out)


def pycon_blocks(text: str):
    return [m.group(2) for m in FENCE.finditer(text) if m.group(1) == "pycon"]


@contextlib.contextmanager
def in_root():
    old = os.getcwd()
    os.chdir(ROOT)
    try:
        yield
    finally:
        os.chdir(old)


# --- regenerating the outputs ---------------------------------------------------------------
def update(text: str) -> str:
    """The text with every console block's outputs and every pycon block's results
    replaced by what the code prints now (run in the working directory)."""
    def console(m):
        lines, body = [], m.group(2).splitlines()
        for line in body:
            if line.startswith("$ "):
                lines.append(line)
                lines += run_command(line[2:]).rstrip("\n").splitlines()
        return "```console\n" + "\n".join(lines) + "\n```"

    def pycon(m):
        import code

        interp = code.InteractiveInterpreter({})
        lines, src = [], []
        for line in m.group(2).splitlines():
            if line.startswith(">>> ") or line.startswith("... "):
                src.append(line)
        stmts, cur = [], []
        for line in src:
            if line.startswith(">>> ") and cur:
                stmts.append(cur)
                cur = []
            cur.append(line)
        if cur:
            stmts.append(cur)
        for st in stmts:
            lines += st
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                interp.runsource("\n".join(s[4:] for s in st) + "\n", symbol="single")
            lines += buf.getvalue().rstrip("\n").splitlines()
        return "```pycon\n" + "\n".join(lines) + "\n```"

    def both(m):
        return console(m) if m.group(1) == "console" else pycon(m)

    return FENCE.sub(both, text)
