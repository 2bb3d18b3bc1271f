# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node benchmarks' ROS side: the node in its own process under a watchdog, service
calls waited for on the calling thread, the empty-service floor, the benchmark scenes.

Needs the ROS environment (``source install/setup.bash``): the package's generated
message and service modules live in the install tree. Importing this module gives the
process its own DDS domain (``ROS_DOMAIN_ID`` from the process id, discovery limited to
localhost) unless the environment already sets them, so that a benchmark never hears
another run on the same machine.
"""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

os.environ.setdefault("ROS_DOMAIN_ID", str(1 + os.getpid() % 100))
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

import yaml  # noqa: E402
from rclpy.node import Node  # noqa: E402

from wrenchcone_ros.core import enumerate_modes, load_scene, wrench_cone  # noqa: E402
from wrenchcone_ros.node.executors import SpinThread  # noqa: E402

from wrenchcone_ros.ros import conversions as conv  # noqa: E402,F401  (the ROS adapters)

HERE = os.path.dirname(os.path.abspath(__file__))
#: The paper's disc (the scene `make run` starts the node on).
PAPER_DISC = os.path.join(HERE, "..", "..", "examples", "paper_disc.yaml")
#: The Python of helper processes, with -P: the working directory is not put on sys.path,
#: so that a benchmark started from the repository's root runs the package the
#: environment names, not whatever directory it was started from.
PYTHON = [sys.executable, "-P"]

#: A square on two pins plus three free fixels: 17 feasible modes, every F changes when
#: the square slides along the pins (x). The scene of node_latency, node_stream,
#: node_snapshot_cost and marker_cost.
SQUARE = {
    "workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.2, 0.1],
                  "shape": {"type": "polygon",
                            "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]}},
    "friction": 0.3,
    "fixels": [[-0.5, -1.0], [0.5, -1.0], [1.5, 0.0], [-1.5, 0.5], [0.0, 1.5]],
}
CYCLE = 100  # distinct poses of a stream: x = STEP * (k % CYCLE)
STEP = 4e-4  # m; the square slides along its two pins, the free fixels stay free

#: Seconds a node (or helper process) may take to say "ready" before the watchdog kills it.
READY_TIMEOUT_S = 120.0
#: Seconds a stopped node may take to end after SIGINT before it is killed.
STOP_TIMEOUT_S = 20.0


def feasible_modes(data: dict = SQUARE) -> list[str]:
    """The modes of a scene whose open mode is feasible, in enumeration order."""
    scene = load_scene(data)
    return [m for m in enumerate_modes(scene.in_contact) if wrench_cone(scene, m).feasible]


@contextmanager
def scene_file(data: dict) -> Iterator[str]:
    """A temporary YAML scene file holding ``data``, removed afterwards."""
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(data, f)
    try:
        yield f.name
    finally:
        os.unlink(f.name)


def call_and_wait(client, request, timeout: float = 30.0) -> tuple[float, object]:
    """(round trip s, response) of one rclpy service call, waited for on this thread
    (the client's node is spun elsewhere)."""
    done = threading.Event()
    t0 = time.perf_counter()
    future = client.call_async(request)
    future.add_done_callback(lambda _f: done.set())
    if not done.wait(timeout):
        raise RuntimeError(f"no reply from {client.srv_name} in {timeout:g} s")
    return time.perf_counter() - t0, future.result()


def wait_for_services(*clients, timeout: float = 30.0) -> None:
    for c in clients:
        if not c.wait_for_service(timeout_sec=timeout):
            raise RuntimeError(f"{c.srv_name} not available after {timeout:g} s")


def spin(nodes: list[Node], name: str) -> SpinThread:
    """Spin ``nodes`` in a thread of their own on the node's executor kind (on a 2-core
    machine a MultiThreadedExecutor client was itself the bottleneck)."""
    return SpinThread(nodes, nodes[0].get_logger(), name)


_LIVE: list[ChildProcess] = []


@atexit.register
def _kill_leftovers() -> None:
    for child in list(_LIVE):
        child.kill()


class ChildProcess:
    """A helper process that prints a line containing ``ready_text`` once it is ready,
    watched: killed when it is not ready within ``ready_timeout`` s, and at the latest
    when this process exits. Its output after the ready line is drained (kept in
    :attr:`log`) so that it never blocks on a full pipe."""

    def __init__(self, cmd: list[str], ready_text: str, stream: str = "stdout",
                 env: dict | None = None, ready_timeout: float = READY_TIMEOUT_S) -> None:
        pipe = {"stdout": subprocess.PIPE, "stderr": subprocess.DEVNULL}
        if stream == "stderr":
            pipe = {"stdout": subprocess.DEVNULL, "stderr": subprocess.PIPE}
        self.proc = subprocess.Popen(cmd, text=True, env=env, **pipe)
        _LIVE.append(self)
        out = self.proc.stdout if stream == "stdout" else self.proc.stderr
        ready = threading.Event()
        self.log: list[str] = []

        def drain() -> None:
            for line in out:
                if not ready.is_set() and ready_text in line:
                    ready.set()
                else:
                    self.log.append(line)

        self._drain = threading.Thread(target=drain, daemon=True)
        self._drain.start()
        deadline = time.monotonic() + ready_timeout
        while not ready.wait(0.1):
            if not self._drain.is_alive() or time.monotonic() > deadline:  # ended, or hung
                self.kill()
                tail = "".join(self.log[-5:]).strip()
                what = ("ended" if self.proc.returncode not in (None, -9)
                        else f"not ready in {ready_timeout:g} s")
                raise RuntimeError(f"{' '.join(cmd[:3])}... {what}"
                                   + (f": {tail}" if tail else ""))

    @property
    def pid(self) -> int:
        return self.proc.pid

    def log_text(self, timeout: float = 10.0) -> str:
        """Its output after the ready line (complete once the process has ended)."""
        self._drain.join(timeout)
        return "".join(self.log)

    def stop(self, signum: int = 2, timeout: float = STOP_TIMEOUT_S) -> int:
        """Send ``signum`` (SIGINT), wait up to ``timeout`` s, kill if it is still there;
        the exit code."""
        if self.proc.poll() is None:
            self.proc.send_signal(signum)
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if self in _LIVE:
            _LIVE.remove(self)
        return self.proc.returncode

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        if self in _LIVE:
            _LIVE.remove(self)


class NodeProcess(ChildProcess):
    """The wrenchcone node in its own process, as deployed (``python -m
    wrenchcone_ros.node``), ready when it logs "ready:"; its CPU and memory from /proc.

    ``instrument``: a JSON file to which the node program records its public timing
    hooks (``harness/instrumented_node.py``: service callbacks, worker steps, pauses,
    collections) instead of running plain; ``executor``: the executor the program spins
    the node on (``harness/node_program.py``: lane, the default, multi_threaded or
    single_threaded; not with ``instrument``)."""

    def __init__(self, ns: str, args: list[str], instrument: str | None = None,
                 executor: str = "lane") -> None:
        env = dict(os.environ)
        program = ["-m", "wrenchcone_ros.node"]  # the installed package (PYTHON: -P)
        if executor != "lane":  # the program with another executor (node_program.py)
            program = [os.path.join(HERE, "node_program.py"), executor]
        if instrument is not None:
            program = [os.path.join(HERE, "instrumented_node.py")]
            env["WRENCHCONE_INSTRUMENT_FILE"] = instrument
        super().__init__([*PYTHON, *program, "--ros-args", "-r", f"__ns:={ns}",
                          *args], "ready:", stream="stderr", env=env)

    def cpu_s(self) -> float:
        fields = open(f"/proc/{self.pid}/stat").read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def rss_mb(self) -> float:
        for line in open(f"/proc/{self.pid}/status"):
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return float("nan")


def start_trigger_server(ns: str) -> ChildProcess:
    """An empty std_srvs/Trigger service (``<ns>/trigger``) in its own process
    (``harness/empty_service.py``): the floor of a service call on this machine, measured
    side by side with the node."""
    return ChildProcess([*PYTHON, os.path.join(HERE, "empty_service.py"), ns], "ready")


def start_pose_stream(ns: str, rate_hz: float, seconds: float, out: str) -> ChildProcess:
    """The pose stream of ``harness/pose_stream.py`` (the square sliding along its pins,
    ``STEP`` per pose, ``CYCLE`` distinct poses), started and discovered: the stream
    begins when this returns; its records are in ``out`` (JSON) once it has ended."""
    return ChildProcess([*PYTHON, os.path.join(HERE, "pose_stream.py"), ns, str(rate_hz),
                         str(seconds), str(STEP), str(CYCLE), out], "go")
