# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Point the ROS wheels' exported CMake files at this interpreter's include dirs.

The ros-jazzy-* wheels are built on a manylinux image; their exported CMake files name
that machine's Python and numpy include directories, so generating interfaces fails with
"includes non-existent path". Rewrite both paths in PREFIX/share/**/*.cmake (idempotent):
any absolute ``.../include/python3.N`` and ``.../site-packages/numpy/(_core|core)/include``
becomes this interpreter's, whichever machine or venv wrote it.

A changed file is written beside the old one and renamed over it, never rewritten in
place: uv installs a wheel's files as hardlinks to its cache, and an in-place write would
change the cache too, so the next venv installed from it would name this venv's numpy.

Then every absolute path in an INTERFACE_INCLUDE_DIRECTORIES of those files must exist;
a missing one is named with its file, and the exit status is 1.

Usage: python tools/fix_wheel_cmake.py PREFIX
"""

import os
import pathlib
import re
import sys
import sysconfig

import numpy

#: an absolute include directory of some Python 3 or of some numpy, inside a quoted
#: CMake list ("a;b")
INCLUDE_PATTERN = re.compile(
    r'(?<=[";])/[^";\s]*?(?:/include/python3\.\d+'
    r"|/site-packages/numpy/(?:_core|core)/include)(?=[\";])")
INTERFACE_PATTERN = re.compile(r'INTERFACE_INCLUDE_DIRECTORIES\s+"([^"]*)"')


def replace_file(path: pathlib.Path, text: str) -> None:
    """Write ``text`` to a new file and rename it over ``path`` (a new inode: a hardlink
    to an installer's cache keeps the old text)."""
    tmp = path.with_name(path.name + ".fix_wheel_cmake.tmp")
    tmp.write_text(text)
    os.chmod(tmp, path.stat().st_mode & 0o7777)
    os.replace(tmp, path)


def missing_includes(text: str) -> list[str]:
    """The absolute INTERFACE_INCLUDE_DIRECTORIES entries of ``text`` that do not exist."""
    return [entry for match in INTERFACE_PATTERN.finditer(text)
            for entry in match.group(1).split(";")
            if entry.startswith("/") and not os.path.isdir(entry)]


def main(prefix: str) -> int:
    py_inc = sysconfig.get_paths()["include"]
    np_inc = numpy.get_include()

    def repl(m: re.Match) -> str:
        return np_inc if "/numpy/" in m.group(0) else py_inc

    changed, missing = 0, []
    for path in sorted(pathlib.Path(prefix, "share").rglob("*.cmake")):
        text = path.read_text()
        new = INCLUDE_PATTERN.sub(repl, text)
        if new != text:
            replace_file(path, new)
            changed += 1
        missing += [f"{path}: {entry}" for entry in missing_includes(new)]
    print(f"fix_wheel_cmake: rewrote {changed} file(s) to {py_inc} and {np_inc}")
    if missing:
        print("fix_wheel_cmake: include directories that do not exist (CMake refuses to "
              "generate with them):\n  " + "\n  ".join(missing), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else sys.prefix))
