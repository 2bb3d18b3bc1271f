"""Input subscriptions: ``workpiece_pose`` and ``fixels`` -> the input store.

Each callback checks the frame, converts the message (wrenchcone_ros.conversions),
stores the value with its header stamp, and asks the node for a new snapshot. A bad
message is refused with one log line (at once when the reason changes, at most every
:data:`REFUSAL_LOG_PERIOD_S` while it repeats) and leaves the snapshot as it was; no
callback ever raises.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseArray, PoseStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.node.parameters import parameter_value
from wrenchcone_ros.node.store import InputStore

#: Inputs: the ROS default (reliable, volatile, depth 10).
INPUT_QOS = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST,
                       reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)
#: A refused input message of the same kind is logged at most once per this period.
REFUSAL_LOG_PERIOD_S = 5.0


class InputSubscriptions:
    """The node's input topics; ``on_change(reason)`` is called after a stored input."""

    def __init__(self, node: Node, store: InputStore,
                 on_change: Callable[[str], None]) -> None:
        self.node = node
        self.store = store
        self.on_change = on_change
        self._refusals: dict[str, tuple[list[str], float, int]] = {}
        node.create_subscription(PoseStamped, "workpiece_pose", self._on_pose, INPUT_QOS)
        node.create_subscription(PoseArray, "fixels", self._on_fixels, INPUT_QOS)

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
            self.refuse(what, f"frame_id {frame_id!r} is not the fixture frame "
                              f"{expected!r} (parameter fixture_frame)")
            return False
        return True

    def _on_pose(self, msg: PoseStamped) -> None:
        self._on_input("workpiece_pose", msg, lambda m: conv.pose_to_planar(
            m.pose, parameter_value(self.node, "tilt_tolerance")), self.store.set_pose,
            "pose")

    def _on_fixels(self, msg: PoseArray) -> None:
        self._on_input("fixels", msg, conv.fixels_from_pose_array, self.store.set_fixels,
                       "fixels")

    def _on_input(self, topic: str, msg: Any, convert, store, reason: str) -> None:
        """Check the frame, convert, store the value with its stamp and rebuild the
        snapshot; refuse (with a reason) instead of ever raising."""
        try:
            if not self._frame_ok(topic, msg.header.frame_id):
                return
            value = convert(msg)
            store(value, (msg.header.stamp.sec, msg.header.stamp.nanosec))
            self.on_change(reason)
        except conv.ConversionError as exc:
            self.refuse(topic, str(exc))
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"{topic} handling failed: {exc!r}")
