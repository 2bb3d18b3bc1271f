"""Input subscriptions: ``workpiece_pose`` and ``fixels`` -> the input store.

Each input is checked: the frame, the size (``max_fixels``), the conversion
(wrenchcone_ros.ros.conversions: finite, in the coordinate limits, planar), the stamp order
(a message stamped earlier than the one in use is refused: the newest wins); then the
value with its header stamp and node-clock arrival time goes into the
:class:`~wrenchcone_ros.node.store.InputStore` and ``on_change()`` wakes the publishing
worker. The fixels are checked in their callback.

The pose is PULLED, not pushed (:class:`PoseInbox`): no executor runs a callback per
pose message. Its subscription (serialized, depth 1) lives on a hidden helper node that
no executor spins, so the middleware keeps only the newest message; whoever needs a
snapshot (a service request, the publishing worker) takes that message when it needs
it (:meth:`InputStore.current` calls :meth:`InputSubscriptions.pull_pose`), and the
store decodes and checks it then. The publishing worker sleeps in :meth:`PoseInbox.wait`
until a pose is waiting or something else changed. A 1 kHz stream thus costs no Python
work per message, and a service request never queues behind pose callbacks in the
executor nor waits for the GIL they take (docs/node.md, "Pulled pose"). The
arrival time of a pose is the node-clock time it is taken: at most one worker cycle
after it arrived. Only the newest pose of a burst is examined. No scene is built here;
the snapshot is built once per use (coalescing). A bad message is refused with one log
line (at once when the reason changes, at most every :data:`REFUSAL_LOG_PERIOD_S` while
it repeats) and leaves the inputs as they were; nothing here ever raises into the node.

QoS: :data:`INPUT_QOS` is BEST_EFFORT, VOLATILE, KEEP_LAST 1 (the sensor-data profile
with depth 1): it matches both reliable and best-effort publishers, and a burst never
queues (latest wins). Reliability, durability, history and depth can be overridden at
start (QoSOverridingOptions, declared on the node itself for both topics), e.g.
``-p "qos_overrides./fixels.subscription.reliability:=reliable"``.
"""

from __future__ import annotations

import re
import threading
import time
from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseArray, PoseStamped
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.guard_condition import GuardCondition
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions
from rclpy.serialization import deserialize_message

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.node import fastcheck, rclpy_boundary
from wrenchcone_ros.node.parameters import parameter_value
from wrenchcone_ros.node.store import InputStore, StampOrderError


def input_qos() -> QoSProfile:
    """A new copy of :data:`INPUT_QOS`: each subscription gets its own, because a QoS
    override (QoSOverridingOptions) changes the profile it is given in place."""
    return QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.BEST_EFFORT,
                      durability=DurabilityPolicy.VOLATILE)


#: Inputs: best effort (accepts reliable and best-effort publishers), depth 1.
INPUT_QOS = input_qos()
#: A refused input message of the same kind is logged at most once per this period (s).
REFUSAL_LOG_PERIOD_S = 5.0
#: A number in a refusal's text (a stamp, a coordinate): two refusals that differ only
#: in their numbers are of one kind.
_NUMBER = re.compile(r"[-+]?\d[\d.]*(?:[eE][-+]?\d+)?")


