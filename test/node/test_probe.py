# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_probe (src/probe.c), the compiled check_wrench client, run as the installed
program against the real node over DDS: its lines say what the node answered (checked
against the core's cone), and bad arguments, a missing service and signals end it with
the documented exit codes."""

from __future__ import annotations

import math
import re
import signal
import subprocess
import threading
from pathlib import Path

import pytest
from helpers.node_harness import installed_program
from std_srvs.srv import Trigger

from wrenchcone_ros.core import default_scene, wrench_cone
from wrenchcone_msgs.msg import Status

S = Status
INSIDE, OUTSIDE = (0.1, -1.0, 0.0), (0.0, 1.0, 0.0)  # of the default scene's "na" cone
DEADLINE_S = 60.0  # a guard against a hang only


def installed_probe() -> Path:
    return installed_program("wrenchcone_probe")


def probe(*args: str, timeout: float = DEADLINE_S) -> subprocess.CompletedProcess:
    return subprocess.run([str(installed_probe()), *args], capture_output=True, text=True,
                          timeout=timeout)


def read_lines(path: Path) -> list[list[str]]:
    header, *lines = path.read_text().splitlines()
    assert header.split() == ["kind", "sent_ns", "round_trip_ns", "status", "consistent",
                              "pose_stamp_ns", "inputs_version"]
    return [line.split() for line in lines]


def with_trigger(h) -> str:
    """An empty std_srvs/Trigger service beside the node (the floor the probe measures)."""
    h.tester.create_service(Trigger, "trigger", lambda req, resp: resp)
    return f"{h.ns}/trigger"


def test_installed_probe_reports_what_the_node_answers(harness, tmp_path):
    h = harness
    trigger = with_trigger(h)
    cone = wrench_cone(default_scene(), "na")
    assert cone.contains(INSIDE) and not cone.contains(OUTSIDE)  # not vacuous
    for g in (INSIDE, OUTSIDE):
        out = tmp_path / "calls.txt"
        done = probe("--mode", "na", "--wrench", ",".join(map(str, g)), "--rate", "50",
                     "--seconds", "0.5", "--service", f"{h.ns}/wrenchcone/check_wrench",
                     "--trigger", trigger, "--out", str(out))
        assert done.returncode == 0, done.stderr
        assert done.stderr.splitlines()[0] == "ready", done.stderr
        lines = read_lines(out)
        checks = [x for x in lines if x[0] == "check"]
        triggers = [x for x in lines if x[0] == "trigger"]
        assert len(checks) >= 5 and len(triggers) == len(checks), lines
        reference = h.check("na", g)  # the same question through rclpy
        for _kind, sent, rtt, status, consistent, stamp, version in checks:
            assert int(rtt) > 0 and int(sent) > 0
            assert int(status) == S.OK
            assert bool(int(consistent)) == cone.contains(g) == reference.consistent
            assert int(version) == reference.inputs_version
            assert int(stamp) == (reference.pose_stamp.sec * 10**9
                                  + reference.pose_stamp.nanosec)
        assert all(int(x[2]) > 0 and x[3:] == ["-1"] * 4 for x in triggers), triggers
        # the summary's percentiles are the lines' (nearest rank)
        for kind, calls in (("check_wrench", checks), ("trigger", triggers)):
            said = re.search(rf"{kind}: (\d+) answered, round trip p50 / p99 / max "
                             r"([\d.]+) / ([\d.]+) / ([\d.]+) ms", done.stderr)
            assert said, done.stderr
            rtt = sorted(int(x[2]) for x in calls)
            n = len(rtt)
            expected = [rtt[math.ceil(n * q) - 1] * 1e-6 for q in (0.5, 0.99)] + [rtt[-1] * 1e-6]
            assert int(said.group(1)) == n
            assert [float(v) for v in said.groups()[1:]] == pytest.approx(expected, abs=6e-4)


def test_probe_says_what_the_node_refuses(harness, tmp_path):
    """A mode the scene cannot have: the node's status is passed on, not hidden."""
    out = tmp_path / "calls.txt"
    done = probe("--mode", "naaa", "--seconds", "0.1", "--service",
                 f"{harness.ns}/wrenchcone/check_wrench", "--out", str(out))
    assert done.returncode == 0, done.stderr
    lines = read_lines(out)
    assert lines and all(x[0] == "check" and int(x[3]) == S.INVALID_MODE and x[4] == "0"
                         for x in lines), lines


def test_probe_waits_for_its_signal_and_ends_at_sigint(harness, tmp_path):
    out = tmp_path / "calls.txt"
    proc = subprocess.Popen(
        [str(installed_probe()), "--mode", "na", "--seconds", "3600", "--wait-for-signal",
         "--service", f"{harness.ns}/wrenchcone/check_wrench", "--out", str(out)],
        stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stderr.readline().strip() == "ready"
        threading.Event().wait(0.3)
        assert read_lines(out) == []  # nothing called before SIGUSR1
        proc.send_signal(signal.SIGUSR1)
        threading.Event().wait(0.5)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=DEADLINE_S)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    lines = read_lines(out)
    assert len(lines) >= 3 and all(int(x[3]) == S.OK for x in lines), lines
    assert f"{len(lines)} calls, 0 unanswered, 0 errors" in err, err


@pytest.mark.parametrize("args, says", [
    ([], "--mode is required"),
    (["--mode", "na", "--rate", "fast"], "--rate takes a positive number, not 'fast'"),
    (["--mode", "na", "--seconds", "-1"], "--seconds takes a positive number, not '-1'"),
    (["--mode", "na", "--wrench", "1,2"], "--wrench takes three finite numbers"),
    (["--mode", "na", "--wrench", "1,nan,0"], "--wrench takes three finite numbers"),
    (["--mode", "na", "--speed", "3"], "unknown option '--speed'"),
    (["--mode"], "every option but --wait-for-signal takes a value"),
])
def test_probe_refuses_bad_arguments_with_exit_2(args, says):
    done = probe(*args)
    assert done.returncode == 2, done
    first = done.stderr.splitlines()[0]
    assert first.startswith("wrenchcone_probe: ") and says in first, done.stderr
    assert "usage: wrenchcone_probe" in done.stderr or "not '" in first


def test_probe_help_exits_0():
    done = probe("--help")
    assert done.returncode == 0 and "usage: wrenchcone_probe" in done.stdout, done


def test_probe_without_a_service_exits_2():
    done = probe("--mode", "na", "--timeout", "0.5", "--service", "/nobody/check_wrench")
    assert done.returncode == 2, done
    assert "the service /nobody/check_wrench did not appear within 0.5 s" in done.stderr, (
        done.stderr)
