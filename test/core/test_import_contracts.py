# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The import contracts of pyproject.toml ([tool.importlinter], run by `make lint`) hold,
and they catch what they are for: an import that goes up the core's layers, a cycle
made by an import inside a function, ROS (or a generated ROS interface) in the core."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LINT = Path(sys.executable).parent / "lint-imports"

pytestmark = pytest.mark.skipif(not LINT.exists(), reason="import-linter not installed")


def lint(where: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(LINT), "--no-cache"], cwd=where, capture_output=True,
                          text=True, timeout=300)


def _copy(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "wrenchcone_ros" / "wrenchcone_ros", tmp_path / "wrenchcone_ros",
                    ignore=shutil.ignore_patterns("__pycache__", "*.so", "*.nb[ic]"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    return tmp_path


def _append(path: Path, text: str) -> None:
    path.write_text(path.read_text() + text)


@pytest.mark.slow
def test_the_contracts_hold():
    out = lint(ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "BROKEN" not in out.stdout and "0 broken" in out.stdout


@pytest.mark.slow
@pytest.mark.parametrize("module, body, needle", [
    # a cycle through an import inside a function (the kind the layers had before)
    ("core.batch", "def _late():\n    from .classify import only_mode\n    return only_mode\n",
     "wrenchcone_ros.core.batch -> wrenchcone_ros.core.classify"),
    # the environment is read in one place (core/engines/registry.py)
    ("core.scene", "def _env():\n    import os\n    return os.environ.get('X')\n",
     "wrenchcone_ros.core.scene -> os"),
    # the compiled kernel is the engine module's alone
    ("core.robust", "def _late():\n    from . import kernel\n    return kernel\n",
     "wrenchcone_ros.core.robust -> wrenchcone_ros.core.kernel"),
    ("core.scene", "def _late():\n    from . import batch\n    return batch\n",
     "wrenchcone_ros.core.scene -> wrenchcone_ros.core.batch"),
    ("core.directions", "def _ros():\n    import rclpy\n    return rclpy\n", "rclpy"),
    ("core.batch", "def _srv():\n    from wrenchcone_msgs.srv import CheckWrench\n    return CheckWrench\n",
     "wrenchcone_ros.core.batch -> wrenchcone_msgs"),
    ("core.plot", "def _cli():\n    from ..cli import main\n    return main\n",
     "wrenchcone_ros.core.plot -> wrenchcone_ros.cli"),
    # the ROS side too: a cycle between two modules of the node
    ("node.freshness", "def _late():\n    from wrenchcone_ros.node import worker\n    return worker\n",
     ".freshness -> .worker"),
])
def test_a_new_upward_import_or_cycle_breaks_a_contract(tmp_path, module, body, needle):
    where = _copy(tmp_path)
    _append(where / "wrenchcone_ros" / f"{module.replace('.', '/')}.py", "\n\n" + body)
    out = lint(where)
    assert out.returncode != 0 and "BROKEN" in out.stdout, out.stdout + out.stderr
    # a cycle is reported by one of its edges, either way round
    a, _, b = needle.partition(" -> ")
    assert needle in out.stdout or (b and f"{b} -> {a}" in out.stdout), out.stdout


@pytest.mark.slow
def test_a_core_module_without_a_layer_breaks_the_layers_contract(tmp_path):
    where = _copy(tmp_path)
    (where / "wrenchcone_ros" / "core" / "orphan.py").write_text('"""No layer."""\n')
    out = lint(where)
    assert out.returncode != 0 and "orphan" in out.stdout, out.stdout + out.stderr
