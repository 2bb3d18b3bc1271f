# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A second shell: a clean environment (only HOME and PATH=/usr/bin:/bin) that does the
documented sourcing, ``source install/setup.bash``, and nothing else, then runs what the
docs run there: ``python`` with rclpy, the ``wrenchcone`` CLI, ``wrenchcone replay``, the
node program on a scene file answered by the command-line client, ``tray_sim`` and
``tilt_controller``. Before, that shell's ``python`` had no rclpy and none of the programs
was on PATH.

The install tree is the one this run imports the interfaces from (the Makefile's
install/, or the plain workspace of ``make colcon-test``). Besides HOME and PATH the
shell gets only this test's leased ROS domain with localhost discovery (isolation from
other runs) and, when set, WRENCHCONE_ENGINE.
"""

from __future__ import annotations

import json
import os
import shlex
import signal
import subprocess
import threading
from pathlib import Path

import pytest

from wrenchcone_ros.testing.domains import lease_domain

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "paper_disc.yaml"
TIMEOUT_S = 300.0


def install_setup() -> Path:
    """``setup.bash`` of the colcon install tree of wrenchcone_ros on AMENT_PREFIX_PATH."""
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix and (Path(prefix) / "share" / "wrenchcone_ros" / "package.xml").exists():
            for setup in (Path(prefix) / "setup.bash", Path(prefix).parent / "setup.bash"):
                if setup.exists():  # merged install, else isolated (colcon's default)
                    return setup
    pytest.fail("no colcon install of wrenchcone_ros on AMENT_PREFIX_PATH: colcon build "
                "(make build), then source install/setup.bash")


@pytest.fixture(scope="module")
def shell_env():
    with lease_domain() as lease:
        env = {"HOME": os.environ.get("HOME", "/root"), "PATH": "/usr/bin:/bin",
               "ROS_DOMAIN_ID": str(lease.domain_id),
               "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}
        if "WRENCHCONE_ENGINE" in os.environ:
            env["WRENCHCONE_ENGINE"] = os.environ["WRENCHCONE_ENGINE"]
        else:
            # numba caches each compiled kernel function per source path: the install
            # tree's are compiled on their first use, each in the node's first call that
            # needs it (the classification's took longer than the controller's 10 s call
            # in a fresh clone). These tests check the shell, not the kernel: the
            # reference engine, as colcon test runs them.
            env["WRENCHCONE_ENGINE"] = "numpy"
        yield env


def in_second_shell(command: str) -> list[str]:
    """``bash -c`` that sources the install tree, then runs ``command``."""
    return ["bash", "-c", f"source {shlex.quote(str(install_setup()))} && {command}"]


def run(command: str, env: dict, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(in_second_shell(command), env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=TIMEOUT_S, check=False)


@pytest.mark.slow
def test_python_there_has_rclpy_and_the_interfaces(shell_env, tmp_path):
    out = run("python -c 'import rclpy, wrenchcone_msgs.srv, wrenchcone_ros.node; "
              "print(rclpy.__name__)'", shell_env, tmp_path)
    assert out.returncode == 0 and out.stdout.strip() == "rclpy", out.stderr


@pytest.mark.slow
def test_the_cli_and_replay_are_on_path(shell_env, tmp_path):
    from wrenchcone_ros import __version__

    out = run("wrenchcone --version", shell_env, tmp_path)
    assert (out.returncode, out.stdout.strip()) == (0, f"wrenchcone {__version__}"), out.stderr
    out = run("wrenchcone replay --help", shell_env, tmp_path)
    assert out.returncode == 0 and out.stdout.startswith("usage: wrenchcone replay"), out.stderr


@pytest.mark.slow
def test_the_programs_are_on_path(shell_env, tmp_path):
    out = run("command -v wrenchcone wrenchcone_node tray_sim tilt_controller", shell_env,
              tmp_path)
    assert out.returncode == 0 and len(out.stdout.split()) == 4, out.stdout + out.stderr
    out = run("tray_sim", shell_env, tmp_path)  # runs, and refuses to start without a scene
    assert out.returncode == 2 and "scene_file is required" in out.stderr, out.stderr


class Program:
    """A command of the second shell running in the background; its stderr collected."""

    def __init__(self, command: str, env: dict, cwd: Path, until: str) -> None:
        self.proc = subprocess.Popen(in_second_shell(f"exec {command}"), env=env, cwd=cwd,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True)
        self.lines: list[str] = []
        self.until = until
        self.seen = threading.Event()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        for line in self.proc.stderr:
            self.lines.append(line)
            if self.until in line:
                self.seen.set()
        self.seen.set()  # ended

    def wait_for(self, timeout: float = TIMEOUT_S) -> bool:
        """True once ``until`` was logged, False when the program ended without it."""
        return self.seen.wait(timeout) and any(self.until in line for line in self.lines)

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            code = self.proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            code = self.proc.wait()
        self.reader.join(timeout=10)
        return code

    @property
    def log(self) -> str:
        return "".join(self.lines[-40:])


@pytest.mark.slow
def test_the_node_there_answers_the_client_of_another(shell_env, tmp_path):
    node = Program(f"wrenchcone_node --ros-args -p scene_file:={SCENE}", shell_env, tmp_path,
                   until="ready:")
    try:
        assert node.wait_for() and node.proc.poll() is None, node.log
        out = run("python -m wrenchcone_ros.ros.client check na 0.1 -1 0 --timeout 60",
                  shell_env, tmp_path)
        assert out.returncode == 0, out.stdout + out.stderr
        reply = json.loads(out.stdout)
        assert reply["status"] == "OK" and reply["consistent"] is True, reply
    finally:
        code = node.stop()
    assert code == 0, node.log


def closed_loop_commands() -> list[str]:
    """The three commands of docs/closed_loop.md, section 1, as the page shows them."""
    text = (ROOT / "docs" / "closed_loop.md").read_text()
    section = text.split("## 1.", 1)[1].split("\n## ", 1)[0]
    block = next([line.strip() for line in chunk.splitlines()]
                 for chunk in section.split("\n\n")
                 if all(line.startswith("    ") for line in chunk.splitlines()))
    assert all(line.startswith(("wrenchcone_node", "tray_sim", "tilt_controller", "-p"))
               for line in block), block
    return _commands(block)


def _commands(lines: list[str]) -> list[str]:
    out: list[str] = []
    continued = False
    for line in lines:
        text = line.removesuffix("\\").strip()
        if continued:
            out[-1] += " " + text
        else:
            out.append(text)
        continued = line.endswith("\\")
    return out


@pytest.mark.slow
def test_the_closed_loop_of_the_docs_runs_as_written(shell_env):
    """The node, tray_sim and tilt_controller with the commands of docs/closed_loop.md
    section 1, each in a second shell, in lockstep as the page says (``-p
    lockstep:=true`` added to tray_sim and tilt_controller): the controller seats the
    pawl."""
    node_cmd, tray_cmd, controller_cmd = closed_loop_commands()
    assert node_cmd.startswith("wrenchcone_node ") and tray_cmd.startswith("tray_sim ") \
        and controller_cmd.startswith("tilt_controller "), (node_cmd, tray_cmd, controller_cmd)
    lockstep = " -p lockstep:=true"
    programs = [Program(node_cmd, shell_env, ROOT, until="ready:")]
    try:
        assert programs[0].wait_for(), programs[0].log
        programs.append(Program(tray_cmd + lockstep, shell_env, ROOT, until="\n"))  # not waited for
        programs.append(Program(controller_cmd + lockstep, shell_env, ROOT, until="SEATED"))
        assert programs[-1].wait_for(), "\n".join(p.log for p in programs)
    finally:
        codes = [p.stop() for p in reversed(programs)]
    assert codes == [0] * len(programs), (codes, "\n".join(p.log for p in programs))


@pytest.mark.slow
def test_pytest_there_has_the_kit_without_a_flag(shell_env, tmp_path):
    """The colcon install tree holds the distribution's metadata with the pytest11 entry
    point; before, a colcon install had none and the plugin needed ``-p``."""
    prefix = str(install_setup().parent / "wrenchcone_ros")
    out = run("python -c 'import importlib.metadata as m; print(*(d.locate_file(\"\") "
              "for d in m.distributions() if d.metadata[\"Name\"] == \"wrenchcone_ros\" "
              "and any(e.group == \"pytest11\" for e in d.entry_points)), sep=\"\\n\")'",
              shell_env, tmp_path)
    assert out.returncode == 0, out.stderr
    assert any(line.startswith(prefix) for line in out.stdout.splitlines()), out.stdout
    out = run("pytest --fixtures -p no:cacheprovider", shell_env, tmp_path)
    assert "INTERNALERROR" not in out.stdout + out.stderr, out.stdout[-3000:] + out.stderr
    listed = {line.split()[0] for line in out.stdout.splitlines() if line[:1].isalpha()}
    assert {"wrenchcone_node", "wrenchcone_client", "wrenchcone_spin",
            "wrenchcone_client_module", "wrenchcone_client_session"} <= listed, out.stdout
