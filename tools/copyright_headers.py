# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Check or add the copyright and licence header of the repository's source files.

Every Python file, C source, CMake file and the Makefile starts with (after a ``#!``
line, if any)::

    # Copyright 2026 wrenchcone_ros developers
    # SPDX-License-Identifier: MIT

in the file's comment syntax (``//`` in C). The year is the year the header was added;
a header with another year is accepted.

Usage::

    python tools/copyright_headers.py --check [PATH ...]   # list the files without it
    python tools/copyright_headers.py --fix [PATH ...]     # add it where missing

Without PATH: every covered file of the repository (``git ls-files``: tracked and new
files not ignored; a directory walk outside a git checkout). Exit status 1 when
``--check`` finds a file without the header.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OWNER = "wrenchcone_ros developers"
YEAR = 2026
#: Comment prefix by file suffix (or whole name).
PREFIXES = {".py": "#", ".cmake": "#", "CMakeLists.txt": "#", "Makefile": "#", ".sh": "#",
            ".c": "//", ".h": "//"}
#: Directories never scanned (build products, the venv, third-party trees).
SKIP_DIRS = {".git", ".venv", "build", "install", "log", "build-colcon-test",
             "install-colcon-test", "__pycache__"}
#: Lines a header may follow: a ``#!`` line, a coding line.
PREAMBLE = re.compile(r"#!.*|#.*coding[:=].*")
COPYRIGHT = re.compile(r"(#|//) Copyright \d{4}(-\d{4})? " + re.escape(OWNER) + r"\s*$")
SPDX = re.compile(r"(#|//) SPDX-License-Identifier: MIT\s*$")


def prefix_of(path: Path) -> str | None:
    """The comment prefix of a covered file, None for a file the header is not for."""
    return PREFIXES.get(path.name) or PREFIXES.get(path.suffix)


def covered_files(root: Path = ROOT) -> list[Path]:
    """Every covered file of the repository, sorted."""
    try:
        out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"],
                             cwd=root, capture_output=True, text=True, check=True).stdout
        paths = [root / line for line in out.splitlines()]
    except (OSError, subprocess.CalledProcessError):
        paths = [p for p in root.rglob("*") if not SKIP_DIRS & set(p.relative_to(root).parts)]
    return sorted(p for p in paths
                  if p.is_file() and not p.is_symlink() and prefix_of(p)
                  and not SKIP_DIRS & set(p.relative_to(root).parts))


def _split(text: str) -> tuple[list[str], list[str]]:
    lines = text.splitlines(keepends=True)
    n = 0
    while n < len(lines) and n < 2 and PREAMBLE.fullmatch(lines[n].rstrip("\n")):
        n += 1
    return lines[:n], lines[n:]


def has_header(path: Path) -> bool:
    """Whether the file's first lines (after a preamble) are the two header lines."""
    _, body = _split(path.read_text())
    return (len(body) >= 2 and bool(COPYRIGHT.match(body[0]))
            and bool(SPDX.match(body[1])))


def add_header(path: Path) -> bool:
    """Add the header where it is missing; True if the file changed."""
    if has_header(path):
        return False
    prefix = prefix_of(path)
    head, body = _split(path.read_text())
    header = [f"{prefix} Copyright {YEAR} {OWNER}\n", f"{prefix} SPDX-License-Identifier: MIT\n"]
    if head and not head[-1].endswith("\n"):
        head[-1] += "\n"
    path.write_text("".join(head + header + body))
    return True


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true", help="list the files without it")
    mode.add_argument("--fix", action="store_true", help="add it where it is missing")
    parser.add_argument("paths", nargs="*", type=Path,
                        help="files (default: every covered file of the repository)")
    args = parser.parse_args(argv)
    paths = [p.resolve() for p in args.paths] or covered_files()
    unknown = [p for p in paths if not p.is_file() or not prefix_of(p)]
    if unknown:
        parser.error("not a covered source file: " + ", ".join(map(str, unknown)))
    if args.fix:
        changed = [p for p in paths if add_header(p)]
        for p in changed:
            print(f"added: {_shown(p)}")
        print(f"copyright_headers: {len(changed)} file(s) changed, {len(paths)} checked")
        return 0
    missing = [p for p in paths if not has_header(p)]
    for p in missing:
        print(_shown(p))
    print(f"copyright_headers: {len(missing)} of {len(paths)} file(s) lack the header"
          + (" (add it: python tools/copyright_headers.py --fix PATH ...)" if missing else ""),
          file=sys.stderr)
    return 1 if missing else 0


def _shown(path: Path) -> str:
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


if __name__ == "__main__":
    sys.exit(main())
