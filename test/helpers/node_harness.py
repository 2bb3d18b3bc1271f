# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Launch-free harness: the real node in-process, real DDS traffic, clean shutdown.

One rclpy context per test session (see conftest.py, which also isolates the run with its
own ROS_DOMAIN_ID and localhost-only discovery). Each test gets its own namespace, so
latched topics of one test never reach another. The node under test and a tester node
share one executor spun in a background thread; the test thread makes real service
calls (check_wrench, get_cone, the standard set_parameters), publishes real messages
and reads real subscriptions. Waits have generous deadlines that only guard against a
hang; no test asserts anything about time.
"""

from __future__ import annotations

import itertools
import os
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from geometry_msgs.msg import Pose, PoseArray, PoseStamped
from rcl_interfaces.srv import SetParameters, SetParametersAtomically
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_msgs.msg import Fixel, Fixels, WrenchCone
from wrenchcone_ros.node import CONE_QOS, WrenchConeNode
from wrenchcone_ros.node.executors import SpinThread
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, GetCone

DEADLINE_S = 30.0  # only a guard against hanging; never asserted on
#: The tester publishes inputs as most publishers do: reliable, depth 10 (the node's
#: best-effort subscription accepts them; test_node_live.py also uses best effort).
PUBLISHER_QOS = QoSProfile(depth=10)
#: Tests that are not about staleness switch it off (input_timeout 0): a loaded test
#: machine may take more than the default second between a publish and a check.
#: The paper's disc as the node's scene file (without one the node waits for inputs).
HARNESS_DEFAULTS = {"input_timeout": 0.0,
                    "scene_file": str(Path(__file__).resolve().parents[2] / "examples"
                                      / "paper_disc.yaml")}
#: Fixels are latched data: the node's default subscription is reliable, transient local.
FIXELS_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                        reliability=ReliabilityPolicy.RELIABLE)
_counter = itertools.count()


class Collector:
    """Messages of one subscription, with a wait for a condition on the latest."""

    def __init__(self) -> None:
        self.messages: list[Any] = []
        self._cond = threading.Condition()

    def __call__(self, msg: Any) -> None:
        with self._cond:
            self.messages.append(msg)
            self._cond.notify_all()

    def wait_for(self, predicate: Callable[[Any], bool], what: str, since: int = 0) -> Any:
        """The first message (in arrival order, old ones included, from index ``since``)
        satisfying predicate."""
        seen = since
        with self._cond:
            while True:
                for msg in self.messages[seen:]:
                    if predicate(msg):
                        return msg
                seen = len(self.messages)
                if not self._cond.wait(DEADLINE_S):
                    raise AssertionError(f"never received {what}; got {len(self.messages)} "
                                         f"message(s), last {self.messages[-1:]!r}")


def installed_program(name: str) -> Path:
    """``lib/wrenchcone_ros/<name>`` of the colcon install on AMENT_PREFIX_PATH."""
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        path = Path(prefix) / "lib" / "wrenchcone_ros" / name
        if path.exists():
            return path
    pytest.fail(f"no installed lib/wrenchcone_ros/{name} on AMENT_PREFIX_PATH; run colcon "
                "build (make build) and source install/setup.bash")


def pose_message(sec: int, frame: str = "world") -> PoseStamped:
    """A PoseStamped at the origin, identity orientation, stamped ``sec`` seconds."""
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.header.stamp.sec = sec
    msg.pose.orientation.w = 1.0
    return msg


class Harness:
    def __init__(self, context, parameters: dict[str, Any] | None = None,
                 cli_args: list[str] | None = None) -> None:
        # pid in the namespace too: two runs that drew the same ROS_DOMAIN_ID still
        # never share a topic or a service
        self.ns = f"/t{os.getpid()}_{next(_counter)}"
        # a test of a parameters file (cli_args) gets the file's values, not these
        values = {**(HARNESS_DEFAULTS if cli_args is None else {}), **(parameters or {})}
        overrides = [Parameter(k, value=v) for k, v in values.items()]
        # cli_args: node-specific command-line arguments, e.g. ["--ros-args",
        # "--params-file", path], parsed by rcl exactly as for `ros2 run ... --ros-args`
        self.node = WrenchConeNode(namespace=self.ns, context=context,
                                   parameter_overrides=overrides, cli_args=cli_args)
        self.tester = Node("tester", namespace=self.ns, context=context)
        base = f"{self.ns}/wrenchcone"
        self.check_cli = self.tester.create_client(CheckWrench, f"{base}/check_wrench")
        self.cone_cli = self.tester.create_client(GetCone, f"{base}/get_cone")
        self.classify_cli = self.tester.create_client(ClassifyWrench,
                                                      f"{base}/classify_wrench")
        self.param_cli = self.tester.create_client(SetParameters, f"{base}/set_parameters")
        self.atomic_cli = self.tester.create_client(SetParametersAtomically,
                                                    f"{base}/set_parameters_atomically")
        self.pose_pub = self.tester.create_publisher(PoseStamped, "workpiece_pose",
                                                     PUBLISHER_QOS)
        self.fixel_pub = self.tester.create_publisher(Fixels, "fixels", FIXELS_QOS)
        self.fixel_pose_pub = self.tester.create_publisher(PoseArray, "fixel_poses",
                                                           FIXELS_QOS)
        # spun as main() spins it (executors.make_executor)
        self.spinner = SpinThread([self.node, self.tester], self.node.get_logger(),
                                  "harness-fast-lane", context)
        for cli in (self.check_cli, self.cone_cli, self.classify_cli, self.param_cli,
                    self.atomic_cli):
            assert cli.wait_for_service(timeout_sec=DEADLINE_S), cli.srv_name

    def close(self) -> None:
        self.spinner.stop()
        self.tester.destroy_node()
        self.node.destroy_node()

    # --- calls --------------------------------------------------------------------
    def _call(self, client, request):
        done = threading.Event()
        future = client.call_async(request)
        future.add_done_callback(lambda _f: done.set())
        assert done.wait(DEADLINE_S), f"no reply from {client.srv_name}"
        return future.result()

    def check(self, mode: Any, g: Sequence[float] = (0.0, 0.0, 0.0),
              out_of_plane: Sequence[float] = (0.0, 0.0, 0.0),
              classify: bool = False) -> CheckWrench.Response:
        req = CheckWrench.Request()
        req.mode = mode
        req.classify = classify
        req.wrench.force.x, req.wrench.force.y, req.wrench.torque.z = (float(v) for v in g)
        (req.wrench.force.z, req.wrench.torque.x,
         req.wrench.torque.y) = (float(v) for v in out_of_plane)
        return self._call(self.check_cli, req)

    def classify(self, g: Sequence[float], out_of_plane: Sequence[float] = (0.0, 0.0, 0.0)
                 ) -> ClassifyWrench.Response:
        req = ClassifyWrench.Request()
        req.wrench.force.x, req.wrench.force.y, req.wrench.torque.z = (float(v) for v in g)
        (req.wrench.force.z, req.wrench.torque.x,
         req.wrench.torque.y) = (float(v) for v in out_of_plane)
        return self._call(self.classify_cli, req)

    def get_cone(self, mode: str) -> GetCone.Response:
        return self._call(self.cone_cli, GetCone.Request(mode=mode))

    def set_parameters(self, **values: Any) -> list:
        """Set parameters through the node's standard set_parameters service."""
        req = SetParameters.Request()
        req.parameters = [Parameter(k.replace("__", "."), value=v).to_parameter_msg()
                          for k, v in values.items()]
        return list(self._call(self.param_cli, req).results)

    def set_parameters_atomically(self, values: dict[str, Any]):
        """All or nothing, one validation and one rebuild (set_parameters_atomically)."""
        req = SetParametersAtomically.Request()
        req.parameters = [Parameter(k, value=v).to_parameter_msg() for k, v in values.items()]
        return self._call(self.atomic_cli, req).result

    # --- topics -------------------------------------------------------------------
    def subscribe_cone(self, mode: str) -> Collector:
        """~/cone/<mode> (wrenchcone_msgs/msg/WrenchCone, latched)."""
        return self.subscribe(WrenchCone, f"wrenchcone/cone/{mode}", CONE_QOS)

    def subscribe(self, msg_type: Any, topic: str, qos: Any) -> Collector:
        col = Collector()
        self.tester.create_subscription(msg_type, topic, col, qos)
        return col

    def publish_pose(self, x: float, y: float, theta: float, frame: str = "world",
                     stamp: tuple[int, int] = (0, 0), quaternion=None) -> None:
        msg = PoseStamped()
        msg.header.frame_id = frame
        msg.header.stamp.sec, msg.header.stamp.nanosec = stamp
        msg.pose.position.x, msg.pose.position.y = float(x), float(y)
        q = quaternion or conv.yaw_to_quaternion(theta)
        (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
         msg.pose.orientation.w) = q
        self.pose_pub.publish(msg)

    def publish_fixels(self, positions: Sequence[Sequence[float]], frame: str = "world",
                       stamp: tuple[int, int] = (0, 0),
                       radii: float | Sequence[float] = 0.0,
                       frictions: Sequence[float | None] | None = None,
                       publisher: Any = None) -> Fixels:
        """The fixture as a wrenchcone_msgs/Fixels on ``fixels`` (latched publisher, or
        ``publisher``): one radius (m) for all or one per fixel; friction None: unset."""
        n = len(positions)
        radii = [radii] * n if isinstance(radii, (int, float)) else list(radii)
        frictions = [None] * n if frictions is None else list(frictions)
        msg = Fixels()
        msg.header.frame_id = frame
        msg.header.stamp.sec, msg.header.stamp.nanosec = stamp
        for (x, y), r, mu in zip(positions, radii, frictions):
            f = Fixel(radius=float(r))
            f.position.x, f.position.y = float(x), float(y)
            if mu is not None:
                f.friction = float(mu)
            msg.fixels.append(f)
        (publisher or self.fixel_pub).publish(msg)
        return msg

    def publish_fixel_poses(self, positions: Sequence[Sequence[float]], frame: str = "world",
                            stamp: tuple[int, int] = (0, 0)) -> PoseArray:
        """Fixel positions only, as a geometry_msgs/PoseArray on ``fixel_poses``."""
        msg = PoseArray()
        msg.header.frame_id = frame
        msg.header.stamp.sec, msg.header.stamp.nanosec = stamp
        for x, y in positions:
            p = Pose()
            p.position.x, p.position.y = float(x), float(y)
            p.orientation.w = 1.0
            msg.poses.append(p)
        self.fixel_pose_pub.publish(msg)
        return msg

    def wait_version_above(self, version: int) -> int:
        """Wait (through get_cone replies) until the node has a newer input snapshot."""
        for _ in range(100000):
            v = self.get_cone("").inputs_version
            if v > version:
                return v
            done = threading.Event()
            done.wait(0.01)
        raise AssertionError(f"inputs_version never rose above {version}")


def published_rows(msg: WrenchCone) -> tuple[np.ndarray, np.ndarray, int | None]:
    """(F, E, None) of a published cone, or (no rows, no rows, status) when no wrench is
    consistent (an infeasible or invalid mode)."""
    rows = conv.message_rows(msg)
    if rows is None:
        return np.zeros((0, 3)), np.zeros((0, 3)), int(msg.status)
    return rows[0], rows[1], None


def same_rows(a: np.ndarray, b: np.ndarray, tol: float = 1e-9) -> bool:
    """Equal as sets of rows (order-free), within tol."""
    a, b = np.asarray(a, float).reshape(-1, 3), np.asarray(b, float).reshape(-1, 3)
    if a.shape != b.shape:
        return False
    used = set()
    for r in a:
        for j, s in enumerate(b):
            if j not in used and np.allclose(r, s, atol=tol, rtol=0):
                used.add(j)
                break
        else:
            return False
    return True


def no_cone(msg: WrenchCone, status: int) -> bool:
    """The message says "no wrench is consistent" with this status, and carries no rows."""
    return (msg.status == status and not msg.feasible and msg.message != ""
            and not (msg.inequalities or msg.equalities or msg.generators or msg.lineality))
