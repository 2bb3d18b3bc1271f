# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ROS side of the test kit: an isolated context, the node spun in a thread, inputs.

Used by the pytest fixtures of :mod:`wrenchcone_ros.testing.plugin`, and usable without
pytest (a script, another test framework). Everything here is real: a real rclpy
context on its own DDS domain, the real :class:`~wrenchcone_ros.node.WrenchConeNode`,
real publishers and service calls.

What the kit shares with the closed loop of :mod:`wrenchcone_ros.sim` lives below both
and is importable from here by the same names: :func:`isolated_context` and
:data:`ISOLATED_DISCOVERY` (:mod:`wrenchcone_ros.ros.contexts`), :class:`ExecutorThread`
(:mod:`wrenchcone_ros.ros.spinning`), :data:`FIXELS_QOS` and :data:`POSE_QOS`
(:mod:`wrenchcone_ros.ros.qos`), :class:`NodeFactory`, :func:`make_node` and
:func:`scene_file` (:mod:`wrenchcone_ros.node.inprocess`).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import PoseStamped
from rclpy.context import Context
from rclpy.executors import Executor
from rclpy.node import Node

from wrenchcone_ros.node.inprocess import NodeFactory, make_node, scene_file  # noqa: F401
from wrenchcone_ros.ros.client import WrenchConeClient
from wrenchcone_ros.ros.contexts import ISOLATED_DISCOVERY, isolated_context  # noqa: F401
from wrenchcone_ros.ros.conversions import yaw_to_quaternion
from wrenchcone_ros.ros.qos import FIXELS_QOS, POSE_QOS
from wrenchcone_ros.ros.spinning import ExecutorThread  # noqa: F401
from wrenchcone_msgs.msg import Fixel, Fixels

#: Seconds a publisher waits for the node's subscription to be matched before it
#: publishes (a message sent before the match is lost, like a first service call).
MATCH_TIMEOUT_S = 10.0


class InputPublishers:
    """Publishers of the node's inputs, as the user's system has them.

    ``workpiece_pose`` (geometry_msgs/PoseStamped, :data:`POSE_QOS`) and ``fixels``
    (wrenchcone_msgs/Fixels, :data:`FIXELS_QOS`: latched), both relative to
    ``node``'s namespace, stamped with ``node``'s clock.

    Parameters
    ----------
    node : rclpy.node.Node
        The node that owns the publishers (need not be spun).
    frame : str
        The ``header.frame_id`` of every message (the node's ``fixture_frame``).
    """

    def __init__(self, node: Node, frame: str = "world") -> None:
        self.node = node
        self.frame = frame
        self.pose = node.create_publisher(PoseStamped, "workpiece_pose", POSE_QOS)
        self.fixels = node.create_publisher(Fixels, "fixels", FIXELS_QOS)

    def _stamp(self, msg: Any, stamp: tuple[int, int] | None) -> None:
        msg.header.frame_id = self.frame
        if stamp is None:
            msg.header.stamp = self.node.get_clock().now().to_msg()
        else:
            msg.header.stamp.sec, msg.header.stamp.nanosec = stamp

    @staticmethod
    def _wait_for_match(publisher: Any, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while publisher.get_subscription_count() == 0:
            if time.monotonic() >= deadline:
                raise TimeoutError(f"no subscription to {publisher.topic_name} matched "
                                   f"within {timeout} s (is the node running in this "
                                   "context and namespace?)")
            time.sleep(0.01)

    def publish_pose(self, x: float, y: float, theta: float, *,
                     stamp: tuple[int, int] | None = None,
                     timeout: float = MATCH_TIMEOUT_S) -> PoseStamped:
        """Publish the workpiece pose once the node's subscription is matched.

        Parameters
        ----------
        x, y : float
            Position of the workpiece frame in the fixture frame (m).
        theta : float
            Rotation about the fixture's z axis (rad, counter-clockwise).
        stamp : tuple of int, optional
            ``(sec, nanosec)``; default: now on the publishing node's clock.
        timeout : float
            Seconds to wait for a matched subscription.

        Returns
        -------
        geometry_msgs.msg.PoseStamped
            The message published.

        Raises
        ------
        TimeoutError
            No subscription matched within ``timeout`` s (nothing is published).
        """
        msg = PoseStamped()
        self._stamp(msg, stamp)
        msg.pose.position.x, msg.pose.position.y = float(x), float(y)
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = yaw_to_quaternion(float(theta))
        self._wait_for_match(self.pose, timeout)
        self.pose.publish(msg)
        return msg

    def publish_fixels(self, positions: Sequence[Sequence[float]],
                       radii: float | Sequence[float] = 0.0, *,
                       frictions: Sequence[float | None] | None = None,
                       stamp: tuple[int, int] | None = None) -> Fixels:
        """Publish the fixture (latched: a node that starts later gets it too).

        Parameters
        ----------
        positions : sequence of (x, y)
            Fixel centres in the fixture frame (m), in fixel order.
        radii : float or sequence of float, optional
            Pin radius (m) of every fixel, or one per fixel; 0: point fixels.
        frictions : sequence of float or None, optional
            Each fixel's friction coefficient, None where the node's ``friction``
            parameter applies (default: None for every fixel).
        stamp : tuple of int, optional
            ``(sec, nanosec)``; default: now on the publishing node's clock.

        Returns
        -------
        wrenchcone_msgs.msg.Fixels
            The message published.

        Raises
        ------
        ValueError
            ``radii`` or ``frictions`` of another length than ``positions``.
        """
        n = len(positions)
        radii = [radii] * n if isinstance(radii, (int, float)) else list(radii)
        frictions = [None] * n if frictions is None else list(frictions)
        if len(radii) != n or len(frictions) != n:
            raise ValueError(f"{n} positions but {len(radii)} radii and {len(frictions)} "
                             "frictions: give one per fixel (or one radius for all)")
        msg = Fixels()
        self._stamp(msg, stamp)
        for (x, y), r, mu in zip(positions, radii, frictions):
            f = Fixel(radius=float(r))
            f.position.x, f.position.y = float(x), float(y)
            f.friction = Fixel.FRICTION_UNSET if mu is None else float(mu)
            msg.fixels.append(f)
        self.fixels.publish(msg)
        return msg

    def wait_until_used(self, client: WrenchConeClient, msg: PoseStamped | Fixels,
                        timeout: float = MATCH_TIMEOUT_S) -> None:
        """Wait until the node answers from ``msg`` (a pose or fixels message published).

        A pose is published again every :data:`REPUBLISH_S` while waiting: the pose is
        sensor data (best effort), and a message sent while discovery is still matching
        the two sides may be lost (the same stamp twice is the same input to the node).

        Every reply of the node carries the stamps of the pose and fixels it was
        computed from; this asks (check_wrench with an empty mode: a cheap refusal that
        still says which inputs it saw) until the stamp is ``msg``'s.

        Parameters
        ----------
        client : WrenchConeClient
            A client of the node.
        msg : geometry_msgs.msg.PoseStamped or wrenchcone_msgs.msg.Fixels
            What :meth:`publish_pose` or :meth:`publish_fixels` returned.
        timeout : float
            Seconds to wait in all.

        Raises
        ------
        TimeoutError
            The node did not answer from ``msg`` within ``timeout`` s (e.g. it refused
            the message: see its log).
        """
        field = "pose_stamp" if isinstance(msg, PoseStamped) else "fixels_stamp"
        deadline = time.monotonic() + timeout
        next_publish = time.monotonic() + REPUBLISH_S
        while True:
            if isinstance(msg, PoseStamped) and time.monotonic() >= next_publish:
                self.pose.publish(msg)
                next_publish = time.monotonic() + REPUBLISH_S
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"the node did not answer from the {field[:-6]} stamped "
                                   f"{msg.header.stamp.sec}.{msg.header.stamp.nanosec:09d} "
                                   f"within {timeout} s")
            reply = client.check_wrench("", (0.0, 0.0, 0.0), timeout=remaining)
            if getattr(reply, field) == msg.header.stamp:
                return
            time.sleep(0.01)

    def destroy(self) -> None:
        """Remove both publishers."""
        self.node.destroy_publisher(self.pose)
        self.node.destroy_publisher(self.fixels)