class PoseInbox:
    """The newest ``workpiece_pose`` message, waiting in the middleware to be taken.

    A serialized subscription on a hidden helper node ``_<node>_pose_inbox`` (same
    namespace and context, not added to any executor, no parameters or rosout), to the
    owner's resolved topic name (so the owner's remappings apply) with the owner's QoS
    overrides. With the compiled lane, every take goes through :attr:`lane`
    (fastcheck.py), which thus knows when the newest pose was received, and whose
    check_wrench thread takes poses too (it wakes a :meth:`wait` when it took one);
    without it (:class:`~.fastcheck.NoLane`) the inbox takes the pose itself.
    :meth:`take_newest` takes what is waiting (thread-safe); :meth:`wait` blocks (without
    the GIL) until a message is waiting, :meth:`wake` is called or the timeout passes.
    The same rclpy primitives as ``rclpy.wait_for_message``: a wait set of the
    subscription and a guard condition (rclpy_boundary.py; on an rclpy version it was not
    written for, the public fallback: a subscription callback in a thread of its own)."""

    def __init__(self, owner: Node, topic: str, qos: QoSProfile,
                 overrides: QoSOverridingOptions) -> None:
        name = owner.resolve_topic_name(topic)
        # what Node.create_subscription does for its QoS override parameters, on the owner
        rclpy_boundary.declare_qos_parameters(owner, name, PoseStamped, qos, overrides)
        self.node = Node(f"_{owner.get_name()}_pose_inbox", namespace=owner.get_namespace(),
                         context=owner.context, use_global_arguments=False,
                         start_parameter_services=False, enable_rosout=False)
        self._guard = GuardCondition(None, None, context=owner.context)
        self._closed = threading.Event()
        self._woken = threading.Event()  # the wake-up of the public fallback's wait
        self._clock = owner.get_clock()
        self._take_lock = threading.Lock()
        self._last_ns = -1
        #: Takes the poses (and answers check_wrench once the node serves it); a NoLane
        #: (false) when the node has no compiled lane
        self.lane = fastcheck.new_lane(owner)
        self._pushed: rclpy_boundary.PushedMessages | None = None
        self._wait: rclpy_boundary.SubscriptionWait | None = None
        if rclpy_boundary.accepted():
            self.subscription = self.node.create_subscription(
                PoseStamped, name, lambda _msg: None, qos, raw=True)
            self._wait = rclpy_boundary.SubscriptionWait(owner.context, self.subscription,
                                                         self._guard)
            if self.lane:
                self.lane.attach_poses(self.subscription, self._guard)
        else:
            self._pushed = rclpy_boundary.PushedMessages(self.node, PoseStamped, name, qos,
                                                         self._woken.set)
            self.subscription = self._pushed.subscription

    def take_newest(self) -> tuple[bytes, int] | None:
        """The newest waiting message (serialized) and when it was received (node clock,
        ns; strictly increasing from take to take), or None; older ones are dropped."""
        if self._closed.is_set():
            return None
        if self.lane:
            return self.lane.take_pose()
        with self._take_lock:
            data = None
            if self._pushed is not None:
                data = self._pushed.take()
            else:
                while (taken := rclpy_boundary.take_serialized(self.subscription)) is not None:
                    data = taken
            if data is None:
                return None
            received = max(self._clock.now().nanoseconds, self._last_ns + 1)
            self._last_ns = received  # strictly increasing: a stamp names one take
            return data, received

    def wait(self, timeout_s: float) -> None:
        """Block until a message is waiting, :meth:`wake` was called, or ``timeout_s``;
        after :meth:`close` (or a context shut down), only sleep ``timeout_s``."""
        if self._closed.is_set() or not self.node.context.ok():
            self._closed.wait(timeout_s)
            return
        if self._wait is not None:
            self._wait.wait(timeout_s)
            return
        self._woken.wait(timeout_s)
        self._woken.clear()

    def wake(self) -> None:
        """End a :meth:`wait` in progress (or the next one) at once."""
        self._woken.set()
        try:
            self._guard.trigger()
        except Exception:  # noqa: BLE001 - destroyed or shut down: nobody waits any more
            pass

    def close(self) -> None:
        """Stop taking (and the lane's service) and end any wait; then join the waiting
        thread and :meth:`destroy`."""
        self._closed.set()
        self.lane.close()
        self.wake()

    def destroy(self) -> None:
        self._closed.set()
        self.lane.close()  # before the subscription and guard it points to
        if self._pushed is not None:
            self._pushed.destroy()
        self._guard.destroy()
        self.node.destroy_node()


class InputSubscriptions:
    """The node's input topics; ``on_change(reason)`` is called after a stored input."""

    def __init__(self, node: Node, store: InputStore,
                 on_change: Callable[[], None]) -> None:
        self.node = node
        self.store = store
        self.on_change = on_change
        self._refusals: dict[str, tuple[str, float, int]] = {}
        self.group = MutuallyExclusiveCallbackGroup()
        overrides = QoSOverridingOptions.with_default_policies()
        # the pose is pulled (PoseInbox): taken serialized when a snapshot is needed,
        # decoded and checked by the store then
        self.pose_inbox = PoseInbox(node, "workpiece_pose", input_qos(), overrides)
        store.pull_pose = self.pull_pose
        store.decode_pose = self._decode_pose
        store.refuse_pose = lambda why: self.refuse("workpiece_pose", why)
        node.create_subscription(PoseArray, "fixels", self._on_fixels, input_qos(),
                                 callback_group=self.group, qos_overriding_options=overrides)

    def refuse(self, what: str, why: str) -> None:
        """Log a refused input: at once when the reason changes, else at most every 5 s."""
        now = time.monotonic()
        last = self._refusals.get(what)
        kind = _NUMBER.sub("#", why)  # the reason's gist, without its numbers
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

    def pull_pose(self) -> None:
        """Take the newest waiting pose message into the store (undecoded) and wake the
        worker; nothing when none is waiting. Never raises."""
        try:
            taken = self.pose_inbox.take_newest()
            if taken is None:
                return
            self.store.set_raw_pose(*taken)
            self.on_change()
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.node.get_logger().error(f"taking workpiece_pose failed: {exc!r}",
                                         throttle_duration_sec=5.0)

    def destroy(self) -> None:
        self.pose_inbox.destroy()

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
