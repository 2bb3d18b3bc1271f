# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""docs/testing.md shows the kit as it is: the example file CI runs, every fixture."""

from __future__ import annotations

import ast

from helpers.docs_examples import ROOT, blocks

DOC = ROOT / "docs" / "testing.md"
EXAMPLE = ROOT / "test" / "ros" / "test_testing_kit_example.py"
PLUGIN = ROOT / "wrenchcone_ros" / "wrenchcone_ros" / "testing" / "plugin.py"
LICENCE_LINES = 2  # the file's copyright header, which the page leaves out


def test_the_worked_example_is_the_file_ci_runs():
    (example,) = [b for b in blocks(DOC) if b.lang == "python"]
    assert example.text == EXAMPLE.read_text().split("\n", LICENCE_LINES)[LICENCE_LINES], (
        f"{DOC.name}:{example.line}: the python block differs from {EXAMPLE.name}; paste "
        "the file (without its licence lines) into the page")


def test_every_fixture_of_the_plugin_is_documented():
    tree = ast.parse(PLUGIN.read_text())
    fixtures = [f.name for f in tree.body if isinstance(f, ast.FunctionDef)
                and any("fixture" in ast.unparse(d) for d in f.decorator_list)]
    assert len(fixtures) >= 8, fixtures
    text = DOC.read_text()
    assert [f for f in fixtures if f"| `{f}` |" not in text] == []
