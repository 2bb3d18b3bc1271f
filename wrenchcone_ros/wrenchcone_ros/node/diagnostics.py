# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``/diagnostics``: the node's health as diagnostic_msgs/DiagnosticArray, at a set rate.

Published every 1 / ``diagnostics_rate`` s (parameter; 0 = none) on the absolute topic
``/diagnostics`` (where diagnostic aggregators and rqt_runtime_monitor listen). Each
status has ``hardware_id`` = the node's fully qualified name and a name starting with it:

``<node>: inputs``
    values: inputs_version, snapshot status, pose / fixels age (s since the last accepted
    message, node clock, or "none received": the scene file's values are in use), their
    header stamps and sources (``topic``, ``scene_file`` or ``none``: the replies'
    pose_source / fixels_source), unknown parameters given at start, the fixture in use
    (fixel count, radii, friction, the topic it came from), how many times its fixel
    count or radii changed since start (each change is a new fixture, also named in the
    message and logged once) and ``interfaces``, the wrenchcone_msgs interface version the
    node was built with (``wrenchcone_msgs 0.3.0``; Status.INTERFACE_VERSION).
    OK: the inputs make a scene. WARN: no inputs yet while ``wait_for_inputs`` is true;
    inputs older than ``input_timeout`` / ``fixels_timeout`` (STALE_INPUTS: no cone is
    published); parameters given at start that the node does not know (a misspelt key in
    a params file). ERROR: the inputs make no valid scene (e.g. a fixel inside the
    workpiece).
``<node>: mode <mode>`` (each monitored mode)
    values: status, message, feasible, facets, equalities, compute_ms (how long the cone
    of the current snapshot took), inputs_version.
    OK: the cone is published. WARN: the mode cannot happen with the current inputs
    (MODE_INFEASIBLE, MODE_NOT_ALLOWED e.g. a contact lost, NO_INPUTS) or no cone is
    vouched for (STALE_INPUTS): not a fault of the node, but a controller relying on it
    must stop. ERROR: INVALID_MODE, SCENE_ERROR, INTERNAL_ERROR, LIMIT_EXCEEDED.
``<node>: requests``
    values: per service, the number of calls and of replies per status since start.
    OK; WARN when any reply was INTERNAL_ERROR (a bug: see the log).
"""

from __future__ import annotations

import threading
from collections import Counter
from collections.abc import Callable
from typing import Any

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rclpy.node import Node
from rclpy.qos import QoSProfile

from wrenchcone_ros.node.parameters import unknown_start_parameters
from wrenchcone_ros.node.publishers import SnapshotPublisher
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    NO_INPUTS,
    OK,
    SCENE_ERROR,
    STALE_INPUTS,
    STATUS_NAMES,
)
from wrenchcone_msgs.msg import Status
from wrenchcone_ros.node.answers import Answer
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.store import Snapshot

#: The diagnostics convention: volatile, reliable, depth 10.
DIAGNOSTICS_QOS = QoSProfile(depth=10)
LEVEL_NAMES = {DiagnosticStatus.OK: "OK", DiagnosticStatus.WARN: "WARN",
               DiagnosticStatus.ERROR: "ERROR", DiagnosticStatus.STALE: "STALE"}
#: Level of a monitored mode's status (module docstring).
MODE_LEVELS = {OK: DiagnosticStatus.OK, MODE_INFEASIBLE: DiagnosticStatus.WARN,
               MODE_NOT_ALLOWED: DiagnosticStatus.WARN, NO_INPUTS: DiagnosticStatus.WARN,
               STALE_INPUTS: DiagnosticStatus.WARN}


class RequestCounts:
    """Service calls and replies per status since start (services.py records them)."""

    def __init__(self) -> None:
        self.calls: Counter[str] = Counter()
        self.replies: Counter[tuple[str, int]] = Counter()
        #: The compiled lane's counts (fastcheck.py, ``Lane.stats``): its own replies
        #: are added to check_wrench's (the forwarded ones are recorded here already)
        self.compiled: Callable[[], dict] | None = None

    def merged(self) -> tuple[Counter[str], Counter[tuple[str, int]], dict]:
        """(calls, replies per status, the compiled lane's stats) so far."""
        calls, replies = Counter(self.calls), Counter(self.replies)
        stats: dict = {"fast": 0, "serving": False}
        if self.compiled is not None:
            stats = self.compiled()
            fast = stats["fast"]
            calls["check_wrench"] += fast
            for status, n in stats["fast_statuses"].items():
                replies[("check_wrench", status)] += n
        return calls, replies, stats

    def record(self, service: str, status: int) -> None:
        self.calls[service] += 1
        self.replies[(service, int(status))] += 1


def _kv(key: str, value: Any) -> KeyValue:
    return KeyValue(key=key, value=str(value))


def _stamp(stamp: tuple[int, int] | None) -> str:
    return "none" if stamp is None else f"{stamp[0]}.{stamp[1]:09d}"


def _age(received_ns: int | None, now_ns: int) -> float | None:
    return None if received_ns is None else max(0.0, (now_ns - received_ns) * 1e-9)


def input_status(name: str, snap: Snapshot, fresh: Freshness, unknown: list[str],
                 now_ns: int) -> DiagnosticStatus:
    """``<node>: inputs`` (module docstring); ``now_ns``: the node clock."""
    level, reasons = DiagnosticStatus.OK, []
    if snap.status == SCENE_ERROR:
        level = DiagnosticStatus.ERROR
        reasons.append(snap.message)
    elif snap.status != OK:
        level = DiagnosticStatus.WARN
        reasons.append(snap.message)
    ages = {"pose": _age(snap.pose_received_ns, now_ns),
            "fixels": _age(snap.fixels_received_ns, now_ns)}
    if fresh.stale:
        level = max(level, DiagnosticStatus.WARN)
        reasons.append(fresh.stale)
    if unknown:
        level = max(level, DiagnosticStatus.WARN)
        reasons.append(f"unknown parameter(s) given at start, ignored: {unknown}")
    values = [_kv("inputs_version", snap.version),
              _kv("snapshot status", STATUS_NAMES.get(snap.status, snap.status))]
    for key, stamp, source in (("pose", snap.pose_stamp, snap.pose_source),
                               ("fixels", snap.fixels_stamp, snap.fixels_source)):
        a = ages[key]
        values.append(_kv(f"{key} age s", "none received" if a is None else f"{a:.3f}"))
        values.append(_kv(f"{key} stamp", _stamp(stamp)))
        values.append(_kv(f"{key} source", source or "none"))
    values.append(_kv("unknown parameters", unknown))
    values.append(_kv("fixture", snap.fixture or "none yet"))
    values.append(_kv("fixture changes", snap.fixture_changes))
    # the interfaces the node was built with (a client compares its own)
    values.append(_kv("interfaces", f"wrenchcone_msgs {Status.INTERFACE_VERSION}"))
    message = "; ".join(reasons) or "inputs make a valid scene"
    if snap.fixture_changes:
        message += (f"; new fixture ({snap.fixture_changes} change(s) of fixel count or "
                    f"radii since start): {snap.fixture}")
    return DiagnosticStatus(level=level, name=f"{name}: inputs", message=message,
                            values=values)


def mode_status(name: str, mode: str, ans: Answer | None, version: int,
                fresh: Freshness) -> DiagnosticStatus:
    """``<node>: mode <mode>`` (module docstring)."""
    if fresh.stale:
        return DiagnosticStatus(level=DiagnosticStatus.WARN, name=f"{name}: mode {mode}",
                                message=fresh.stale, values=[
                                    _kv("status", STATUS_NAMES[STALE_INPUTS]),
                                    _kv("inputs_version", version)])
    if ans is None:
        return DiagnosticStatus(level=DiagnosticStatus.STALE, name=f"{name}: mode {mode}",
                                message="not computed yet")
    level = MODE_LEVELS.get(ans.status, DiagnosticStatus.ERROR)
    cone = ans.cone
    feasible = bool(cone is not None and cone.feasible and ans.status == OK)
    values = [_kv("status", STATUS_NAMES.get(ans.status, ans.status)),
              _kv("feasible", feasible),
              _kv("facets", cone.F.shape[0] if feasible else 0),
              _kv("equalities", cone.equalities.shape[0] if feasible else 0),
              _kv("compute_ms", f"{1e3 * ans.seconds:.3f}"),
              _kv("inputs_version", version)]
    message = ans.message or (f"cone published: {cone.F.shape[0]} facet(s)" if feasible
                              else STATUS_NAMES.get(ans.status, ""))
    return DiagnosticStatus(level=level, name=f"{name}: mode {mode}", message=message,
                            values=values)


def request_status(name: str, counts: RequestCounts) -> DiagnosticStatus:
    """``<node>: requests`` (module docstring)."""
    calls, replies, lane = counts.merged()
    internal = sum(n for (_, s), n in replies.items() if s == INTERNAL_ERROR)
    values = [_kv(f"{service} calls", n) for service, n in sorted(calls.items())]
    values += [_kv(f"{service} {STATUS_NAMES.get(s, s)}", n)
               for (service, s), n in sorted(replies.items())]
    values += [_kv("check_wrench answered by the compiled lane", lane["fast"]),
               _kv("compiled lane serving", lane["serving"])]
    level = DiagnosticStatus.WARN if internal else DiagnosticStatus.OK
    message = f"{sum(calls.values())} call(s)" + (
        f", {internal} INTERNAL_ERROR repl{'y' if internal == 1 else 'ies'}" if internal
        else "")
    if counts.compiled is not None and not lane["serving"]:
        level = DiagnosticStatus.ERROR
        message += "; the compiled check_wrench lane stopped: check_wrench is not answered"
    return DiagnosticStatus(level=level, name=f"{name}: requests", message=message,
                            values=values)


class Diagnostics(SnapshotPublisher):
    """Keeps the latest snapshot's monitored answers; a timer publishes /diagnostics."""

    def __init__(self, node: Node, counts: RequestCounts) -> None:
        super().__init__(node)
        self.counts = counts
        self._lock = threading.Lock()  # publish() runs on the node's publishing worker
        self._pub = node.create_publisher(DiagnosticArray, "/diagnostics", DIAGNOSTICS_QOS)
        self._timer: Any = None
        self._rate = 0.0
        self._modes: list[str] = []
        self._answers: dict[str, Answer] = {}
        self._answers_version = 0
        #: Reported at start (a warning) and in every inputs status.
        self.unknown = unknown_start_parameters(node)
        if self.unknown:
            node.get_logger().warning(
                f"parameter(s) given at start that this node does not know, ignored (a "
                f"misspelling?): {self.unknown}; known parameters are listed in "
                "config/wrenchcone.yaml and docs/node.md")

    def modes(self) -> set[str]:
        return set(self._modes)

    def destroy(self) -> None:
        super().destroy()
        self.node.destroy_publisher(self._pub)

    def sync(self, values: dict[str, Any]) -> None:
        self._modes = sorted(values["modes"])
        rate = float(values["diagnostics_rate"])
        if rate != self._rate:
            if self._timer is not None:
                self.node.destroy_timer(self._timer)
                self._timer = None
            if rate > 0:
                # inactive: made stopped (the node's activate starts it)
                self._timer = self.node.create_timer(
                    1.0 / rate, self.publish_now,
                    autostart=bool(getattr(self.node, "active", True)))
            self._rate = rate

    def publish(self, snap: Snapshot, answers: dict[str, Answer],
                freshness: Freshness) -> None:
        with self._lock:  # when stale, answers is empty: each mode says STALE_INPUTS
            self._answers, self._answers_version = dict(answers), snap.version

    def array(self) -> DiagnosticArray:
        """The current DiagnosticArray (module docstring)."""
        name = self.node.get_fully_qualified_name()
        snap = self.node.snapshot
        fresh = self.node.freshness(snap)
        now = self.node.get_clock().now()
        msg = DiagnosticArray()
        msg.header.stamp = now.to_msg()
        msg.status = [input_status(name, snap, fresh, self.unknown, now.nanoseconds)]
        with self._lock:
            answers, version = self._answers, self._answers_version
        msg.status += [mode_status(name, m, answers.get(m), version, fresh)
                       for m in self._modes]
        msg.status.append(request_status(name, self.counts))
        for s in msg.status:
            s.hardware_id = name
        return msg

    def publish_now(self) -> None:
        try:
            self._pub.publish(self.array())
        except Exception as exc:  # noqa: BLE001 - diagnostics must never stop the node
            self.node.get_logger().error(f"publishing diagnostics failed: {exc!r}")
