"""Client example for controller authors: call the node's check_wrench, get_cone,
classify_wrench and force_directions.

As a library (your own node spins elsewhere, or not at all)::

    from wrenchcone_ros.ros.client import WrenchConeClient
    client = WrenchConeClient(my_node)                     # node name /wrenchcone
    client.wait_for_service(timeout=10.0)                  # all four services
    reply = client.check_wrench("na", (1.0, 0.0, -0.5))    # (fx N, fy N, tz N m)
    if reply.status == reply.OK and reply.consistent: ...
    cone = client.get_cone("na")                           # a ConeReply with numpy arrays
    F = cone.F                                             # consistent iff F @ g <= 0
    d = client.force_directions("arr")                     # a pull at the com (radians)
    for lo, hi in zip(d.lo, d.hi): ...                     # point=(x, y): elsewhere

As a command (prints JSON)::

    python -m wrenchcone_ros.ros.client check na 1 0 -0.5
    python -m wrenchcone_ros.ros.client cone na
    python -m wrenchcone_ros.ros.client check na 0.1 -1 0 --classify
    python -m wrenchcone_ros.ros.client classify 0.1 -1 0
    python -m wrenchcone_ros.ros.client directions arr                 # a force at the com
    python -m wrenchcone_ros.ros.client directions arr --point 0.0075 0.035 --exclusive
    python -m wrenchcone_ros.ros.client check na 1 0 -0.5 --node /my_ns/wrenchcone --timeout 5

Calls block the calling thread until the reply arrives or ``timeout`` s pass, whether
``my_node`` is spun by an executor in another thread or by nobody: the service clients
live on a hidden helper node of the client's own (``_<my_node>_wrenchcone_client_<k>``,
same context and namespace), which each call spins in a private executor until its
reply arrives. The caller's node and executor are never touched. Calls from several
threads take turns. ``destroy()`` removes the helper node (or use the client as a
context manager).
"""

from __future__ import annotations

import argparse
import json
import math
import itertools
import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from wrenchcone_ros.ros.conversions import planar_to_wrench, rows_from_flat
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, ForceDirections, GetCone

STATUS = {getattr(CheckWrench.Response, k): k for k in (
    "OK", "MODE_INFEASIBLE", "INVALID_MODE", "MODE_NOT_ALLOWED", "INVALID_WRENCH",
    "NO_INPUTS", "SCENE_ERROR", "INTERNAL_ERROR", "STALE_INPUTS", "LIMIT_EXCEEDED")}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"{self.prog}: error: {message}\n")


@dataclass(frozen=True)
class ConeReply:
    """A get_cone reply with the flattened arrays reshaped to (k, 3)."""

    status: int
    message: str
    feasible: bool
    F: np.ndarray
    equalities: np.ndarray
    G: np.ndarray
    lineality: np.ndarray
    length_scale: float
    inputs_version: int

    def contains(self, g: Sequence[float], tol: float = 1e-9) -> bool:
        """Local membership test; False for an infeasible mode or a failed reply."""
        if self.status != Status.OK or not self.feasible:
            return False
        g = np.asarray(g, dtype=float)
        scale = max(float(np.linalg.norm(g * [1.0, 1.0, 1.0 / self.length_scale])), 1e-300)
        return bool(np.all(self.F @ g <= tol * scale)
                    and np.all(np.abs(self.equalities @ g) <= tol * scale))


_HELPERS = itertools.count()