class Spinner:
    """Spin a test's own nodes (the controller under test) in background threads.

    Calling it with a node spins that node in an executor of its own, on a thread, in the
    node's own context (one of the kit's contexts, so on the test's domain);
    :meth:`close` stops every executor (joining its thread) and destroys every node.
    """

    def __init__(self) -> None:
        self._made: list[tuple[Node, ExecutorThread]] = []

    def __call__(self, node: Node, *, executor: type[Executor] | None = None) -> Node:
        """Spin ``node`` in a background thread until :meth:`close`.

        Parameters
        ----------
        node : rclpy.node.Node
            The node; :meth:`close` destroys it.
        executor : type, optional
            The executor class, called as ``executor(context=node.context)`` (default
            ``SingleThreadedExecutor``).

        Returns
        -------
        rclpy.node.Node
            ``node``.
        """
        thread = ExecutorThread(node.context, executor, name=f"{node.get_name()}-executor")
        self._made.append((node, thread))
        thread.add_node(node)
        return node

    def close(self) -> None:
        """Stop every executor (joining its thread), then destroy its node.

        Raises
        ------
        RuntimeError
            An executor's thread had ended with an exception (a callback of the node
            raised), or did not stop (the first such error; everything is closed
            regardless).
        """
        errors: list[BaseException] = []
        made, self._made = self._made, []
        for node, thread in reversed(made):
            try:
                thread.stop()
            except RuntimeError as exc:
                errors.append(exc)
            finally:
                node.destroy_node()
        if errors:
            raise errors[0]


#: How often :meth:`InputPublishers.wait_until_used` publishes a pose again while it waits (s).
REPUBLISH_S = 0.2


def make_test_node(context: Context, name: str = "wrenchcone_test") -> Node:
    """A plain rclpy node for a test's own side (client, publishers), spun by nobody.

    Parameters
    ----------
    context : rclpy.context.Context
        The test's context.
    name : str
        The node's name.

    Returns
    -------
    rclpy.node.Node
        The node; destroy it with ``destroy_node()``.
    """
    return Node(name, context=context)


def make_client(node: Node, server: Node | str) -> WrenchConeClient:
    """A :class:`~wrenchcone_ros.ros.client.WrenchConeClient` of ``server``.

    Parameters
    ----------
    node : rclpy.node.Node
        The caller's node (spun by someone or not).
    server : rclpy.node.Node or str
        The wrenchcone node, or its fully qualified name.

    Returns
    -------
    WrenchConeClient
        The client; its first call waits for the service (no ``wait_for_service``
        needed).
    """
    name = server if isinstance(server, str) else server.get_fully_qualified_name()
    return WrenchConeClient(node, server=name)
