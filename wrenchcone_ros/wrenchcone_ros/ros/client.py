# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Client library for controller authors: call the node's check_wrench, get_cone,
classify_wrench and force_directions.

As a library (your own node spins elsewhere, or not at all)::

    from wrenchcone_msgs.msg import Status
    from wrenchcone_ros.ros.client import ServiceUnavailable, WrenchConeClient
    client = WrenchConeClient(my_node)                     # node name /wrenchcone
    reply = client.check_wrench("na", (1.0, 0.0, -0.5))    # (fx N, fy N, tz N m)
    if reply.status == Status.OK and reply.consistent: ...
    cone = client.get_cone("na")                           # a ConeReply with numpy arrays
    F = cone.F                                             # consistent iff F @ g <= 0
    d = client.force_directions("arr")                     # a pull at the com (radians)
    for iv in d.intervals: iv.lo, iv.hi, iv.best         # point=(x, y): elsewhere

As a command (prints JSON)::

    python -m wrenchcone_ros.ros.client check na 1 0 -0.5
    python -m wrenchcone_ros.ros.client cone na
    python -m wrenchcone_ros.ros.client check na 0.1 -1 0 --classify
    python -m wrenchcone_ros.ros.client classify 0.1 -1 0
    python -m wrenchcone_ros.ros.client directions arr                 # a force at the com
    python -m wrenchcone_ros.ros.client directions arr --point 0.0075 0.035 --exclusive
    python -m wrenchcone_ros.ros.client check na 1 0 -0.5 --node /my_ns/wrenchcone --timeout 5

Each call first waits for its service to be offered, then for the reply, both within
the call's own ``timeout`` (s): the first call right after construction is not lost
(DDS discards a request sent before the server is discovered), and there is no need to
call :meth:`WrenchConeClient.wait_for_service` first. No reply in time raises
:class:`ServiceUnavailable` (a ``TimeoutError``) naming the service.

Calls block the calling thread, whether ``my_node`` is spun by an executor in another
thread or by nobody: the service clients live on a hidden helper node of the client's
own (``_<my_node>_wrenchcone_client_<k>``, same context and namespace), which each call
spins in a private executor until its reply arrives. The caller's node and executor are
never touched. Calls from several threads take turns (the wait for the turn counts in
the call's timeout). ``destroy()`` removes the helper node (or use the client as a
context manager).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from wrenchcone_ros.ros.conversions import planar_to_wrench, rows_from_flat
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, ForceDirections, GetCone

#: Status code -> name, from wrenchcone_msgs/msg/Status (one table for every interface).
STATUS = {getattr(Status, k): k for k in dir(Status)
          if k.isupper() and isinstance(getattr(Status, k), int)}
#: Default timeout (s) of every call: the wait for the service and for its reply.
DEFAULT_TIMEOUT_S = 10.0

#: The wrenchcone node a client calls by default: relative, resolved in the caller's
#: namespace (a controller in /cell1 calls /cell1/wrenchcone).
DEFAULT_SERVER = "wrenchcone"

#: Seconds between two looks at whether a service is offered, while a call waits for it.
SERVICE_POLL_S = 0.01


class ServiceUnavailable(TimeoutError):
    """No reply from a wrenchcone service within a call's timeout.

    Parameters
    ----------
    service : str
        The service's fully qualified name, e.g. ``/wrenchcone/check_wrench``.
    timeout : float
        The call's timeout (s).
    offered : bool
        Whether a server offered the service during the call (False: none was found,
        e.g. the node is not running, or runs in another ROS domain or namespace).

    Attributes
    ----------
    service, timeout, offered
        As given.
    """

    def __init__(self, service: str, timeout: float, offered: bool) -> None:
        self.service = service
        self.timeout = timeout
        self.offered = offered
        why = ("the server got the request but did not reply in time" if offered else
               "no server offers it (is the node running, in this ROS domain and "
               "namespace?)")
        super().__init__(f"no reply from {service} within {timeout} s: {why}")

    def __reduce__(self) -> tuple[Any, ...]:
        return type(self), (self.service, self.timeout, self.offered)


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"{self.prog}: error: {message}\n")


