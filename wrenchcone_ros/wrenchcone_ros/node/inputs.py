# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Input subscriptions: ``workpiece_pose``, ``fixels`` and ``fixel_poses`` -> the input store.

Both subscriptions are the node's own (remappable, listed under the node, in its
namespace). Each input is checked: the frame, the size (``max_fixels``), the conversion
(wrenchcone_ros.ros.conversions: finite, in the coordinate limits, planar), the stamp
order (a message stamped earlier than the one in use is refused: the newest wins; a jump
back by more than ``stamp_reset_threshold`` resets that input instead, see store.py);
then the value with its header stamp and node-clock arrival time goes into the
:class:`~wrenchcone_ros.node.store.InputStore` and ``on_change()`` wakes the publishing
worker.

The pose is pulled, not pushed (:class:`PoseSlot`): its subscription (raw, depth 1) is
the node's, in a callback group no executor takes a subscription from
(:class:`PulledGroup`), so the middleware keeps only the newest message and no executor
wakes up per pose; whoever needs a snapshot (a service request, the publishing worker)
takes that message then, and the store decodes and checks it. The publishing worker
sleeps in :meth:`PoseSlot.wait` (a wait set of the subscription, without the GIL) until a
pose is waiting or something else changed. A 1 kHz stream thus costs no Python work per
message, and only the newest pose of a burst is examined. (On an rclpy whose internals
this was not written for, rclpy_boundary.py says so and the pose is taken by an ordinary
callback that keeps the newest message.) A bad message is refused with one log line (at once when the reason
changes, at most every :data:`REFUSAL_LOG_PERIOD_S` while it repeats) and leaves the
inputs as they were; nothing here ever raises into the node.

