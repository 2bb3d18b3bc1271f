# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The public API of ``wrenchcone_ros.core`` (core/__init__.py) is what the docs use:
every name the README and docs/ import from the core is exported by the package, the
docs import it from the package (not from the submodule that defines it), and the
planner and the simulation are imported only on first use."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

import wrenchcone_ros.core as core
from helpers.docs_examples import ROOT

_IMPORT = re.compile(r"from (wrenchcone_ros\.core(?:\.[a-z_0-9.]+)?) import \(?([A-Za-z_0-9, \n.>]+)\)?")


def doc_imports() -> list[tuple[str, str, str]]:
    """(file, module, name) for every ``from wrenchcone_ros.core[...] import name`` in the
    README and docs/*.md (pycon continuation prompts ``...`` removed)."""
    out = []
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = path.read_text().replace("\n... ", "\n")
        for m in _IMPORT.finditer(text):
            names = [n.strip() for n in m.group(2).replace(">>>", "").split(",")]
            out += [(path.name, m.group(1), n) for n in names if n.isidentifier()]
    return out


def test_the_docs_import_from_the_core():
    assert len(doc_imports()) > 20  # the regex finds the docs' imports


@pytest.mark.parametrize("file, module, name", sorted(set(doc_imports())))
def test_every_name_the_docs_use_is_exported_and_imported_from_the_package(file, module, name):
    if module == "wrenchcone_ros.core":
        assert name in core.__all__, f"{file}: {name} is not exported by wrenchcone_ros.core"
    else:
        assert name not in core.__all__, \
            f"{file}: import {name} from wrenchcone_ros.core, not from {module}"


def test_every_exported_name_is_the_defining_modules_object():
    """``__all__`` names exist, and each is the object of the submodule that defines it
    (one object, not a copy: ``isinstance`` and identity hold across both routes)."""
    import importlib

    for name in core.__all__:
        value = getattr(core, name)
        home = getattr(value, "__module__", None)
        if home and home.startswith("wrenchcone_ros.core."):
            assert getattr(importlib.import_module(home), name, value) is value, name


@pytest.mark.slow
def test_the_planner_is_imported_on_first_use():
    """``import wrenchcone_ros.core`` does not import the planner nor the simulation; the
    first use of ``plan_seating`` does, and an unknown name is an AttributeError."""
    code = (
        "import sys, wrenchcone_ros.core as c\n"
        "mods = ('wrenchcone_ros.core.plan', 'wrenchcone_ros.core.simulate')\n"
        "assert not any(m in sys.modules for m in mods), [m for m in mods if m in sys.modules]\n"
        "from wrenchcone_ros.core import plan_seating, Actuator\n"
        "assert all(m in sys.modules for m in mods)\n"
        "assert plan_seating.__module__ == 'wrenchcone_ros.core.plan.search'\n"
        "assert 'plan_seating' in dir(c)\n"
        "try:\n    c.no_such_name\nexcept AttributeError as e:\n    print(e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "has no attribute 'no_such_name'" in out.stdout