@dataclass(frozen=True)
class ConeReply:
    """A get_cone reply with the flattened arrays reshaped to (k, 3).

    Parameters
    ----------
    status : int
        A ``wrenchcone_msgs/msg/Status`` code.
    message : str
        What the node says about the answer (empty when nothing to say).
    feasible : bool
        Whether any wrench is consistent with the mode.
    F : numpy.ndarray
        Inequality rows, shape (k, 3): g = (fx N, fy N, tz N m) is in the cone iff
        ``F @ g <= 0`` and ``equalities @ g == 0``.
    equalities : numpy.ndarray
        Equality rows, shape (e, 3).
    G : numpy.ndarray
        Generators (rays), shape (r, 3).
    lineality : numpy.ndarray
        Lineality space basis, shape (l, 3).
    length_scale : float
        The scene's length scale (m) used to compare torques with forces.
    inputs_version : int
        The node's input snapshot the answer was computed from.
    pose_stamp : builtin_interfaces.msg.Time or None, optional
        The stamp of the pose the answer was computed at (None: not known).
    """

    status: int
    message: str
    feasible: bool
    F: np.ndarray
    equalities: np.ndarray
    G: np.ndarray
    lineality: np.ndarray
    length_scale: float
    inputs_version: int
    pose_stamp: Any = None

    def contains(self, g: Sequence[float], tol: float = 1e-9) -> bool:
        """Local membership test of a planar wrench.

        Parameters
        ----------
        g : sequence of float
            (fx N, fy N, tz N m), fixture frame, about the centre of mass.
        tol : float
            Relative tolerance (dimensionless, times the wrench's size with torques
            divided by ``length_scale``).

        Returns
        -------
        bool
            Whether ``g`` is in the cone; False for an infeasible mode or a reply whose
            status is not OK.
        """
        if self.status != Status.OK or not self.feasible:
            return False
        g = np.asarray(g, dtype=float)
        scale = max(float(np.linalg.norm(g * [1.0, 1.0, 1.0 / self.length_scale])), 1e-300)
        return bool(np.all(self.F @ g <= tol * scale)
                    and np.all(np.abs(self.equalities @ g) <= tol * scale))


_HELPERS = itertools.count()


