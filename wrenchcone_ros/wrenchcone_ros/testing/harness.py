# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ROS side of the test kit: an isolated context, the node spun in a thread, inputs.

Used by the pytest fixtures of :mod:`wrenchcone_ros.testing.plugin`, and usable without
pytest (a script, another test framework). Everything here is real: a real rclpy
context on its own DDS domain, the real :class:`~wrenchcone_ros.node.WrenchConeNode`,
real publishers and service calls.
"""

from __future__ import annotations

import inspect
import os
import threading
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import rclpy
import yaml
from geometry_msgs.msg import PoseStamped
from rclpy.context import Context
from rclpy.executors import Executor, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from wrenchcone_ros.core import Scene
from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.ros.client import WrenchConeClient
from wrenchcone_ros.ros.conversions import yaw_to_quaternion
from wrenchcone_ros.testing.domains import DomainLease, lease_domain
from wrenchcone_msgs.msg import Fixel, Fixels

#: Discovery settings for a test context: DDS discovery stays on this machine
#: (``ROS_AUTOMATIC_DISCOVERY_RANGE``) and contacts no configured peer
#: (``ROS_STATIC_PEERS``). Applied while the context is initialised, then restored.
ISOLATED_DISCOVERY = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_STATIC_PEERS": ""}
#: The ``fixels`` publisher's QoS: reliable, transient local, depth 1 (latched static
#: data, as a fixture description or nav2's map publishes it).
FIXELS_QOS = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                        reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: The ``workpiece_pose`` publisher's QoS: reliable, volatile, depth 10 (it reaches a
#: best-effort "sensor data" subscription as well as a reliable one).
POSE_QOS = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)
#: Seconds a publisher waits for the node's subscription to be matched before it
#: publishes (a message sent before the match is lost, like a first service call).
MATCH_TIMEOUT_S = 10.0


@contextmanager
def isolated_context(domain_id: int | None = None) -> Iterator[Context]:
    """An initialised rclpy context (one DDS participant) on a ROS domain of its own.

    Parameters
    ----------
    domain_id : int, optional
        The domain to join (one leased with :func:`~.domains.lease_domain`); default: a
        new lease, given back when the context is shut down.

    Yields
    ------
    rclpy.context.Context
        The context (``context.get_domain_id()`` is the domain id), with
        localhost-only discovery (:data:`ISOLATED_DISCOVERY`). It installs no signal
        handler (it is initialised with ``Context.init``, not ``rclpy.init``).

    Notes
    -----
    The context is shut down on exit; destroy the nodes made in it first. Two contexts
    on one domain are two DDS participants: their nodes meet through DDS discovery,
    as in two processes.
    """
    lease: DomainLease | None = lease_domain() if domain_id is None else None
    saved = {k: os.environ.get(k) for k in ISOLATED_DISCOVERY}
    context = Context()
    try:
        os.environ.update(ISOLATED_DISCOVERY)
        try:
            context.init(domain_id=lease.domain_id if lease else domain_id)
        finally:
            for key, value in saved.items():
                if value is None:
                    os.environ.pop(key, None)
                else:
                    os.environ[key] = value
        yield context
    finally:
        context.try_shutdown()
        if lease is not None:
            lease.release()


def scene_file(scene: str | os.PathLike | Scene, directory: Path) -> str:
    """The ``scene_file`` parameter value for ``scene``.

    Parameters
    ----------
    scene : str, os.PathLike or wrenchcone_ros.core.Scene
        A scene YAML file (absolute, or relative to the working directory), or a scene
        object, which is written to ``directory`` as YAML.
    directory : pathlib.Path
        Where a scene object is written.

    Returns
    -------
    str
        An absolute path.

    Raises
    ------
    FileNotFoundError
        No file at the given path.
    TypeError
        ``scene`` is neither a path nor a Scene.
    """
    if isinstance(scene, Scene):
        path = Path(directory) / f"scene_{id(scene):x}.yaml"
        path.write_text(yaml.safe_dump(scene.to_dict(), sort_keys=False))
        return str(path.resolve())
    if not isinstance(scene, (str, os.PathLike)):
        raise TypeError(f"scene: a path to a scene YAML file or a wrenchcone_ros.core.Scene, "
                        f"got {type(scene).__name__}")
    path = Path(scene).resolve()
    if not path.is_file():
        raise FileNotFoundError(f"scene file {str(scene)!r} not found (resolved to {path}; "
                                f"a relative path is taken from the working directory "
                                f"{os.getcwd()})")
    return str(path)


def make_node(context: Context, scene_path: str | None = None, *,
              parameters: Mapping[str, Any] | None = None, node_name: str = "wrenchcone",
              namespace: str = "") -> Node:
    """Construct the wrenchcone node in this process, as a user's program does.

    Parameters
    ----------
    context : rclpy.context.Context
        The context the node lives in.
    scene_path : str, optional
        Parameter ``scene_file``; None: no scene file (the node then waits for the
        ``workpiece_pose`` and ``fixels`` messages).
    parameters : mapping, optional
        Further parameter overrides, e.g. ``{"input_timeout": 0.0}`` (dotted names for
        nested parameters: ``"workpiece.mass"``).
    node_name, namespace : str
        The node's name and namespace.

    Returns
    -------
    wrenchcone_ros.node.WrenchConeNode
        The node, started: with a class that takes ``autostart`` (the managed node),
        configured and activated in its constructor.
    """
    cls = WrenchConeNode
    values = dict(parameters or {})
    if scene_path is not None:
        values["scene_file"] = scene_path
    kwargs: dict[str, Any] = {
        "namespace": namespace, "context": context,
        "parameter_overrides": [Parameter(k, value=v) for k, v in values.items()]}
    if "autostart" in inspect.signature(cls).parameters:
        kwargs["autostart"] = True
    return cls(node_name, **kwargs)


class ExecutorThread:
    """An rclpy executor spinning some nodes in a background thread.

    Parameters
    ----------
    context : rclpy.context.Context
        The nodes' context.
    executor : type, optional
        The executor class, called as ``executor(context=context)``; default
        ``SingleThreadedExecutor`` (a ``MultiThreadedExecutor`` works the same).
    name : str
        The thread's name.

    Attributes
    ----------
    executor : rclpy.executors.Executor
        The executor; add nodes with :meth:`add_node`.
    error : BaseException or None
        What ended the spinning thread early (an exception raised out of the executor:
        a callback's), or None.
    """

    def __init__(self, context: Context, executor: type[Executor] | None = None,
                 name: str = "wrenchcone-test-executor") -> None:
        self.executor = (executor or SingleThreadedExecutor)(context=context)
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._spin, name=name, daemon=True)
        self.thread.start()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except rclpy.executors.ExternalShutdownException:
            pass
        except BaseException as exc:  # noqa: BLE001 - reported by stop()
            self.error = exc

    def add_node(self, node: Node) -> None:
        """Spin ``node`` too (from now on).

        Parameters
        ----------
        node : rclpy.node.Node
            A node of the thread's context.
        """
        self.executor.add_node(node)

    def stop(self, timeout: float = 10.0) -> None:
        """Shut the executor down and join its thread.

        Parameters
        ----------
        timeout : float
            Seconds to wait for the thread.

        Raises
        ------
        RuntimeError
            The thread is still running after ``timeout`` s, or it had ended with an
            exception (chained).
        """
        self.executor.shutdown(timeout_sec=timeout)
        self.thread.join(timeout)
        if self.thread.is_alive():
            raise RuntimeError(f"the executor thread {self.thread.name} did not stop "
                               f"within {timeout} s")
        if self.error is not None:
            raise RuntimeError(f"the executor spinning the node raised "
                               f"{type(self.error).__name__}: {self.error}") from self.error


class NodeFactory:
    """Wrenchcone nodes in this process, each spun by its own executor in a thread.

    The nodes share one context of their own (one DDS participant) on ``domain_id``,
    made at the first :meth:`make`: a test's nodes, in another context, reach them
    through DDS discovery, as a controller in another process does.

    Parameters
    ----------
    domain_id : int
        The ROS domain (leased by the caller).
    directory : pathlib.Path
        Where scene objects are written as YAML files.
    """

    def __init__(self, domain_id: int, directory: Path) -> None:
        self.domain_id = domain_id
        self.directory = Path(directory)
        self._context_manager: Any = None
        self.context: Context | None = None
        self._made: list[tuple[Node, ExecutorThread]] = []

    def make(self, scene: str | os.PathLike | Scene | None = None, *,
             parameters: Mapping[str, Any] | None = None, node_name: str = "wrenchcone",
             namespace: str = "", executor: type[Executor] | None = None) -> Node:
        """Construct a started wrenchcone node and spin it in a background thread.

        Parameters
        ----------
        scene : str, os.PathLike, wrenchcone_ros.core.Scene or None
            Parameter ``scene_file`` (see :func:`scene_file`); None: no scene file.
        parameters : mapping, optional
            Further parameter overrides.
        node_name, namespace : str
            The node's name and namespace.
        executor : type, optional
            The executor class (default ``SingleThreadedExecutor``).

        Returns
        -------
        wrenchcone_ros.node.WrenchConeNode
            The node (see :func:`make_node`).
        """
        if self.context is None:
            self._context_manager = isolated_context(self.domain_id)
            self.context = self._context_manager.__enter__()
        path = None if scene is None else scene_file(scene, self.directory)
        node = make_node(self.context, path, parameters=parameters, node_name=node_name,
                         namespace=namespace)
        try:
            spinner = ExecutorThread(self.context, executor, name=f"{node_name}-test-executor")
        except BaseException:
            node.destroy_node()
            raise
        self._made.append((node, spinner))
        spinner.add_node(node)
        return node

    def close(self) -> None:
        """Stop every executor (joining its thread), destroy every node (which joins the
        node's own threads), then shut the context down.

        Raises
        ------
        RuntimeError
            An executor's thread had ended with an exception, or did not stop (the first
            such error; everything is closed regardless).
        """
        errors: list[BaseException] = []
        made, self._made = self._made, []
        for node, spinner in reversed(made):
            try:
                spinner.stop()
            except RuntimeError as exc:
                errors.append(exc)
            finally:
                node.destroy_node()
        if self._context_manager is not None:
            manager, self._context_manager, self.context = self._context_manager, None, None
            manager.__exit__(None, None, None)
        if errors:
            raise errors[0]


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
