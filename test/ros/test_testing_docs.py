# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""docs/testing.md shows the kit as it is: the example file CI runs, every fixture."""

from __future__ import annotations

import inspect
import re

from helpers.docs_examples import ROOT, blocks

DOC = ROOT / "docs" / "testing.md"
EXAMPLE = ROOT / "test" / "ros" / "test_testing_kit_example.py"
LICENCE_LINES = 2  # the file's copyright header, which the page leaves out


def test_the_worked_example_is_the_file_ci_runs():
    (example,) = [b for b in blocks(DOC) if b.lang == "python"]
    assert example.text == EXAMPLE.read_text().split("\n", LICENCE_LINES)[LICENCE_LINES], (
        f"{DOC.name}:{example.line}: the python block differs from {EXAMPLE.name}; paste "
        "the file (without its licence lines) into the page")


def table_rows() -> dict[str, tuple[str, str]]:
    """The fixture table of the page: name -> (scope, what the test gets)."""
    rows = {}
    for line in DOC.read_text().splitlines():
        match = re.fullmatch(r"\| `(\w+)` \| (\w+) \| (.*) \|", line)
        if match:
            rows[match[1]] = (match[2], match[3])
    return rows


def call_signature(function) -> str:
    """``(a=None, *, b=None)``: no annotations, no ``self``, as the page writes it."""
    sig = inspect.signature(function)
    params = [p.replace(annotation=inspect.Parameter.empty)
              for p in sig.parameters.values() if p.name != "self"]
    return str(sig.replace(parameters=params, return_annotation=inspect.Signature.empty))


def test_the_fixture_table_is_what_the_plugin_registers(request):
    """Every fixture the plugin registers is a row with its scope, and no row is
    something else; a fixture that yields a callable shows its call signature. Before,
    the factory's row said ``make(...)`` for a fixture that is itself the callable."""
    from wrenchcone_ros.testing import plugin
    from wrenchcone_ros.testing.harness import NodeFactory, Spinner

    # pytest's own registry (what `pytest --fixtures` lists), not the plugin's source
    registered = {d.argname: d.scope
                  for d in request.session._fixturemanager._get_all_fixture_defs()
                  if getattr(d.func, "__module__", "") == plugin.__name__}
    rows = table_rows()
    assert {name: scope for name, (scope, _) in rows.items()} == registered
    callables = {"wrenchcone_node_factory": NodeFactory.make,
                 "wrenchcone_spin": Spinner.__call__}
    for name, (_scope, text) in rows.items():
        shown = re.match(rf"`{name}(\(.*?\))`", text)
        if name in callables:
            assert shown, f"the row of {name} does not start with its call signature"
            assert shown[1].replace('"', "'") == call_signature(callables[name]), name
        else:
            assert shown is None, f"{name} is not a callable"