QoS (the ROS conventions for such data): the pose is sensor data (:func:`pose_qos`:
best effort, volatile, keep last 1: it matches reliable and best-effort publishers and a
burst never queues); the fixture (``fixels``: wrenchcone_msgs/Fixels; ``fixel_poses``:
a PoseArray whose radii are parameter ``fixel_radius``'s) is static data published once
(:func:`fixels_qos`: reliable, transient local, keep last 1, like nav2's map), so a
fixture description published latched before the node starts arrives; a second,
volatile subscription of each fixture topic hears a publisher with the default QoS.
Every policy can be overridden at start (QoSOverridingOptions: history, depth,
reliability and durability), e.g.
``-p "qos_overrides./fixels.subscription.durability:=volatile"`` (the volatile twin:
``subscription_volatile``).
"""

from __future__ import annotations

import re
import threading
import time
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseArray, PoseStamped
from rclpy.callback_groups import CallbackGroup, MutuallyExclusiveCallbackGroup
from rclpy.guard_condition import GuardCondition
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSCompatibility,
    QoSProfile,
    ReliabilityPolicy,
    qos_check_compatible,
)
from rclpy.qos_overriding_options import QoSOverridingOptions, QoSPolicyKind
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.serialization import deserialize_message
from rclpy.subscription import Subscription
from wrenchcone_msgs.msg import Fixels

from wrenchcone_ros.node import rclpy_boundary
from wrenchcone_ros.core import Fixel
from wrenchcone_ros.node.parameters import FixelPositions, parameter_value
from wrenchcone_ros.node.store import InputStore, StampOrderError
from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.ros.qos import fixels_qos


def pose_qos() -> QoSProfile:
    """The pose's QoS: sensor data, depth 1 (a new copy: an override changes it in place)."""
    return QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.VOLATILE)


#: The pose's default QoS (for documentation and tests; each subscription gets a copy).
INPUT_QOS = pose_qos()
#: The QoS policies a user may override at start, for both input topics.
OVERRIDABLE_POLICIES = (QoSPolicyKind.HISTORY, QoSPolicyKind.DEPTH,
                        QoSPolicyKind.RELIABILITY, QoSPolicyKind.DURABILITY)
#: A refused input message of the same kind is logged at most once per this period (s).
REFUSAL_LOG_PERIOD_S = 5.0
#: Period, in seconds, of the check for ``workpiece_pose`` publishers whose QoS cannot
#: match the pulled subscription (the graph's publisher profiles; see InputSubscriptions).
QOS_CHECK_PERIOD_S = 2.0
#: The policy an rclpy ``qos_check_compatible`` reason is about, by its words (the same
#: names as a QoS event's ``last_policy_kind``).
_POLICY_WORDS = ((("best effort", "reliab"), "RELIABILITY"),
                 (("volatile", "transient", "durab"), "DURABILITY"),
                 (("lease",), "LIVELINESS_LEASE_DURATION"),
                 (("liveliness",), "LIVELINESS"), (("deadline",), "DEADLINE"))
#: A number in a refusal's text (a stamp, a coordinate): two refusals that differ only
#: in their numbers are of one kind.
_NUMBER = re.compile(r"[-+]?\d[\d.]*(?:[eE][-+]?\d+)?")


class PulledGroup(CallbackGroup):
    """A callback group from which no executor takes a subscription's messages (they are
    pulled: :class:`PoseSlot`); its other entities (the subscription's QoS event
    handlers) run as in a mutually exclusive group."""

    def __init__(self) -> None:
        super().__init__()
        self._lock = threading.Lock()
        self._running = False

    def can_execute(self, entity: Any) -> bool:
        return not isinstance(entity, Subscription) and not self._running

    def beginning_execution(self, entity: Any) -> bool:
        if isinstance(entity, Subscription):
            return False
        with self._lock:
            if self._running:
                return False
            self._running = True
            return True

    def ending_execution(self, entity: Any) -> None:
        with self._lock:
            self._running = False


class PoseSlot:
    """The newest ``workpiece_pose`` message, serialized, and when it was taken.

    Pulled (``subscription`` given and rclpy_boundary.pull_available()): the message
    waits in the middleware until :meth:`take_newest`; :meth:`wait` blocks on a wait set
    of the subscription and a guard condition. Pushed (the fallback): the subscription's
    callback :meth:`put` keeps it. :meth:`wake` ends a wait for another reason (fixels,
    parameters)."""

    def __init__(self, clock: Any, context: Any) -> None:
        self._clock = clock
        self._lock = threading.Lock()
        self._newest: tuple[bytes, int] | None = None
        self._last_ns = -1
        self._event = threading.Event()
        self._closed = threading.Event()
        self._guard = GuardCondition(None, None, context=context)
        self._wait: rclpy_boundary.SubscriptionWait | None = None
        self._subscription: Any = None
        self._context = context

    def pull_from(self, subscription: Any) -> None:
        """Take the messages of ``subscription`` (in a :class:`PulledGroup`) when asked."""
        self._subscription = subscription
        self._wait = rclpy_boundary.SubscriptionWait(self._context, subscription,
                                                     self._guard)

    def _received(self) -> int:
        received = max(self._clock.now().nanoseconds, self._last_ns + 1)
        self._last_ns = received  # strictly increasing: a stamp names one message
        return received

    def put(self, data: bytes) -> None:
        """The pushed fallback's callback: keep the newest message."""
        with self._lock:
            self._newest = (data, self._received())
        self.wake()

    def take_newest(self) -> tuple[bytes, int] | None:
        """The newest message and its node-clock arrival (ns), or None; older are gone."""
        if self._closed.is_set():
            return None
        with self._lock:
            if self._subscription is not None:
                data = None
                while (taken := rclpy_boundary.take_serialized(self._subscription)) \
                        is not None:
                    data = taken
                return None if data is None else (data, self._received())
            taken, self._newest = self._newest, None
        return taken

    def wait(self, timeout_s: float | None) -> None:
        """Block until a message is waiting or a :meth:`wake`, or ``timeout_s`` (s; None:
        no timeout)."""
        if self._closed.is_set():
            return
        if self._wait is not None and self._context.ok():
            self._wait.wait(timeout_s)
            return
        self._event.wait(timeout_s)  # wake() sets it
        self._event.clear()

    def wake(self) -> None:
        self._event.set()
        try:
            self._guard.trigger()
        except Exception:  # noqa: BLE001 - destroyed or shut down: nobody waits any more
            pass

    def close(self) -> None:
        self._closed.set()
        self.wake()

    def destroy(self) -> None:
        self.close()
        self._subscription = None
        self._guard.destroy()


class InputSubscriptions:
    """The node's input topics; ``on_change()`` is called after a stored input."""

    def __init__(self, node: Node, store: InputStore,
                 on_change: Callable[[], None]) -> None:
        self.node = node
        self.store = store
        self.on_change = on_change
        self._refusals: dict[str, tuple[str, float, int]] = {}
        self.group = MutuallyExclusiveCallbackGroup()
        self.pose_slot = PoseSlot(node.get_clock(), node.context)
        pulled = rclpy_boundary.pull_available()
        store.pull_pose = self.pull_pose
        store.decode_pose = self._decode_pose
        store.refuse_pose = lambda why: self.refuse("workpiece_pose", why)
        store.on_reset = self._log_reset
        store.on_fixture = lambda line: node.get_logger().info(line)
        store.on_refusal = lambda line: node.get_logger().warning(line)
        store.on_caveat = lambda caveat: node.get_logger().warning(f"workpiece: {caveat}")
        # pulled: no QoS event handler in an executor's wait set (the middleware signals
        # a subscription's events through the condition of its data, so the executor
        # would wake up whenever a pose waits untaken); the graph is checked instead
        self.pose_subscription = node.create_subscription(
            PoseStamped, "workpiece_pose", self.pose_slot.put, pose_qos(), raw=True,
            callback_group=PulledGroup() if pulled else self.group,
            qos_overriding_options=QoSOverridingOptions(OVERRIDABLE_POLICIES),
            event_callbacks=(SubscriptionEventCallbacks(use_default_callbacks=False)
                             if pulled else self._events("workpiece_pose")))
        self._qos_timer = None
        if pulled:
            self.pose_slot.pull_from(self.pose_subscription)
            self._warned_publishers: set[bytes] = set()
            self._qos_timer = node.create_timer(QOS_CHECK_PERIOD_S,
                                                self.check_pose_publishers,
                                                callback_group=self.group)
        self.fixture_subscriptions = [
            *self._fixture_pair(Fixels, "fixels", self._on_fixels),
            *self._fixture_pair(PoseArray, "fixel_poses", self._on_fixel_poses)]

    def _fixture_pair(self, msg_type: Any, topic: str, callback: Callable[[Any], None]
                      ) -> list[Subscription]:
        """Two subscriptions of one fixture topic: latched (:func:`fixels_qos`: a
        description published before the node started arrives) and volatile (reliable:
        ``ros2 topic pub`` and most code's default publisher, which the latched one cannot
        match). A latched publisher is heard by both; the store keeps one copy. The
        latched one does not warn about a publisher's durability (the volatile one hears
        that publisher)."""
        volatile = fixels_qos()
        volatile.durability = DurabilityPolicy.VOLATILE
        return [self.node.create_subscription(
            msg_type, topic, callback, qos, callback_group=self.group,
            qos_overriding_options=QoSOverridingOptions(OVERRIDABLE_POLICIES, entity_id=eid),
            event_callbacks=self._events(topic, ignore=ignore))
            for qos, eid, ignore in ((fixels_qos(), None, ("DURABILITY",)),
                                     (volatile, "volatile", ()))]

    def _events(self, topic: str, ignore: tuple[str, ...] = ()
                ) -> SubscriptionEventCallbacks:
        """Say so when a publisher's QoS cannot match the subscription's (nothing would
        ever arrive from it): e.g. a best-effort fixels publisher. A policy in ``ignore``
        is not reported (another subscription of the topic takes that publisher)."""
        def incompatible(event: Any) -> None:
            policy = getattr(event.last_policy_kind, "name", str(event.last_policy_kind))
            if policy not in ignore:
                self._warn_incompatible(topic, policy)
        return SubscriptionEventCallbacks(incompatible_qos=incompatible,
                                          use_default_callbacks=False)

    def _warn_incompatible(self, topic: str, policy: str) -> None:
        self.node.get_logger().warning(
            f"{topic}: a publisher's QoS is incompatible with this subscription's "
            f"(policy {policy}); its messages never arrive. Publish with a matching "
            f"QoS, or override this subscription's, e.g. -p "
            f"qos_overrides.{self.node.resolve_topic_name(topic)}.subscription."
            f"{policy.lower()}:=...", throttle_duration_sec=5.0)

    def check_pose_publishers(self) -> list[str]:
        """Warn once per publisher of ``workpiece_pose`` whose QoS cannot match the
        pulled subscription's (rclpy's ``qos_check_compatible`` on the graph's
        publisher profiles); returns the policies of the new warnings."""
        policies = []
        try:
            topic = self.pose_subscription.topic_name
            mine = self.pose_subscription.qos_profile
            for info in self.node.get_publishers_info_by_topic(topic):
                gid = bytes(info.endpoint_gid)
                if gid in self._warned_publishers:
                    continue
                compatibility, reason = qos_check_compatible(info.qos_profile, mine)
                if compatibility != QoSCompatibility.ERROR:
                    continue
                self._warned_publishers.add(gid)
                policy = next((name for words, name in _POLICY_WORDS
                               if any(w in reason.lower() for w in words)), reason)
                policies.append(policy)
                self._warn_incompatible("workpiece_pose", policy)
        except Exception as exc:  # noqa: BLE001 - a graph query must not hurt the node
            self.node.get_logger().debug(f"workpiece_pose QoS check failed: {exc!r}")
        return policies

    def refuse(self, what: str, why: str) -> None:
        """Log a refused input: at once when the reason changes, else at most every 5 s."""
        if what in ("fixels", "fixel_poses"):
            self.store.fixture_refusal = f"{what}: {why}"
            self.store.touch()
        now = time.monotonic()
        last = self._refusals.get(what)
        kind = _NUMBER.sub("#", why)  # the reason's gist, without its numbers
        if last is not None and last[0] == kind and now - last[1] < REFUSAL_LOG_PERIOD_S:
            self._refusals[what] = (kind, last[1], last[2] + 1)
            return
        repeats = f" ({last[2]} similar refusal(s) not logged)" if last and last[2] else ""
        self._refusals[what] = (kind, now, 0)
        self.node.get_logger().warning(f"{what} message refused: {why}{repeats}")

    def _log_reset(self, what: str, why: str) -> None:
        self.node.get_logger().info(f"{what}: {why}")

    def _frame_ok(self, what: str, frame_id: str) -> bool:
        expected = parameter_value(self.node, "fixture_frame")
        if frame_id != expected:
            self.refuse(what, f"frame_id {frame_id[:64]!r} is not the fixture frame "
                              f"{expected!r} (parameter fixture_frame)")
            return False
        return True

    def pull_pose(self) -> None:
        """Take the newest waiting pose message into the store (undecoded) and wake the
        worker; nothing when none is waiting. Never raises."""
        try:
            taken = self.pose_slot.take_newest()
            if taken is not None:
                self.store.set_raw_pose(*taken)
                self.on_change()  # a request took it: the worker publishes it too
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"taking workpiece_pose failed: {exc!r}",
                                         throttle_duration_sec=5.0)

    def destroy(self) -> None:
        if self._qos_timer is not None:
            self.node.destroy_timer(self._qos_timer)
        self.pose_slot.close()
        self.node.destroy_subscription(self.pose_subscription)
        self.pose_slot.destroy()
        for subscription in self.fixture_subscriptions:
            self.node.destroy_subscription(subscription)

    def _decode_pose(self, data: bytes) -> tuple[tuple[float, float, float],
                                                 tuple[int, int]] | None:
        """The pose and stamp of a serialized PoseStamped, or None (refusal logged)."""
        try:
            fields = conv.pose_stamped_fields(data)  # None: not plain CDR, use rclpy's
            if fields is None:
                msg = deserialize_message(data, PoseStamped)
                p, q = msg.pose.position, msg.pose.orientation
                fields = (msg.header.frame_id, (msg.header.stamp.sec,
                                                msg.header.stamp.nanosec),
                          (p.x, p.y, p.z, q.x, q.y, q.z, q.w))
            frame_id, stamp, values = fields
            if not self._frame_ok("workpiece_pose", frame_id):
                return None
            return conv.planar_pose(values, parameter_value(self.node, "tilt_tolerance")), stamp
        except conv.ConversionError as exc:
            self.refuse("workpiece_pose", str(exc))
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"workpiece_pose handling failed: {exc!r}")
        return None

    def _on_fixels(self, msg: Fixels) -> None:
        self._on_input("fixels", msg, self._fixels, self._store_fixture("fixels"))

    def _on_fixel_poses(self, msg: PoseArray) -> None:
        self._on_input("fixel_poses", msg, self._fixel_poses,
                       self._store_fixture("fixel_poses"))

    def _store_fixture(self, topic: str) -> Callable[..., None]:
        def store(value: Any, stamp: tuple[int, int], received_ns: int) -> None:
            self.store.set_fixels(value, stamp, received_ns, topic)
        return store

    def _count_ok(self, n: int) -> None:
        limit = parameter_value(self.node, "max_fixels")
        if n > limit:
            raise conv.ConversionError(f"{n} fixels is more than max_fixels ({limit})")

    def _fixels(self, msg: Fixels) -> tuple[Fixel, ...]:
        self._count_ok(len(msg.fixels))
        return conv.fixels_from_message(msg)

    def _fixel_poses(self, msg: PoseArray) -> FixelPositions:
        """Positions only: checked now against parameter fixel_radius (no radius, or a
        count that does not fit, refuses the message); the radii are applied when a scene
        is built, so a later fixel_radius applies too."""
        self._count_ok(len(msg.poses))
        fixels = conv.fixels_from_pose_array(msg, parameter_value(self.node, "fixel_radius")
                                             or [])
        return FixelPositions(tuple(f.position for f in fixels))

    def _on_input(self, topic: str, msg: Any, convert, store) -> None:
        """Check the frame, convert, store the value with its stamp and arrival time and
        wake the worker; refuse (with a reason) instead of ever raising."""
        try:
            if not self._frame_ok(topic, msg.header.frame_id):
                return
            value = convert(msg)
            received = self.node.get_clock().now().nanoseconds
            store(value, (msg.header.stamp.sec, msg.header.stamp.nanosec), received)
            self.on_change()
        except (conv.ConversionError, StampOrderError) as exc:
            self.refuse(topic, str(exc))
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"{topic} handling failed: {exc!r}")
