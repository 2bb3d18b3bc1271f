# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A plain rclpy recorder that writes MCAP with the ``mcap`` library (``mcap-ros2-support``):
a writer independent of the loop's (``rosbags``), to check that ``wrenchcone replay``
reads what another tool wrote. Message definitions are assembled from the installed
``.msg`` files (ament index), as rosbag2 writes them (dependencies after a line of ``=``,
each headed ``MSG: pkg/Name``)."""

from __future__ import annotations

import importlib
import re
import sys
import threading
from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from mcap_ros2.writer import Writer
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

PRIMITIVES = {"bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16",
              "uint16", "int32", "uint32", "int64", "uint64", "string", "wstring"}


def _text(pkg: str, name: str) -> str:
    try:
        share = Path(get_package_share_directory(pkg))
    except LookupError:  # the PyPI wheels' interfaces: the venv's share/, not indexed
        share = Path(sys.prefix) / "share" / pkg
    return (share / "msg" / f"{name}.msg").read_text()


def _deps(pkg: str, text: str) -> list[tuple[str, str]]:
    out = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        words = line.split()
        if len(words) < 2 or "=" in words[1]:
            continue  # a constant
        base = re.sub(r"\[.*\]$", "", words[0]).split("<=")[0]
        if base in PRIMITIVES:
            continue
        p, n = base.split("/") if "/" in base else (pkg, base)
        out.append((p, n))
    return out


def message_definition(ros_type: str) -> str:
    """The full definition of "pkg/msg/Name" with its dependencies, rosbag2 style."""
    pkg, _, name = ros_type.split("/")
    main = _text(pkg, name)
    seen, order, todo = set(), [], _deps(pkg, main)
    while todo:
        dep = todo.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        order.append(dep)
        todo += _deps(dep[0], _text(*dep))
    parts = [main] + [f"{'=' * 80}\nMSG: {p}/{n}\n{_text(p, n)}" for p, n in order]
    return "\n".join(parts)


class PlainRecorder:
    """Subscribe with ``node`` to ``topics`` [(topic, "pkg/msg/Name")], write each message
    into the MCAP file ``path`` (log time: the node's clock)."""

    def __init__(self, node, path, topics) -> None:
        self.node = node
        self.file = open(path, "wb")
        self.writer = Writer(self.file)
        self.lock = threading.Lock()
        self.closed = False
        self.subs = []
        for topic, ros_type in topics:
            pkg, kind, name = ros_type.split("/")
            cls = getattr(importlib.import_module(f"{pkg}.{kind}"), name)
            schema = self.writer.register_msgdef(ros_type, message_definition(ros_type))
            qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
            if topic.endswith("fixels"):
                qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                 durability=DurabilityPolicy.TRANSIENT_LOCAL)
            # no QoS event handlers: close() destroys these subscriptions while an
            # executor spins the node, and rclpy's executor does not survive an event
            # handler destroyed under it (InvalidHandle)
            self.subs.append(node.create_subscription(
                cls, topic, lambda msg, t=topic, s=schema: self._write(t, s, msg), qos,
                event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False)))

    def _write(self, topic, schema, msg) -> None:
        with self.lock:
            if not self.closed:
                now = self.node.get_clock().now().nanoseconds
                self.writer.write_message(topic, schema, msg, log_time=now, publish_time=now)

    def close(self) -> None:
        with self.lock:
            self.closed = True
        for s in self.subs:
            self.node.destroy_subscription(s)
        self.writer.finish()
        self.file.close()
