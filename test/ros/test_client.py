# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The client library (wrenchcone_ros.ros.client) against the real node over DDS.

The node runs in-process in a context of its own (the kit's node factory: another DDS
participant), or the client in another process; answers are compared with the core
library computing on the same scene file.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench

from wrenchcone_ros.core import consistent_modes, force_directions, load_scene, wrench_cone
from wrenchcone_ros.ros.client import ServiceUnavailable, WrenchConeClient
from wrenchcone_ros.testing.harness import ExecutorThread

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "examples" / "paper_disc.yaml"
G = (0.1, -1.0, 0.0)  # N, N, N m: consistent with 'na' on the paper's disc
DEADLINE_S = 30.0  # only a guard against a hang; never asserted on

#: A controller's program: make the client and call at once (no wait_for_service).
FIRST_CALL_PROGRAM = """
import sys
import rclpy
from rclpy.node import Node
from wrenchcone_ros.ros.client import WrenchConeClient

rclpy.init()
node = Node("my_controller")
client = WrenchConeClient(node, server=sys.argv[1])
try:
    r = client.check_wrench("na", (0.1, -1.0, 0.0), timeout=float(sys.argv[2]))
    print("answered", r.status, r.consistent, r.margin)
except TimeoutError as exc:
    print("timeout", type(exc).__name__, exc)
client.destroy()
node.destroy_node()
rclpy.shutdown()
"""


