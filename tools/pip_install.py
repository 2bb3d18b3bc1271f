# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Install requirement files into this interpreter's venv with uv when it can, with pip
otherwise; the same packages either way.

    .venv/bin/python tools/pip_install.py -r requirements.txt -r requirements-ros.txt

pip installs the venv's wheels one after another; uv (https://docs.astral.sh/uv/, a
wheel from the package index, installed into the venv first) downloads and unpacks them
in parallel: on a 2-core machine the venv of `make build` takes about half of pip's
time (docs/testing.md quotes the figures). uv does not read pip's configuration, so the
indexes, find-links, constraint files, certificate and timeout that pip would use (its
config files and PIP_* variables, as `pip config list` prints them) are passed on, and
versions are picked across all indexes as pip picks them (the best match). When uv
cannot be installed or fails, pip installs the same files and the reason is printed on
one line. WRENCHCONE_PIP=pip forces pip.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

#: the uv release installed into the venv (a pinned version: the same installer on every
#: machine)
UV_VERSION = "0.13.9"


def pip_config(python: str) -> dict[str, str]:
    """pip's effective settings, ``name -> value`` (environment over config files), from
    ``pip config list``."""
    out = subprocess.run([python, "-m", "pip", "config", "list"], capture_output=True,
                         text=True, check=False).stdout
    found: dict[str, tuple[int, str]] = {}
    for line in out.splitlines():
        key, sep, value = line.partition("=")
        if not sep:
            continue
        scope, _, name = key.rpartition(".")
        if scope not in ("global", "install", ":env:"):
            continue
        rank = {"global": 0, "install": 1, ":env:": 2}[scope]
        if name not in found or rank >= found[name][0]:
            found[name] = (rank, value.strip().strip("'\""))
    return {name: value for name, (_, value) in found.items()}


def uv_arguments(cfg: dict[str, str]) -> tuple[list[str], dict[str, str]]:
    """uv's options and environment that give pip's settings ``cfg``."""
    args = ["--index-strategy", "unsafe-best-match"]
    if cfg.get("index-url"):
        args += ["--index-url", cfg["index-url"]]
    for url in cfg.get("extra-index-url", "").split():
        args += ["--extra-index-url", url]
    for link in cfg.get("find-links", "").split():
        args += ["--find-links", link]
    for path in cfg.get("constraint", "").split():
        if Path(path).exists():
            args += ["--constraint", path]
    for host in cfg.get("trusted-host", "").split():
        args += ["--allow-insecure-host", host]
    env = {}
    if cfg.get("cert"):
        env["SSL_CERT_FILE"] = cfg["cert"]
    if cfg.get("default-timeout") or cfg.get("timeout"):
        env["UV_HTTP_TIMEOUT"] = cfg.get("default-timeout") or cfg["timeout"]
    return args, env


def main(argv: list[str]) -> int:
    python = sys.executable
    pip = [python, "-m", "pip", "--disable-pip-version-check", "install", "-q"]
    uv = Path(python).parent / "uv"
    reason = "WRENCHCONE_PIP=pip" if os.environ.get("WRENCHCONE_PIP") == "pip" else None
    if reason is None and not uv.exists():
        got = subprocess.run([*pip, f"uv=={UV_VERSION}"], capture_output=True, text=True,
                             check=False)
        if got.returncode != 0:
            reason = (f"uv {UV_VERSION} could not be installed from the package index "
                      f"({(got.stderr.strip().splitlines() or ['no message'])[-1]})")
    if reason is None:
        args, env = uv_arguments(pip_config(python))
        done = subprocess.run([str(uv), "pip", "install", "--quiet", "--python", python,
                               *args, *argv], env={**os.environ, **env}, check=False)
        if done.returncode == 0:
            return 0
        reason = f"uv pip install failed (exit status {done.returncode})"
    print(f"pip_install: {reason}; installing with pip", flush=True)
    return subprocess.run([*pip, *argv], check=False).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