class WrenchConeClient:
    """Blocking calls to a wrenchcone node's services, from ``node``'s context and
    namespace (``server``: the wrenchcone node's name, resolved there)."""

    def __init__(self, node: Node, server: str = "/wrenchcone") -> None:
        self.node = node
        #: The hidden helper node that holds the service clients (see the module doc).
        self.helper = Node(f"_{node.get_name()}_wrenchcone_client_{next(_HELPERS)}",
                           namespace=node.get_namespace(), context=node.context,
                           start_parameter_services=False, enable_rosout=False)
        self._executor = SingleThreadedExecutor(context=node.context)
        self._executor.add_node(self.helper)
        self._lock = threading.Lock()  # one call spins the private executor at a time
        self._check = self.helper.create_client(CheckWrench, f"{server}/check_wrench")
        self._cone = self.helper.create_client(GetCone, f"{server}/get_cone")
        self._classify = self.helper.create_client(ClassifyWrench,
                                                   f"{server}/classify_wrench")
        self._directions = self.helper.create_client(ForceDirections,
                                                     f"{server}/force_directions")

    def wait_for_service(self, timeout: float = 10.0) -> bool:
        """Wait until every service the client calls is available (check_wrench, get_cone,
        classify_wrench, force_directions), at most ``timeout`` s in all."""
        deadline = time.monotonic() + timeout
        return all(c.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic()))
                   for c in (self._check, self._cone, self._classify, self._directions))

    def destroy(self) -> None:
        """Remove the helper node and its executor (the client cannot call after this)."""
        self._executor.shutdown()
        self.helper.destroy_node()

    def __enter__(self) -> WrenchConeClient:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.destroy()

    def _call(self, client, request, timeout: float):
        with self._lock:
            future = client.call_async(request)
            self._executor.spin_until_future_complete(future, timeout_sec=timeout)
            if not future.done():
                client.remove_pending_request(future)
                raise TimeoutError(f"no reply from {client.srv_name} within {timeout} s")
            return future.result()

    def check_wrench(self, mode: str, g: Sequence[float], timeout: float = 10.0,
                     classify: bool = False) -> CheckWrench.Response:
        """Is the planar wrench g = (fx, fy, tz) consistent with ``mode``?

        ``classify=True`` also asks which other modes g is consistent with
        (``other_modes``, ``other_margins``) and whether ``mode`` is the only one.
        """
        req = CheckWrench.Request(mode=mode, wrench=planar_to_wrench(g), classify=classify)
        return self._call(self._check, req, timeout)

    def classify_wrench(self, g: Sequence[float], timeout: float = 10.0
                        ) -> ClassifyWrench.Response:
        """Every valid mode g is consistent with (``modes``, ``margins``, best first)."""
        req = ClassifyWrench.Request(wrench=planar_to_wrench(g))
        return self._call(self._classify, req, timeout)

    def force_directions(self, mode: str, point: Sequence[float] | None = None,
                         exclusive: bool = False, timeout: float = 10.0
                         ) -> ForceDirections.Response:
        """Directions (rad, fixture frame) of a pure force consistent with ``mode``: at the
        centre of mass, or at ``point`` (x, y m, workpiece frame). Intervals ``lo``,
        ``hi``, ``best``, ``margin``; ``exclusive``: with no other mode."""
        req = ForceDirections.Request(mode=mode, exclusive=exclusive,
                                      use_point=point is not None)
        if point is not None:
            req.point.x, req.point.y = (float(v) for v in point)
        return self._call(self._directions, req, timeout)

    def get_cone(self, mode: str, timeout: float = 10.0) -> ConeReply:
        r = self._call(self._cone, GetCone.Request(mode=mode), timeout)
        return ConeReply(r.status, r.message, r.feasible, rows_from_flat(r.inequalities),
                         rows_from_flat(r.equalities), rows_from_flat(r.generators),
                         rows_from_flat(r.lineality), r.length_scale, r.inputs_version)


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
        p.add_argument("--node", default="/wrenchcone", help="server node (default %(default)s)")
        p.add_argument("--timeout", type=float, default=10.0)
    args = ap.parse_args(argv)
    if not all(math.isfinite(v) for v in getattr(args, "wrench", ())):
        ap.error(f"the wrench must be three finite numbers, got {args.wrench}")
    if not (math.isfinite(args.timeout) and args.timeout > 0):
        ap.error(f"--timeout must be a positive number of seconds, got {args.timeout}")
    rclpy.init()
    node = Node("wrenchcone_client")
    client = None
    try:
        client = WrenchConeClient(node, args.node)
        if not client.wait_for_service(args.timeout):
            print(json.dumps({"error": f"no {args.node} services within {args.timeout} s"}))
            return 1
        if args.cmd == "check":
            r = client.check_wrench(args.mode, args.wrench, args.timeout, args.classify)
            out = {"consistent": r.consistent, "margin": r.margin,
                   "status": STATUS.get(r.status, r.status), "message": r.message,
                   "inputs_version": r.inputs_version}
            if args.classify:
                out.update(only_mode=r.only_mode, other_modes=dict(
                    zip(r.other_modes, r.other_margins)))
        elif args.cmd == "classify":
            r = client.classify_wrench(args.wrench, args.timeout)
            out = {"status": STATUS.get(r.status, r.status), "message": r.message,
                   "modes": dict(zip(r.modes, r.margins)),
                   "certain": [m for m, c in zip(r.modes, r.certain) if c],
                   "inputs_version": r.inputs_version}
            if r.uncertainty:  # margins in the "any" sets above, in the "all" cones here
                out.update(margins_all=dict(zip(r.modes, r.margins_all)),
                           uncertainty=r.uncertainty, guarantee=r.guarantee)
        elif args.cmd in ("directions", "force_directions"):
            r = client.force_directions(args.mode, args.point, args.exclusive, args.timeout)
            out = {"status": STATUS.get(r.status, r.status), "message": r.message,
                   "intervals": [{"lo": lo, "hi": hi, "best": b, "margin": m}
                                 for lo, hi, b, m in zip(r.lo, r.hi, r.best, r.margin)],
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
    except TimeoutError as exc:
        print(json.dumps({"error": str(exc)}))
        return 1
    finally:
        if client is not None:
            client.destroy()
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(_main())
