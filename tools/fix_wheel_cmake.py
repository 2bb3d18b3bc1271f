# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Point the ROS wheels' exported CMake files at this interpreter's include dirs.

The ros-jazzy-* wheels are built on a manylinux image; their exported CMake files name
that machine's Python and numpy include directories, so generating interfaces fails with
"includes non-existent path". Rewrite both paths in PREFIX/share/**/*.cmake (idempotent).

Usage: python tools/fix_wheel_cmake.py PREFIX
"""

import pathlib
import re
import sys
import sysconfig

import numpy


def main(prefix: str) -> int:
    py_inc = sysconfig.get_paths()["include"]
    np_inc = numpy.get_include()
    pattern = re.compile(
        r"/opt/python/cp3\d+-cp3\d+/(?:include/python3\.\d+"
        r"|lib/python3\.\d+/site-packages/numpy/(?:_core|core)/include)"
    )

    def repl(m: re.Match) -> str:
        return np_inc if "numpy" in m.group(0) else py_inc

    changed = 0
    for path in pathlib.Path(prefix, "share").rglob("*.cmake"):
        text = path.read_text()
        new = pattern.sub(repl, text)
        if new != text:
            path.write_text(new)
            changed += 1
    print(f"fix_wheel_cmake: rewrote {changed} file(s) to {py_inc} and {np_inc}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else sys.prefix))
