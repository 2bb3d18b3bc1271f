# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Per-snapshot publishers: everything the node publishes when its inputs change.

A publisher is a :class:`SnapshotPublisher`: it says which modes it needs
(:meth:`~SnapshotPublisher.modes`), follows parameter changes
(:meth:`~SnapshotPublisher.sync`) and publishes one snapshot given the answers of the
monitored modes and the inputs' freshness (:meth:`~SnapshotPublisher.publish`). The
node's publishing worker (one thread, coalescing: it always takes the newest snapshot,
never one per message) computes those answers once per snapshot
(:func:`wrenchcone_ros.node.answers.monitored_answers`) and hands the same dict to every
publisher in ``WrenchConeNode.snapshot_publishers``; to add a topic, add a class here and
append an instance there. ``publish`` runs on the worker thread, ``sync`` on an executor
thread: guard shared state (ConePublishers holds a lock).

Lazy publishing: a cone topic with no subscriber is not built or published for a
snapshot (at a 1 kHz pose stream the messages cost more than the cones); the snapshot is
kept as pending, and published as soon as a subscriber appears: the publisher's
``matched`` event (:func:`on_new_subscriber`) says so, no timer polls for it, so an idle
node does not wake up. A late subscriber may first receive the topic's previous latched
message (its header stamp and inputs_version say which inputs it is from), then the
current one. The markers do the same. Nothing is published while the node is not active
(the worker publishes the newest snapshot when it is activated).

Staleness: when the inputs are older than their timeout, ``freshness.stale`` is set and
``answers`` is empty (no cone is vouched for); the cone topics then publish status
STALE_INPUTS with no rows, once, until fresh inputs arrive.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from rclpy.event_handler import PublisherEventCallbacks
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from wrenchcone_ros.ros import conversions as conv
from wrenchcone_msgs.msg import WrenchCone
from wrenchcone_ros.node.status import OK, STALE_INPUTS, STATUS_NAMES
from wrenchcone_ros.node.answers import Answer, uncertainty_text
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.store import Snapshot

#: Latched cone topics: a late subscriber gets the last published cone at once.
CONE_QOS = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


class SnapshotPublisher:
    """Base of the per-snapshot publishers (see the module docstring)."""

    def __init__(self, node: Node) -> None:
        self.node = node

    def modes(self) -> set[str]:
        """The modes whose answers :meth:`publish` needs."""
        return set()

    def sync(self, values: dict[str, Any]) -> None:
        """Follow the node's parameter values (create / destroy topics)."""

    def publish(self, snap: Snapshot, answers: dict[str, Answer],
                freshness: Freshness) -> None:
        """Publish what this snapshot says; must not raise (log and carry on)."""

    def destroy(self) -> None:
        """Destroy this publisher's ROS entities (lifecycle cleanup, node end)."""
        timer = getattr(self, "_timer", None)
        if timer is not None:
            self.node.destroy_timer(timer)
            self._timer = None


def on_new_subscriber(node: Node, catch_up: Callable[[], None]) -> PublisherEventCallbacks:
    """A publisher's event callbacks that call ``catch_up()`` when a subscriber has
    matched it while the node is active (rclpy's default callbacks for the other
    events).

    Parameters
    ----------
    node : rclpy.node.Node
        The node (its ``active`` attribute, if it has one, gates the call).
    catch_up : callable
        Publishes what is pending.

    Returns
    -------
    rclpy.event_handler.PublisherEventCallbacks
        For ``create_publisher(..., event_callbacks=...)``.
    """
    def matched(info: Any) -> None:
        if info.current_count_change > 0 and getattr(node, "active", True):
            catch_up()
    return PublisherEventCallbacks(matched=matched)


def snapshot_stamp(snap: Snapshot) -> tuple[int, int] | None:
    """The stamp of the newest input a snapshot was built from (None: the scene's own)."""
    return conv.newest_stamp(snap.pose_stamp, snap.fixels_stamp)


