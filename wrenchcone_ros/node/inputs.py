"""Input subscriptions: ``workpiece_pose`` and ``fixels`` -> the input store.

Each input is checked: the frame, the size (``max_fixels``), the conversion
(wrenchcone_ros.conversions: finite, in the coordinate limits, planar), the stamp order
(a message stamped earlier than the one in use is refused: the newest wins); then the
value with its header stamp and node-clock arrival time goes into the
:class:`~wrenchcone_ros.node.store.InputStore` and ``on_change()`` wakes the publishing
worker. The fixels are checked in their callback. The pose is subscribed serialized
(``raw=True``): its callback only keeps the newest bytes and their arrival time, and the
store decodes and checks them when a snapshot is taken (:meth:`InputStore.set_raw_pose`),
so a 1 kHz stream costs one cheap callback per message and one decode per snapshot; only
the newest pose of a burst is examined. No scene is built here; the snapshot is built
once per use (coalescing). A bad message is refused with one
log line (at once when the reason changes, at most every :data:`REFUSAL_LOG_PERIOD_S`
while it repeats) and leaves the inputs as they were; no callback ever raises.

QoS: :data:`INPUT_QOS` is BEST_EFFORT, VOLATILE, KEEP_LAST 1 (the sensor-data profile
with depth 1): it matches both reliable and best-effort publishers, and a burst never
queues (latest wins). Reliability, durability, history and depth can be overridden at
start (QoSOverridingOptions), e.g. ``-p "qos_overrides./fixels.subscription.reliability:=reliable"``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseArray, PoseStamped
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions
from rclpy.serialization import deserialize_message

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.node.parameters import parameter_value
from wrenchcone_ros.node.store import InputStore, StampOrderError

#: Inputs: best effort (accepts reliable and best-effort publishers), depth 1.
INPUT_QOS = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                       reliability=ReliabilityPolicy.BEST_EFFORT,
                       durability=DurabilityPolicy.VOLATILE)
#: A refused input message of the same kind is logged at most once per this period.
REFUSAL_LOG_PERIOD_S = 5.0


class InputSubscriptions:
    """The node's input topics; ``on_change(reason)`` is called after a stored input."""

    def __init__(self, node: Node, store: InputStore,
                 on_change: Callable[[], None]) -> None:
        self.node = node
        self.store = store
        self.on_change = on_change
        self._refusals: dict[str, tuple[list[str], float, int]] = {}
        self.group = MutuallyExclusiveCallbackGroup()
        overrides = QoSOverridingOptions.with_default_policies()
        # the pose arrives serialized (raw) and is decoded only when a snapshot is taken
        # (InputStore.set_raw_pose): a 1 kHz stream costs one cheap callback per message
        store.decode_pose = self._decode_pose
        store.refuse_pose = lambda why: self.refuse("workpiece_pose", why)
        node.create_subscription(PoseStamped, "workpiece_pose", self._on_raw_pose,
                                 INPUT_QOS, callback_group=self.group,
                                 qos_overriding_options=overrides, raw=True)
        node.create_subscription(PoseArray, "fixels", self._on_fixels, INPUT_QOS,
                                 callback_group=self.group, qos_overriding_options=overrides)

    def refuse(self, what: str, why: str) -> None:
        """Log a refused input: at once when the reason changes, else at most every 5 s."""
        now = time.monotonic()
        last = self._refusals.get(what)
        kind = why.split(" ", 3)[:3]  # the reason's gist, without its numbers
        if last is not None and last[0] == kind and now - last[1] < REFUSAL_LOG_PERIOD_S:
            self._refusals[what] = (kind, last[1], last[2] + 1)
            return
        repeats = f" ({last[2]} similar refusal(s) not logged)" if last and last[2] else ""
        self._refusals[what] = (kind, now, 0)
        self.node.get_logger().warning(f"{what} message refused: {why}{repeats}")

    def _frame_ok(self, what: str, frame_id: str) -> bool:
        expected = parameter_value(self.node, "fixture_frame")
        if frame_id != expected:
            self.refuse(what, f"frame_id {frame_id[:64]!r} is not the fixture frame "
                              f"{expected!r} (parameter fixture_frame)")
            return False
        return True

    def _on_raw_pose(self, data: bytes) -> None:
        self.store.set_raw_pose(data, self.node.get_clock().now().nanoseconds)
        self.on_change()

    def _decode_pose(self, data: bytes) -> tuple[tuple[float, float, float],
                                                 tuple[int, int]] | None:
        """The pose and stamp of a serialized PoseStamped, or None (refusal logged)."""
        try:
            msg = deserialize_message(data, PoseStamped)
            if not self._frame_ok("workpiece_pose", msg.header.frame_id):
                return None
            pose = conv.pose_to_planar(msg.pose, parameter_value(self.node, "tilt_tolerance"))
            return pose, (msg.header.stamp.sec, msg.header.stamp.nanosec)
        except conv.ConversionError as exc:
            self.refuse("workpiece_pose", str(exc))
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"workpiece_pose handling failed: {exc!r}")
        return None

    def _on_fixels(self, msg: PoseArray) -> None:
        self._on_input("fixels", msg, self._fixels, self.store.set_fixels)

    def _fixels(self, msg: PoseArray) -> list[tuple[float, float]]:
        limit = parameter_value(self.node, "max_fixels")
        if len(msg.poses) > limit:
            raise conv.ConversionError(f"{len(msg.poses)} fixels is more than max_fixels "
                                       f"({limit})")
        return conv.fixels_from_pose_array(msg)

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
