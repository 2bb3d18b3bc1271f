# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Build-time helper of CMakeLists.txt (run by the interpreter the package is built for).

``dist-info SETUP_PY OUT_DIR``
    Writes ``wrenchcone_ros-<version>.dist-info/`` (METADATA, entry_points.txt,
    top_level.txt, INSTALLER) into OUT_DIR from setup.py's ``entry_points`` and the
    version of ``wrenchcone_ros/_version.py``, and prints the console scripts as a CMake
    list of ``name=module:function``. Installed beside the package, it makes the
    distribution and its entry points (the pytest plugin, the programs) visible to
    ``importlib.metadata`` on a colcon install tree, as ``pip install`` would.
``scripts-dir``
    Prints the directory of this interpreter's programs (``python``, ``pip``, a venv's
    console scripts) when it is not the system's own interpreter (a venv, conda, a
    Python built into a prefix of its own), else nothing: the directory the
    environment hook puts on PATH.

setup.py is read, not run: this needs no setuptools.
"""

from __future__ import annotations

import ast
import configparser
import io
import os
import re
import sys
import sysconfig
from pathlib import Path

NAME = "wrenchcone_ros"
SYSTEM_PREFIXES = {"/usr", "/usr/local", "/"}


def setup_keywords(setup_py: Path) -> dict:
    """The literal keyword arguments of setup.py's ``setup(...)`` call."""
    tree = ast.parse(setup_py.read_text(), str(setup_py))
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "setup":
            out = {}
            for kw in node.keywords:
                try:
                    out[kw.arg] = ast.literal_eval(kw.value)
                except ValueError:
                    pass  # not a literal (the version, the packages): read elsewhere
            return out
    raise SystemExit(f"{setup_py}: no setup(...) call")


def version(package_dir: Path) -> str:
    text = (package_dir / NAME / "_version.py").read_text()
    return re.search(r'^__version__ = "([^"]+)"$', text, re.M).group(1)


def write_dist_info(setup_py: Path, out_dir: Path) -> list[str]:
    kw = setup_keywords(setup_py)
    ver = version(setup_py.parent)
    dist = out_dir / f"{NAME}-{ver}.dist-info"
    dist.mkdir(parents=True, exist_ok=True)
    for old in out_dir.glob(f"{NAME}-*.dist-info"):  # an earlier version's
        if old != dist:
            for f in old.iterdir():
                f.unlink()
            old.rmdir()
    meta = ["Metadata-Version: 2.1", f"Name: {NAME}", f"Version: {ver}"]
    if kw.get("description"):
        meta.append(f"Summary: {kw['description']}")
    if kw.get("python_requires"):
        meta.append(f"Requires-Python: {kw['python_requires']}")
    # no Requires-Dist: a colcon install's dependencies are package.xml's (rosdep's)
    parser = configparser.ConfigParser(delimiters=("=",), interpolation=None)
    parser.optionxform = str  # keep the names' case
    for group, entries in kw.get("entry_points", {}).items():
        parser[group] = dict(e.replace(" ", "").split("=", 1) for e in entries)
    text = io.StringIO()
    parser.write(text)
    files = {"METADATA": "\n".join(meta) + "\n", "entry_points.txt": text.getvalue(),
             "top_level.txt": NAME + "\n", "INSTALLER": "colcon\n"}
    for name, content in files.items():
        path = dist / name
        if not path.exists() or path.read_text() != content:  # no rebuild for nothing
            path.write_text(content)
    return [e.replace(" ", "") for e in kw.get("entry_points", {}).get("console_scripts", [])]


def scripts_dir() -> str:
    """This interpreter's scripts directory, or "" for the system's interpreter."""
    system = (sys.prefix == sys.base_prefix
              and os.path.realpath(sys.base_prefix) in SYSTEM_PREFIXES)
    return "" if system else sysconfig.get_path("scripts")


def main(argv: list[str]) -> None:
    if argv[:1] == ["dist-info"] and len(argv) == 3:
        print(";".join(write_dist_info(Path(argv[1]), Path(argv[2]))), end="")
    elif argv == ["scripts-dir"]:
        print(scripts_dir(), end="")
    else:
        raise SystemExit("usage: install_metadata.py dist-info SETUP_PY OUT_DIR | scripts-dir")


if __name__ == "__main__":
    main(sys.argv[1:])
