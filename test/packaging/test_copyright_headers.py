# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Every source file carries the copyright and SPDX header (tools/copyright_headers.py).

ament_copyright has no wheel, so the repository's own script checks the header; the
test also shows that the script tells a file without it apart and that --fix adds it
after a ``#!`` line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TOOL = ROOT / "tools" / "copyright_headers.py"


def _run(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(TOOL), *args], cwd=cwd,
                          capture_output=True, text=True, timeout=60)


def test_every_source_file_has_the_header():
    out = _run("--check")
    assert out.returncode == 0, (
        "files without the copyright header (python tools/copyright_headers.py --fix "
        "PATH ...):\n" + out.stdout)
    assert "0 of " in out.stderr and int(out.stderr.split(" of ")[1].split()[0]) > 100


def test_check_and_fix_on_files_without_it(tmp_path):
    script = tmp_path / "tool.py"
    script.write_text('#!/usr/bin/env python3\n"""A tool."""\nprint("hi")\n')
    source = tmp_path / "lane.c"
    source.write_text("#include <stdio.h>\n")
    out = _run("--check", str(script), str(source))
    assert out.returncode == 1 and out.stdout.split() == [str(script), str(source)]
    assert _run("--fix", str(script), str(source)).returncode == 0
    assert script.read_text() == (
        "#!/usr/bin/env python3\n# Copyright 2026 wrenchcone_ros developers\n"
        '# SPDX-License-Identifier: MIT\n"""A tool."""\nprint("hi")\n')
    assert source.read_text().startswith(
        "// Copyright 2026 wrenchcone_ros developers\n// SPDX-License-Identifier: MIT\n#incl")
    assert _run("--check", str(script), str(source)).returncode == 0
    assert _run("--fix", str(script)).stdout.startswith("copyright_headers: 0 file(s) changed")
    # the script still runs, the header is a comment
    assert subprocess.run([sys.executable, str(script)], capture_output=True,
                          text=True).stdout == "hi\n"