class WrenchConeClient:
    """Blocking calls to a wrenchcone node's services.

    Parameters
    ----------
    node : rclpy.node.Node
        The caller's node: its context and namespace are used; it may be spun by an
        executor in another thread, or by nobody (it is never spun or touched here).
    server : str
        The wrenchcone node's name, resolved in ``node``'s namespace (default
        DEFAULT_SERVER, ``wrenchcone``: relative, so that a controller and a node started
        in the same namespace pair up; ``/wrenchcone`` for the root's).

    Attributes
    ----------
    node : rclpy.node.Node
        The caller's node.
    helper : rclpy.node.Node
        The hidden node that holds the service clients (see the module docstring).
    """

    def __init__(self, node: Node, server: str = DEFAULT_SERVER) -> None:
        self.node = node
        # the process's own remaps (launch's __node, __ns) are the caller's node's, not
        # the helper's: with them it would be a second node of the caller's name
        self.helper = Node(f"_{node.get_name()}_wrenchcone_client_{next(_HELPERS)}",
                           namespace=node.get_namespace(), context=node.context,
                           start_parameter_services=False, enable_rosout=False,
                           use_global_arguments=False)
        self._executor = SingleThreadedExecutor(context=node.context)
        self._executor.add_node(self.helper)
        self._lock = threading.Lock()  # one call spins the private executor at a time
        self._check = self.helper.create_client(CheckWrench, f"{server}/check_wrench")
        self._cone = self.helper.create_client(GetCone, f"{server}/get_cone")
        self._classify = self.helper.create_client(ClassifyWrench,
                                                   f"{server}/classify_wrench")
        self._directions = self.helper.create_client(ForceDirections,
                                                     f"{server}/force_directions")

    def wait_for_service(self, timeout: float = DEFAULT_TIMEOUT_S) -> bool:
        """Wait until every service the client calls is offered.

        Not needed before a call (each call waits for its own service); useful to check
        at start-up that the node is there.

        Parameters
        ----------
        timeout : float
            Seconds to wait in all, for check_wrench, get_cone, classify_wrench and
            force_directions.

        Returns
        -------
        bool
            True when all four are offered, False when ``timeout`` s passed first.
        """
        deadline = time.monotonic() + timeout
        return all(self._wait_offered(c, deadline)
                   for c in (self._check, self._cone, self._classify, self._directions))

    def destroy(self) -> None:
        """Remove the helper node and its executor (the client cannot call after this)."""
        self._executor.shutdown()
        self.helper.destroy_node()

    def __enter__(self) -> WrenchConeClient:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.destroy()

    @staticmethod
    def _wait_offered(client: Any, deadline: float) -> bool:
        while not client.service_is_ready():
            if time.monotonic() >= deadline or not client.context.ok():
                return client.service_is_ready()
            time.sleep(SERVICE_POLL_S)
        return True

    def _call(self, client: Any, request: Any, timeout: float) -> Any:
        """Wait for the service, send ``request``, wait for the reply: all within
        ``timeout`` s; raise ServiceUnavailable when any step runs out of time."""
        deadline = time.monotonic() + timeout
        if not self._lock.acquire(timeout=max(0.0, timeout)):
            raise ServiceUnavailable(client.srv_name, timeout, client.service_is_ready())
        try:
            if not self._wait_offered(client, deadline):
                raise ServiceUnavailable(client.srv_name, timeout, False)
            future = client.call_async(request)
            # spin_once, not spin_until_future_complete: rclpy's adds a done callback to
            # the future at every wake-up, each run as a task of this executor when the
            # reply comes, and the tasks this call did not run stay queued; in a process
            # that calls for minutes they pile up (thousands) and every later spin walks
            # them (test/ros/test_client.py). The reply is taken by this executor, so the
            # future is done when spin_once returns after it.
            while not future.done():
                left = deadline - time.monotonic()
                if left <= 0.0:
                    break
                self._executor.spin_once(timeout_sec=left)
            if not future.done():
                client.remove_pending_request(future)
                raise ServiceUnavailable(client.srv_name, timeout, True)
            return future.result()
        finally:
            self._lock.release()

    def check_wrench(self, mode: str, g: Sequence[float], timeout: float = DEFAULT_TIMEOUT_S,
                     classify: bool = False) -> CheckWrench.Response:
        """Is the planar wrench ``g`` consistent with ``mode``?

        Parameters
        ----------
        mode : str
            One letter per fixel (``a s l r n``; wildcards ``c``, ``*``).
        g : sequence of float
            (fx N, fy N, tz N m), fixture frame, about the centre of mass.
        timeout : float
            Seconds for the whole call (waiting for the service and the reply).
        classify : bool
            Also ask which other modes ``g`` is consistent with (``others``, a list of
            ``wrenchcone_msgs/ModeMatch``) and whether ``mode`` is the only one
            (``only_mode``).

        Returns
        -------
        wrenchcone_msgs.srv.CheckWrench.Response
            ``status`` (a ``wrenchcone_msgs/msg/Status`` code), ``consistent``,
            ``margin``, ``message``, ``inputs_version`` and the classification fields.

        Raises
        ------
        ServiceUnavailable
            No reply within ``timeout`` s.
        """
        req = CheckWrench.Request(mode=mode, wrench=planar_to_wrench(g), classify=classify)
        return self._call(self._check, req, timeout)

    def classify_wrench(self, g: Sequence[float], timeout: float = DEFAULT_TIMEOUT_S
                        ) -> ClassifyWrench.Response:
        """Every valid mode ``g`` is consistent with.

        Parameters
        ----------
        g : sequence of float
            (fx N, fy N, tz N m), fixture frame, about the centre of mass.
        timeout : float
            Seconds for the whole call.

        Returns
        -------
        wrenchcone_msgs.srv.ClassifyWrench.Response
            ``matches`` (a list of ``wrenchcone_msgs/ModeMatch``: mode, margin, certain,
            margin_all), best first; ``status``, ``message``.

        Raises
        ------
        ServiceUnavailable
            No reply within ``timeout`` s.
        """
        req = ClassifyWrench.Request(wrench=planar_to_wrench(g))
        return self._call(self._classify, req, timeout)

    def force_directions(self, mode: str, point: Sequence[float] | None = None,
                         exclusive: bool = False, timeout: float = DEFAULT_TIMEOUT_S
                         ) -> ForceDirections.Response:
        """Directions of a pure force consistent with ``mode``.

        Parameters
        ----------
        mode : str
            One letter per fixel.
        point : sequence of float, optional
            Where the force acts, (x, y) m in the workpiece frame; default the centre
            of mass.
        exclusive : bool
            Only directions consistent with ``mode`` and no other mode.
        timeout : float
            Seconds for the whole call.

        Returns
        -------
        wrenchcone_msgs.srv.ForceDirections.Response
            ``intervals`` (a list of ``wrenchcone_msgs/DirectionInterval``: ``lo``,
            ``hi`` in rad, fixture frame, counter-clockwise from +x, each with its
            ``best`` direction and ``margin``); ``status``, ``message``.

        Raises
        ------
        ServiceUnavailable
            No reply within ``timeout`` s.
        """
        req = ForceDirections.Request(mode=mode, exclusive=exclusive,
                                      use_point=point is not None)
        if point is not None:
            req.point.x, req.point.y = (float(v) for v in point)
        return self._call(self._directions, req, timeout)

    def get_cone(self, mode: str, timeout: float = DEFAULT_TIMEOUT_S) -> ConeReply:
        """The wrench cone of ``mode``.

        Parameters
        ----------
        mode : str
            One letter per fixel.
        timeout : float
            Seconds for the whole call.

        Returns
        -------
        ConeReply
            The reply with its arrays as numpy (k, 3) arrays.

        Raises
        ------
        ServiceUnavailable
            No reply within ``timeout`` s.
        """
        r = self._call(self._cone, GetCone.Request(mode=mode), timeout)
        return ConeReply(r.status, r.message, r.feasible, rows_from_flat(r.inequalities),
                         rows_from_flat(r.equalities), rows_from_flat(r.generators),
                         rows_from_flat(r.lineality), r.length_scale, r.inputs_version,
                         r.pose_stamp)


