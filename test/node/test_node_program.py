# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node started exactly as a user starts it: the installed launcher
(``lib/wrenchcone_ros/wrenchcone_node``, what ``ros2 run`` and ``make run`` execute), in
its own process. A plan goal with Monte Carlo runs finishes (its worker processes must
not start nodes of their own), a cancel is answered by the one action server, and a
second goal after it is accepted."""

from __future__ import annotations

import os
import signal
import subprocess
import threading
from pathlib import Path

from action_msgs.msg import GoalStatus
from helpers.node_harness import installed_program
from rclpy.action import ActionClient
from rclpy.action.graph import get_action_server_names_and_types_by_node
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node

from wrenchcone_msgs.action import PlanSeating
from wrenchcone_msgs.msg import Status

ROOT = Path(__file__).resolve().parents[2]
PAWL = ROOT / "examples" / "pawl_seating.yaml"
DEADLINE_S = 180.0


class Program:
    """The installed launcher in a process of its own; its stderr is collected."""

    def __init__(self, ns: str, *args: str) -> None:
        cmd = [str(installed_program("wrenchcone_node")), "--ros-args", "-r",
               f"__ns:={ns}", "-p", f"scene_file:={PAWL}", "-p", "input_timeout:=0.0", *args]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True, env=dict(os.environ))
        self.lines: list[str] = []
        self.ready = threading.Event()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        for line in self.proc.stderr:
            self.lines.append(line)
            if "ready:" in line:
                self.ready.set()

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait()


def spawned_workers(pid: int) -> set[int]:
    """The multiprocessing worker processes below ``pid`` (from /proc: each process's
    parent and command line; not multiprocessing's resource tracker)."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = open(f"/proc/{entry}/stat").read()
            except OSError:
                continue
            parents[int(entry)] = int(stat.rsplit(")", 1)[1].split()[1])
    out, frontier = set(), {pid}
    while frontier:
        frontier = {p for p, parent in parents.items() if parent in frontier} - out
        out |= frontier

    def cmdline(p: int) -> bytes:
        try:
            return open(f"/proc/{p}/cmdline", "rb").read()
        except OSError:
            return b""
    return {p for p in out if b"spawn_main" in cmdline(p)}


def _wait(future, timeout: float = DEADLINE_S):
    done = threading.Event()
    future.add_done_callback(lambda _f: done.set())
    assert done.wait(timeout), "no answer"
    return future.result()


def test_a_plan_with_runs_a_cancel_and_a_second_goal_through_the_installed_launcher(
        ros_context):
    ns = f"/prog{os.getpid()}"
    program = Program(ns)
    client_node = Node("plan_client", namespace=ns, context=ros_context)
    executor = MultiThreadedExecutor(num_threads=2, context=ros_context)
    executor.add_node(client_node)
    spinner = threading.Thread(target=executor.spin, daemon=True)
    spinner.start()
    client = ActionClient(client_node, PlanSeating, f"{ns}/wrenchcone/plan_seating")
    try:
        assert program.ready.wait(120), "".join(program.lines)
        assert client.wait_for_server(timeout_sec=60)
        goal = PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=12, seed=3)
        feedback = []
        handle = _wait(client.send_goal_async(goal, feedback_callback=feedback.append))
        assert handle.accepted
        result = _wait(handle.get_result_async())
        assert result.status == GoalStatus.STATUS_SUCCEEDED, result.result.message
        r = result.result
        assert r.status == Status.OK and r.runs == 12 and len(r.segments) >= 2, r.message
        assert any(f.feedback.simulations_total == 12 for f in feedback)
        workers = spawned_workers(program.proc.pid)
        assert workers, "the runs were not made in worker processes"

        # a long goal, cancelled once its runs started: CANCELED, by the one server
        long_goal = PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=400)
        started = threading.Event()
        handle = _wait(client.send_goal_async(
            long_goal, feedback_callback=lambda f: f.feedback.simulations_run
            and started.set()))
        assert handle.accepted
        assert started.wait(120), "no simulation feedback"
        cancel = _wait(handle.cancel_goal_async())
        assert len(cancel.goals_canceling) == 1
        result = _wait(handle.get_result_async())
        assert result.status == GoalStatus.STATUS_CANCELED
        assert result.result.status == Status.CANCELED

        # the next goal is accepted (nothing is left busy) and finishes
        handle = _wait(client.send_goal_async(
            PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=4, seed=1)))
        assert handle.accepted
        assert _wait(handle.get_result_async()).status == GoalStatus.STATUS_SUCCEEDED
        # the worker processes were started once: the same ones served every goal
        assert spawned_workers(program.proc.pid) == workers

        # one node, one action server: the Monte Carlo workers started none
        names = [n for n, s in client_node.get_node_names_and_namespaces() if s == ns]
        assert names.count("wrenchcone") == 1, names
        servers = get_action_server_names_and_types_by_node(client_node, "wrenchcone", ns)
        assert [n for n, _ in servers] == [f"{ns}/wrenchcone/plan_seating"], servers
    finally:
        client.destroy()
        executor.shutdown(timeout_sec=2.0)
        client_node.destroy_node()
        code = program.stop()
    text = "".join(program.lines)
    assert code == 0 and "Traceback" not in text, text
    assert text.count("ready:") == 1, text  # no worker started a node of its own
