# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""tools/pip_install.py: uv gets the settings pip would use (read from pip itself, here
set through PIP_* variables and a config file of this test's own), and a forced pip
install installs what was asked."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import zipfile
from pathlib import Path

TOOL = Path(__file__).resolve().parents[2] / "tools" / "pip_install.py"
spec = importlib.util.spec_from_file_location("pip_install", TOOL)
pip_install = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pip_install)


def test_pips_settings_become_uvs(tmp_path, monkeypatch):
    constraints = tmp_path / "constraints.txt"
    constraints.write_text("torch<=2.14.1\n")
    conf = tmp_path / "pip.conf"
    conf.write_text(f"[global]\nindex-url = https://index.example/simple\n"
                    f"extra-index-url = file:///a/simple file:///b/simple\n"
                    f"constraint = {constraints}\ntrusted-host = index.example\n")
    monkeypatch.setenv("PIP_CONFIG_FILE", str(conf))
    monkeypatch.setenv("PIP_FIND_LINKS", "/wheels")
    monkeypatch.setenv("PIP_CERT", "/etc/ssl/certs/ca.crt")
    monkeypatch.setenv("PIP_DEFAULT_TIMEOUT", "180")
    cfg = pip_install.pip_config(sys.executable)
    args, env = pip_install.uv_arguments(cfg)
    assert args == ["--index-strategy", "unsafe-best-match",
                    "--index-url", "https://index.example/simple",
                    "--extra-index-url", "file:///a/simple",
                    "--extra-index-url", "file:///b/simple",
                    "--find-links", "/wheels",
                    "--constraint", str(constraints),
                    "--allow-insecure-host", "index.example"]
    assert env == {"SSL_CERT_FILE": "/etc/ssl/certs/ca.crt", "UV_HTTP_TIMEOUT": "180"}


def test_the_environment_wins_over_the_config_file(tmp_path, monkeypatch):
    conf = tmp_path / "pip.conf"
    conf.write_text("[global]\nfind-links = /from/file\n")
    monkeypatch.setenv("PIP_CONFIG_FILE", str(conf))
    monkeypatch.setenv("PIP_FIND_LINKS", "/from/env")
    assert pip_install.pip_config(sys.executable)["find-links"] == "/from/env"


def _wheel(where: Path) -> Path:
    """A minimal wheel of a package ``tinypkg`` (a zip file: the module and its
    dist-info)."""
    path = where / "tinypkg-1.0-py3-none-any.whl"
    files = {"tinypkg/__init__.py": "VALUE = 7\n",
             "tinypkg-1.0.dist-info/METADATA": "Metadata-Version: 2.1\nName: tinypkg\n"
                                               "Version: 1.0\n",
             "tinypkg-1.0.dist-info/WHEEL": "Wheel-Version: 1.0\nGenerator: test\n"
                                            "Root-Is-Purelib: true\nTag: py3-none-any\n"}
    files["tinypkg-1.0.dist-info/RECORD"] = "".join(f"{k},,\n" for k in files) + \
        "tinypkg-1.0.dist-info/RECORD,,\n"
    with zipfile.ZipFile(path, "w") as z:
        for name, text in files.items():
            z.writestr(name, text)
    return path


def test_forced_pip_installs_the_requirements(tmp_path):
    """WRENCHCONE_PIP=pip: pip installs a requirement file (a local wheel of this test's
    own, no index) into a fresh venv, and says so."""
    req = tmp_path / "req.txt"
    req.write_text(f"{_wheel(tmp_path)}\n")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = str(venv / "bin" / "python")
    done = subprocess.run([py, str(TOOL), "--no-index", "-r", str(req)],
                          capture_output=True, text=True,
                          env={"PATH": "/usr/bin:/bin", "WRENCHCONE_PIP": "pip"})
    assert done.returncode == 0, done.stderr
    assert "pip_install: WRENCHCONE_PIP=pip; installing with pip" in done.stdout
    got = subprocess.run([py, "-c", "import tinypkg; print(tinypkg.VALUE)"],
                         capture_output=True, text=True, cwd=tmp_path)
    assert got.stdout.strip() == "7", got.stderr