def ros_env(domain_id: int) -> dict[str, str]:
    """The environment of a process in the test's domain."""
    return {**os.environ, "ROS_DOMAIN_ID": str(domain_id),
            "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}


def test_the_first_call_of_another_process_is_answered(wrenchcone_node_factory,
                                                       wrenchcone_domain_id):
    """A controller process that makes the client and calls at once: the request went
    out before DDS had discovered the service, and the call timed out after 10 s."""
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()
    out = subprocess.run([sys.executable, "-c", FIRST_CALL_PROGRAM, server, "10"],
                         capture_output=True, text=True, env=ros_env(wrenchcone_domain_id),
                         timeout=120, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    margin = wrench_cone(load_scene(DISC), "na").margin(G)
    assert out.stdout.split() == ["answered", str(Status.OK), "True", repr(margin)], out.stdout


#: A controller's program started as launch starts it in a namespace, with its node
#: renamed: ``--ros-args -r __node:=ctl1 -r __ns:=/cell1`` (global remaps of the process).
NAMESPACED_PROGRAM = """
import sys
import rclpy
from rclpy.node import Node
from wrenchcone_ros.ros.client import WrenchConeClient

rclpy.init(args=sys.argv)
node = Node("my_controller")
client = WrenchConeClient(node)  # the default server, resolved in the node's namespace
r = client.check_wrench("na", (0.1, -1.0, 0.0), timeout=30.0)
print(node.get_fully_qualified_name(), client.helper.get_fully_qualified_name(), r.status,
      r.consistent)
client.destroy()
node.destroy_node()
rclpy.shutdown()
"""


def test_a_namespaced_renamed_controller_reaches_the_node_of_its_namespace(
        wrenchcone_node_factory, wrenchcone_domain_id):
    """Remapped with ``__node`` and ``__ns`` as launch does, the caller's node is
    /cell1/ctl1, the client's hidden node keeps a name of its own (it does not take the
    process's ``__node`` remap: two nodes of one name), and the default server,
    relative, is the wrenchcone node of the same namespace, not the one at the root
    (a pawl there: its answer to the disc's mode 'na' would be a refusal)."""
    wrenchcone_node_factory(DISC, namespace="/cell1")
    wrenchcone_node_factory(ROOT / "examples" / "pawl_polygon.yaml")  # /wrenchcone: a decoy
    out = subprocess.run([sys.executable, "-c", NAMESPACED_PROGRAM, "--ros-args", "-r",
                          "__node:=ctl1", "-r", "__ns:=/cell1"],
                         capture_output=True, text=True, env=ros_env(wrenchcone_domain_id),
                         timeout=120, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    name, helper, status, consistent = out.stdout.split()
    assert name == "/cell1/ctl1"
    assert helper != name and helper.startswith("/cell1/"), helper
    assert (int(status), consistent) == (Status.OK, "True"), out.stdout


def test_the_first_call_right_after_construction_is_answered(wrenchcone_node_factory,
                                                             wrenchcone_test_node):
    """The same in one process (the node in a context of its own)."""
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()
    with WrenchConeClient(wrenchcone_test_node, server=server) as client:
        r = client.check_wrench("na", G)
    assert r.status == Status.OK and r.consistent
    assert r.margin == wrench_cone(load_scene(DISC), "na").margin(G)


def every_call(client: WrenchConeClient, timeout: float) -> list:
    return [lambda: client.check_wrench("na", G, timeout=timeout),
            lambda: client.get_cone("na", timeout=timeout),
            lambda: client.classify_wrench(G, timeout=timeout),
            lambda: client.force_directions("na", timeout=timeout)]


def test_no_server_raises_service_unavailable_naming_the_service(wrenchcone_test_node):
    with WrenchConeClient(wrenchcone_test_node, server="/nobody") as client:
        for call, name in zip(every_call(client, 0.2), ("check_wrench", "get_cone",
                                                        "classify_wrench",
                                                        "force_directions")):
            with pytest.raises(ServiceUnavailable) as caught:
                call()
            assert caught.value.service == f"/nobody/{name}"
            assert not caught.value.offered and caught.value.timeout == 0.2
            assert isinstance(caught.value, TimeoutError)
            assert str(caught.value).startswith(f"no reply from /nobody/{name} within 0.2 s")


def test_a_server_that_does_not_reply_in_time(wrenchcone_context, wrenchcone_test_node):
    release = threading.Event()

    def stuck(request, response):
        release.wait(DEADLINE_S)
        return response

    server = Node("stuck", context=wrenchcone_context)
    server.create_service(CheckWrench, "~/check_wrench", stuck)
    spinner = ExecutorThread(wrenchcone_context)
    spinner.add_node(server)
    try:
        with WrenchConeClient(wrenchcone_test_node, server="/stuck") as client:
            with pytest.raises(ServiceUnavailable) as caught:
                client.check_wrench("na", G, timeout=1.0)
        assert caught.value.service == "/stuck/check_wrench" and caught.value.offered
    finally:
        release.set()
        spinner.stop()
        server.destroy_node()


def test_calls_from_a_node_spun_by_the_callers_executor(wrenchcone_node_factory,
                                                        wrenchcone_test_node,
                                                        wrenchcone_context):
    """The caller's node in the caller's MultiThreadedExecutor (another thread): every
    service answers, as the core computes it, and the executor gets no other node."""
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()
    spinner = ExecutorThread(wrenchcone_context, MultiThreadedExecutor)
    spinner.add_node(wrenchcone_test_node)
    scene = load_scene(DISC)
    try:
        with WrenchConeClient(wrenchcone_test_node, server=server) as client:
            check, cone, classified, directions = (call() for call in
                                                   every_call(client, DEADLINE_S))
            assert check.status == Status.OK and check.consistent
            assert check.margin == wrench_cone(scene, "na").margin(G)
            assert cone.feasible and cone.contains(G) and not cone.contains((0.0, 1.0, 0.0))
            assert [m.mode for m in classified.matches] == [
                m.mode for m in consistent_modes(scene, G)]
            assert [(iv.lo, iv.hi) for iv in directions.intervals] == [
                (i.lo, i.hi) for i in force_directions(scene, "na")]
            assert spinner.executor.get_nodes() == [wrenchcone_test_node]
    finally:
        spinner.stop()


def test_calls_from_several_threads_of_a_node_nobody_spins(wrenchcone_node_factory,
                                                           wrenchcone_test_node):
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()
    replies: list = []
    with WrenchConeClient(wrenchcone_test_node, server=server) as client:
        threads = [threading.Thread(target=lambda: replies.extend(
            client.check_wrench("na", G, timeout=DEADLINE_S) for _ in range(3)))
            for _ in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(DEADLINE_S)
    assert len(replies) == 12
    assert all(r.status == Status.OK and r.consistent for r in replies)


@pytest.mark.slow
def test_command_line_no_reply_exits_1_naming_the_service(wrenchcone_domain_id):
    out = subprocess.run(
        [sys.executable, "-m", "wrenchcone_ros.ros.client", "check", "na", "0", "0", "0",
         "--node", "/nobody", "--timeout", "0.3"], capture_output=True, text=True,
        env=ros_env(wrenchcone_domain_id), cwd=ROOT / "test", timeout=120, check=False)
    assert out.returncode == 1, out.stderr[-2000:]
    reply = json.loads(out.stdout)
    assert reply["service"] == "/nobody/check_wrench"
    assert reply["error"].startswith("no reply from /nobody/check_wrench within 0.3 s")


def test_many_calls_leave_no_tasks_behind(wrenchcone_node_factory, wrenchcone_test_node):
    """A controller calls for minutes: after 300 calls the client's executor holds no
    queued tasks. (rclpy's spin_until_future_complete adds a done callback at every
    wake-up, each queued as a task when the reply comes; the tasks a call did not run
    piled up by thousands in the closed loop, and every spin walked them.)"""
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()
    with WrenchConeClient(wrenchcone_test_node, server=server) as client:
        for _ in range(100):
            assert client.get_cone("na", timeout=DEADLINE_S).status == Status.OK
            assert client.check_wrench("na", G, timeout=DEADLINE_S).consistent
            assert client.force_directions("na", timeout=DEADLINE_S).status == Status.OK
        queued = len(client._executor._tasks)
    assert queued <= 3, queued


@pytest.mark.slow
def test_command_line_exit_status_is_the_documented_one(wrenchcone_node_factory,
                                                        wrenchcone_domain_id):
    """docs/node.md's statement of the command line's exit status, and what it does:
    0 for status OK, 3 for any other status, 1 for no reply, 2 for bad arguments."""
    text = " ".join((ROOT / "docs" / "node.md").read_text().split())
    assert ("exit status 0 for status OK, 3 for any other status (named in the JSON), "
            "1 when no reply came, 2 for bad arguments") in text
    server = wrenchcone_node_factory(DISC).get_fully_qualified_name()

    def run(*words: str) -> subprocess.CompletedProcess:
        return subprocess.run(
            [sys.executable, "-m", "wrenchcone_ros.ros.client", *words, "--node", server],
            capture_output=True, text=True, env=ros_env(wrenchcone_domain_id),
            cwd=ROOT / "test", timeout=120, check=False)

    ok = run("check", "na", "0.1", "-1", "0")
    assert ok.returncode == 0 and json.loads(ok.stdout)["status"] == "OK", ok.stdout
    refused = run("check", "nn", "0.1", "-1", "0")  # fixel 2 is not in contact
    assert refused.returncode == 3, refused.stdout
    assert json.loads(refused.stdout)["status"] == "MODE_NOT_ALLOWED"
    bad = run("check", "na", "x", "-1", "0")
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1, bad.stderr
