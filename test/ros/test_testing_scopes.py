# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The test kit's fixtures for a user's own node (``wrenchcone_spin``), its module- and
session-scoped variants, and what a test module that imports ROS unsourced is told."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import pytest
from rclpy.node import Node

import wrenchcone_ros
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench
from wrenchcone_ros.testing.harness import Spinner

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "examples" / "paper_disc.yaml"
DEADLINE_S = 60.0  # only a guard against a hang; never asserted on
#: The directory the package under test is imported from (the source tree, or an
#: install tree's site-packages), for pytest runs of their own.
PACKAGE_PATH = str(Path(wrenchcone_ros.__file__).resolve().parents[1])


@pytest.fixture(scope="session")
def wrenchcone_scene():
    return DISC  # session scope: the session variants below use it too


class Controller(Node):
    """A minimal controller: asks check_wrench from a timer until it has an answer."""

    def __init__(self, context, server: str) -> None:
        super().__init__("my_controller", context=context)
        self.client = self.create_client(CheckWrench, f"{server}/check_wrench")
        self.answered = threading.Event()
        self.reply = None
        self.pending = None
        self.timer = self.create_timer(0.05, self.tick)

    def tick(self) -> None:
        if self.pending is None and self.client.service_is_ready():
            request = CheckWrench.Request(mode="na")
            request.wrench.force.x, request.wrench.force.y = 0.1, -1.0
            self.pending = self.client.call_async(request)
            self.pending.add_done_callback(self.done)

    def done(self, future) -> None:
        self.reply = future.result()
        self.answered.set()


@pytest.mark.slow
def test_spin_runs_the_users_node_beside_the_wrenchcone_node(wrenchcone_node,
                                                            wrenchcone_context,
                                                            wrenchcone_spin):
    controller = Controller(wrenchcone_context, wrenchcone_node.get_fully_qualified_name())
    assert wrenchcone_spin(controller) is controller
    assert controller.answered.wait(DEADLINE_S), "the controller's call was never answered"
    assert controller.reply.status == Status.OK and controller.reply.consistent


class Raising(Node):
    def __init__(self, context) -> None:
        super().__init__("raising", context=context)
        self.create_timer(0.01, self.tick)

    def tick(self) -> None:
        raise ZeroDivisionError("in the user's callback")


@pytest.mark.slow
def test_the_spinner_stops_destroys_and_reports_a_callback_error(wrenchcone_context):
    spinner = Spinner()
    quiet = spinner(Node("quiet", context=wrenchcone_context))
    raising = spinner(Raising(wrenchcone_context))
    threads = [thread.thread for _node, thread in spinner._made]
    deadline = threading.Event()
    while threads[1].is_alive() and not deadline.wait(0.02):
        pass  # until the raising node's executor thread has ended
    with pytest.raises(RuntimeError, match="ZeroDivisionError"):
        spinner.close()
    assert not any(t.is_alive() for t in threads)
    for node in (quiet, raising):  # destroyed: rclpy refuses to use its handle
        with pytest.raises(Exception, match="destruction was requested"):
            node.create_publisher(Status, "x", 1)


MODULE_NODES: list[int] = []
SESSION_NODES: list[int] = []


@pytest.mark.slow
@pytest.mark.parametrize("wrench", [(0.1, -1.0, 0.0), (1.0, -1.0, -1.0), (0.5, -1.0, 0.0)])
def test_the_module_variants_share_one_node(wrench, wrenchcone_node_module,
                                            wrenchcone_client_module,
                                            wrenchcone_node_session):
    MODULE_NODES.append(id(wrenchcone_node_module))
    SESSION_NODES.append(id(wrenchcone_node_session))
    reply = wrenchcone_client_module.check_wrench("na", wrench)
    assert reply.status == Status.OK, reply.message
    assert len(set(MODULE_NODES)) == 1 and len(set(SESSION_NODES)) == 1
    assert wrenchcone_node_module is not wrenchcone_node_session


INNER_MODULE = textwrap.dedent('''
    import pytest
    from wrenchcone_msgs.msg import Status

    NODES = []


    @pytest.fixture(scope="module")
    def wrenchcone_scene():
        return {scene!r}


    @pytest.mark.parametrize("i", range(5))
    def test_check(i, wrenchcone_client_module, wrenchcone_node_module):
        NODES.append(id(wrenchcone_node_module))
        assert wrenchcone_client_module.check_wrench("na", (0.1, -1.0, 0.0)).consistent
        assert len(set(NODES)) == 1
''')
INNER_AFTER = textwrap.dedent('''
    import threading


    def test_nothing_left_after_the_module():
        assert [t.name for t in threading.enumerate()] == ["MainThread"]
''')


def inner_env() -> dict:
    # not this run's PYTEST_* variables (under pytest-xdist they would make the inner run
    # start xdist's own threads); the package under test first on the path
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
    env["PYTHONPATH"] = os.pathsep.join([PACKAGE_PATH, env.get("PYTHONPATH", "")])
    env["WRENCHCONE_ENGINE"] = "numpy"  # these runs are about the fixtures
    return env


@pytest.mark.slow
def test_a_module_node_is_made_once_and_gone_after_the_module(tmp_path):
    (tmp_path / "test_a_module.py").write_text(INNER_MODULE.format(scene=str(DISC)))
    (tmp_path / "test_b_after.py").write_text(INNER_AFTER)
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "-p", "no:xdist", "-p", "no:rerunfailures", "."], cwd=tmp_path,
                         env=inner_env(), capture_output=True, text=True, timeout=600,
                         check=False)
    assert out.returncode == 0 and "6 passed" in out.stdout, out.stdout[-3000:] + out.stderr


@pytest.mark.slow
def test_a_test_module_importing_ros_unsourced_gets_one_line(tmp_path):
    """Before, pytest printed the ImportError's traceback and a hint about sys.path."""
    (tmp_path / "test_controller.py").write_text(
        "from wrenchcone_msgs.msg import Status\n\n\ndef test_ok():\n    assert Status.OK == 0\n")
    unsourced = {k: os.environ[k] for k in ("PATH", "HOME") if k in os.environ}
    unsourced["PYTHONPATH"] = PACKAGE_PATH  # the package (and its plugin), no interfaces
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "test_controller.py"], cwd=tmp_path, env=unsourced,
                         capture_output=True, text=True, timeout=300, check=False)
    assert out.returncode == 2, out.stdout[-3000:] + out.stderr
    assert "Traceback" not in out.stdout and "Hint:" not in out.stdout, out.stdout[-3000:]
    assert ("test_controller.py: No module named 'wrenchcone_msgs': source the ROS workspace "
            "first: `source install/setup.bash`") in out.stdout, out.stdout[-3000:]
