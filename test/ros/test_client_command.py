# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The client example against the real node: as a library and as a command."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import textwrap
import threading

import pytest
from helpers.node_harness import DEADLINE_S
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from wrenchcone_msgs.msg import Status
from wrenchcone_ros.ros.client import WrenchConeClient
from wrenchcone_ros.core import consistent_modes, default_scene, force_directions, wrench_cone
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, GetCone

pytestmark = pytest.mark.slow  # the client command in subprocesses, against a node over DDS


def test_library_calls(harness):
    client = WrenchConeClient(harness.tester, server=f"{harness.ns}/wrenchcone")
    assert client.wait_for_service(30)
    cone = wrench_cone(default_scene(), "na")
    r = client.check_wrench("na", (0.1, -1.0, 0.0))
    assert r.status == Status.OK and r.consistent
    assert r.margin == pytest.approx(cone.margin((0.1, -1.0, 0.0)), abs=1e-12)
    c = client.get_cone("na")
    assert c.feasible and c.F.shape == cone.F.shape
    assert c.contains((0.1, -1.0, 0.0)) and not c.contains((0.0, 1.0, 0.0))
    k = client.classify_wrench((0.1, -1.0, 0.0))
    assert [m.mode for m in k.matches] == [m.mode for m in consistent_modes(
        default_scene(), (0.1, -1.0, 0.0))]
    r = client.check_wrench("na", (0.1, -1.0, 0.0), classify=True)
    assert [m.mode for m in r.others] == [m.mode for m in k.matches if m.mode != "na"]
    for point in (None, (0.0, 0.5)):
        d = client.force_directions("na", point)
        core = force_directions(default_scene(), "na", point=point)
        assert d.status == Status.OK
        assert [(iv.lo, iv.hi) for iv in d.intervals] == [(i.lo, i.hi) for i in core]


def run_cli(harness, *args):
    # a fresh process in the same (isolated) ROS domain; cwd is the repository root, so
    # the source tree shadows the install tree on sys.path: the client must cope
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run(
        [sys.executable, "-m", "wrenchcone_ros.ros.client", *args,
         "--node", f"{harness.ns}/wrenchcone", "--timeout", "30"],
        capture_output=True, text=True, cwd=root, env=dict(os.environ), check=False)
    return out.returncode, json.loads(out.stdout.strip().splitlines()[-1])


def test_command_line(harness):
    code, out = run_cli(harness, "check", "na", "0.1", "-1", "0")
    assert code == 0 and out["consistent"] is True and out["status"] == "OK"
    code, out = run_cli(harness, "cone", "na")
    assert code == 0 and out["feasible"] and len(out["F"]) == 3
    code, out = run_cli(harness, "classify", "0.1", "-1", "0")
    core = consistent_modes(default_scene(), (0.1, -1.0, 0.0))
    assert code == 0 and [m["mode"] for m in out["matches"]] == [m.mode for m in core]
    assert all(m["certain"] for m in out["matches"])  # nominal: every match holds
    assert "uncertainty" not in out
    code, out = run_cli(harness, "directions", "na")  # at the com
    core = force_directions(default_scene(), "na")
    assert code == 0 and [(i["lo"], i["hi"]) for i in out["intervals"]] == [
        (iv.lo, iv.hi) for iv in core]
    code, out = run_cli(harness, "force_directions", "na", "--point", "0", "0.5",
                        "--exclusive")
    core = force_directions(default_scene(), "na", point=(0.0, 0.5), exclusive=True)
    assert code == 0 and [i["best"] for i in out["intervals"]] == [iv.best for iv in core]
    code, out = run_cli(harness, "check", "nn", "0.1", "-1", "0")
    assert code == 3 and out["status"] == "MODE_NOT_ALLOWED" and out["consistent"] is False


def test_command_line_help():
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.ros.client", "directions",
                          "--help"], capture_output=True, text=True, check=False)
    assert out.returncode == 0 and "--point" in out.stdout and "--exclusive" in out.stdout