def _match(m: Any) -> dict[str, Any]:
    """A wrenchcone_msgs/ModeMatch as JSON: the same field names."""
    return {"mode": m.mode, "margin": m.margin, "certain": m.certain,
            "margin_all": m.margin_all}


def _main(argv: list[str] | None = None) -> int:
    ap = _Parser(prog="python -m wrenchcone_ros.ros.client",
                 description="Call a wrenchcone node and print JSON. Exit code 0: status "
                             "OK; 3: another status; 1: no reply; 2: bad arguments.")
    sub = ap.add_subparsers(dest="cmd", required=True, parser_class=_Parser)
    # a positional with nargs=3 and a tuple metavar breaks argparse's --help (ValueError)
    wrench_help = "the wrench: FX FY (N) TZ (N m), fixture frame, about the com"
    c = sub.add_parser("check", help="check_wrench MODE FX FY TZ")
    c.add_argument("mode")
    c.add_argument("wrench", nargs=3, type=float, metavar="F", help=wrench_help)
    c.add_argument("--classify", action="store_true", help="also report the other modes")
    g = sub.add_parser("cone", help="get_cone MODE")
    g.add_argument("mode")
    k = sub.add_parser("classify", help="classify_wrench FX FY TZ")
    k.add_argument("wrench", nargs=3, type=float, metavar="F", help=wrench_help)
    d = sub.add_parser("directions", aliases=["force_directions"],
                       help="force_directions MODE [--point X Y] [--exclusive]")
    d.add_argument("mode")
    d.add_argument("--point", nargs=2, type=float, metavar=("X", "Y"), default=None,
                   help="where the force acts (m, workpiece frame; default the com)")
    d.add_argument("--exclusive", action="store_true",
                   help="only directions consistent with no other mode")
    for p in (c, g, k, d):
        p.add_argument("--node", default=DEFAULT_SERVER,
                       help="server node, resolved in this program's namespace (default "
                       "%(default)s)")
        p.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S,
                       help="seconds per call (default %(default)s)")
    args = ap.parse_args(argv)
    if not all(math.isfinite(v) for v in getattr(args, "wrench", ())):
        ap.error(f"the wrench must be three finite numbers, got {args.wrench}")
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        ap.error(f"--timeout must be a positive number of seconds, got {args.timeout}")
    rclpy.init()
    node = Node("wrenchcone_client")
    client = None
    try:
        client = WrenchConeClient(node, args.node)  # each call waits for its service
        if args.cmd == "check":
            r = client.check_wrench(args.mode, args.wrench, args.timeout, args.classify)
            out = {"consistent": r.consistent, "margin": r.margin,
                   "status": STATUS.get(r.status, r.status), "message": r.message,
                   "inputs_version": r.inputs_version}
            if args.classify:
                out.update(only_mode=r.only_mode, others=[_match(m) for m in r.others])
        elif args.cmd == "classify":
            r = client.classify_wrench(args.wrench, args.timeout)
            out = {"status": STATUS.get(r.status, r.status), "message": r.message,
                   "matches": [_match(m) for m in r.matches],
                   "inputs_version": r.inputs_version}
            if r.uncertainty:
                out.update(uncertainty=r.uncertainty, guarantee=r.guarantee)
        elif args.cmd in ("directions", "force_directions"):
            r = client.force_directions(args.mode, args.point, args.exclusive, args.timeout)
            out = {"status": STATUS.get(r.status, r.status), "message": r.message,
                   "intervals": [{"lo": iv.lo, "hi": iv.hi, "best": iv.best,
                                  "margin": iv.margin} for iv in r.intervals],
                   "inputs_version": r.inputs_version}
        else:
            r = client.get_cone(args.mode, args.timeout)
            out = {"status": STATUS.get(r.status, r.status), "message": r.message,
                   "feasible": r.feasible, "F": r.F.tolist(),
                   "equalities": r.equalities.tolist(), "G": r.G.tolist(),
                   "lineality": r.lineality.tolist(), "length_scale": r.length_scale,
                   "inputs_version": r.inputs_version}
        print(json.dumps(out))
        return 0 if r.status == Status.OK else 3
    except ServiceUnavailable as exc:
        print(json.dumps({"error": str(exc), "service": exc.service}))
        return 1
    finally:
        if client is not None:
            client.destroy()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(_main())