class ConePublishers(SnapshotPublisher):
    """``~/cone/<mode>`` (wrenchcone_msgs/msg/WrenchCone, latched) for every mode of the
    ``modes`` parameter: header (newest input stamp, fixture frame), status, message,
    inputs_version and the rows; a mode that is not valid has its status and no rows;
    uncertainty and guarantee: the uncertainty set the answer was computed for and its
    guarantee (empty: the nominal model; answers.py)."""

    def __init__(self, node: Node) -> None:
        super().__init__(node)
        self._pubs: dict[str, Any] = {}
        self._reported: dict[str, tuple[int, str]] = {}
        #: mode -> (snapshot, answer, freshness) not published for want of a subscriber
        self._pending: dict[str, tuple[Snapshot, Answer | None, Freshness]] = {}
        # publish() runs on the publishing worker, sync() and the matched events on the
        # executor
        self._lock = threading.Lock()

    def modes(self) -> set[str]:
        return set(self._pubs)

    def destroy(self) -> None:
        super().destroy()
        with self._lock:
            for pub in self._pubs.values():
                self.node.destroy_publisher(pub)
            self._pubs.clear()
            self._pending.clear()

    def sync(self, values: dict[str, Any]) -> None:
        wanted = set(values["modes"])
        with self._lock:
            for mode in list(self._pubs):
                if mode not in wanted:
                    self.node.destroy_publisher(self._pubs.pop(mode))
                    self._reported.pop(mode, None)
                    self._pending.pop(mode, None)
            for mode in sorted(wanted - set(self._pubs)):
                self._pubs[mode] = self.node.create_publisher(
                    WrenchCone, f"~/cone/{mode}", CONE_QOS,
                    event_callbacks=on_new_subscriber(self.node, self._catch_up))

    def publish(self, snap: Snapshot, answers: dict[str, Answer],
                freshness: Freshness) -> None:
        with self._lock:
            for mode, pub in list(self._pubs.items()):
                ans = answers.get(mode)
                if not freshness.stale and ans is not None:
                    self._report(mode, ans)
                if pub.get_subscription_count() > 0:
                    self._pending.pop(mode, None)
                    self._publish_one(mode, pub, snap, ans, freshness)
                else:  # nobody listens: build nothing now, catch up when someone does
                    self._pending[mode] = (snap, ans, freshness)

    def _catch_up(self) -> None:
        with self._lock:
            for mode in list(self._pending):
                pub = self._pubs.get(mode)
                if pub is not None and pub.get_subscription_count() > 0:
                    self._publish_one(mode, pub, *self._pending.pop(mode))

    def _publish_one(self, mode: str, pub: Any, snap: Snapshot, ans: Answer | None,
                     freshness: Freshness) -> None:
        try:
            stamp = snapshot_stamp(snap)
            if freshness.stale or ans is None:  # no cone is vouched for: no rows
                msg = conv.cone_message(mode, STALE_INPUTS, freshness.stale or
                                        "not computed", None, frame_id=snap.frame_id,
                                        stamp=stamp, inputs_version=snap.version)
                msg.uncertainty = uncertainty_text(snap.uncertainty)
            else:
                msg = conv.cone_message(mode, ans.status, ans.message, ans.cone,
                                        frame_id=snap.frame_id, stamp=stamp,
                                        inputs_version=snap.version)
                msg.uncertainty, msg.guarantee = ans.uncertainty, ans.guarantee
            msg.pose_source, msg.fixels_source = snap.pose_source, snap.fixels_source
            pub.publish(msg)
        except Exception as exc:  # noqa: BLE001 - keep serving the other modes
            self.node.get_logger().error(f"publishing cone of {mode!r} failed: {exc!r}")

    def _report(self, mode: str, ans: Answer) -> None:
        """Log a monitored mode's state when it changes (not on every update)."""
        key = (ans.status, ans.message if ans.status != OK else "")
        previous = self._reported.get(mode)
        if previous is not None and previous[0] == ans.status:
            return
        self._reported[mode] = key
        if ans.status == OK:
            if previous is not None:
                self.node.get_logger().info(f"mode {mode!r} is valid again")
        else:
            self.node.get_logger().warning(
                f"mode {mode!r}: {STATUS_NAMES[ans.status]}: {ans.message} (published with "
                "this status and no rows until it changes; reported once)")