@pytest.mark.parametrize("args", [["--help"], ["check", "--help"], ["cone", "--help"],
                                  ["classify", "--help"], ["directions", "--help"]])
def test_client_help(args):
    """`check --help` / `classify --help` raised ValueError (a tuple metavar)."""
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.ros.client", *args],
                         capture_output=True, text=True, check=False, timeout=60)
    assert out.returncode == 0 and "usage" in out.stdout and not out.stderr


@pytest.mark.parametrize("args", [["check", "na", "1", "x", "0"], ["check", "na", "1", "nan", "0"],
                                  ["classify", "1", "2"], ["nope"]])
def test_client_bad_arguments_exit_2_one_line(args):
    out = subprocess.run([sys.executable, "-m", "wrenchcone_ros.ros.client", *args],
                         capture_output=True, text=True, check=False, timeout=60)
    assert out.returncode == 2 and len(out.stderr.strip().splitlines()) == 1, out.stderr


#: The documented pattern, as a program: a node nobody spins, then several calls.
_UNSPUN_PROGRAM = textwrap.dedent("""
    import sys
    import rclpy
    from rclpy.node import Node
    from wrenchcone_msgs.msg import Status
    from wrenchcone_ros.ros.client import WrenchConeClient

    rclpy.init()
    node = Node("my_controller")
    client = WrenchConeClient(node, server=sys.argv[1])
    assert client.wait_for_service(timeout=30.0)
    answered = 0
    for k in range(6):
        try:
            r = client.check_wrench("na", (0.1, -1.0, 0.0), timeout=3.0)
        except TimeoutError as exc:
            print("timeout", k, exc)
            continue
        answered += r.status == Status.OK and r.consistent
    answered += client.get_cone("na", timeout=3.0).feasible
    answered += client.force_directions("na", timeout=3.0).status == 0
    print("answered", answered)
    node.destroy_node()
    rclpy.shutdown()
""")


def test_several_calls_from_a_node_nobody_spins(harness):
    """docs/node.md's client pattern: after the first call, node.executor stayed set (the
    global executor spin_until_future_complete had used), so every later call waited
    for a reply without anything spinning the node and timed out."""
    out = subprocess.run([sys.executable, "-c", _UNSPUN_PROGRAM, f"{harness.ns}/wrenchcone"],
                         capture_output=True, text=True, check=False, timeout=120,
                         env=dict(os.environ))
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip().splitlines()[-1] == "answered 8", out.stdout


def test_several_calls_from_a_node_spun_in_another_thread(harness):
    node = Node("spun_user", namespace=harness.ns, context=harness.node.context)
    executor = SingleThreadedExecutor(context=harness.node.context)
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    try:
        client = WrenchConeClient(node, server=f"{harness.ns}/wrenchcone")
        assert client.wait_for_service(DEADLINE_S)
        for _ in range(6):
            r = client.check_wrench("na", (0.1, -1.0, 0.0), timeout=DEADLINE_S)
            assert r.status == Status.OK and r.consistent
        assert client.get_cone("na", timeout=DEADLINE_S).feasible
    finally:
        executor.shutdown()
        thread.join(DEADLINE_S)
        node.destroy_node()


def test_wait_for_service_waits_for_every_service_the_client_uses(ros_context):
    """A server with check_wrench, get_cone and classify_wrench but no force_directions:
    wait_for_service must not say ready (it did: it ignored force_directions)."""
    server = Node("partial", namespace="/partial_server", context=ros_context)
    user = Node("partial_user", namespace="/partial_server", context=ros_context)
    try:
        for srv_type, name in ((CheckWrench, "check_wrench"), (GetCone, "get_cone"),
                               (ClassifyWrench, "classify_wrench")):
            server.create_service(srv_type, f"~/{name}", lambda req, resp: resp)
        client = WrenchConeClient(user, server="/partial_server/partial")
        assert not client.wait_for_service(timeout=1.0)
    finally:
        user.destroy_node()
        server.destroy_node()
