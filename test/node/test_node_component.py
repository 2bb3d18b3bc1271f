# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node as a ROS 2 component: its endpoints are its own (remaps, namespace, listed
by node), it is managed (lifecycle over DDS), it answers nothing that is not the user's
(NO_INPUTS without scene_file, a latched fixture that arrives), it recovers from stamps
that jump back, it follows action conventions, and a user's script can spin it with a
plain executor without the process being changed."""

from __future__ import annotations

import gc
import signal
import sys
import threading
import time
from pathlib import Path

import pytest
from geometry_msgs.msg import PoseStamped, Wrench
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from helpers.node_harness import DEADLINE_S
from rclpy.action import ActionClient
from rclpy.action.graph import get_action_server_names_and_types_by_node
from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data

from wrenchcone_msgs.action import PlanSeating
from wrenchcone_msgs.msg import Fixels, Status
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, ForceDirections, GetCone
from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.ros import conversions as conv

ROOT = Path(__file__).resolve().parents[2]
PAWL = ROOT / "examples" / "pawl_seating.yaml"
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
SERVICES = {"check_wrench": CheckWrench, "get_cone": GetCone,
            "classify_wrench": ClassifyWrench, "force_directions": ForceDirections}
_count = iter(range(10_000))


def unique_ns() -> str:
    return f"/c{id(object())}_{next(_count)}"


def call(node: Node, srv_type, name: str, request=None, timeout: float = DEADLINE_S):
    """One service call from ``node`` (spun elsewhere); the reply or an AssertionError."""
    cli = node.create_client(srv_type, name)
    try:
        assert cli.wait_for_service(timeout_sec=timeout), f"no service {name}"
        done = threading.Event()
        future = cli.call_async(request if request is not None else srv_type.Request())
        future.add_done_callback(lambda _f: done.set())
        assert done.wait(timeout), f"no reply from {name}"
        return future.result()
    finally:
        node.destroy_client(cli)


def wait_until(predicate, what: str, timeout: float = DEADLINE_S):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


class Spun:
    """Nodes spun by an executor in a thread, destroyed at exit."""

    def __init__(self, context, *nodes, executor=None):
        self.nodes = list(nodes)
        self.executor = executor or MultiThreadedExecutor(num_threads=4, context=context)
        for n in nodes:
            self.executor.add_node(n)
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def close(self):
        self.executor.shutdown(timeout_sec=2.0)
        self.thread.join(5.0)
        for n in self.nodes:
            n.destroy_node()


def pawl_fixels():
    """The pawl's fixels (positions, radii, friction) as its scene file has them."""
    from wrenchcone_ros.core import load_scene

    return load_scene(PAWL).fixels


def fixels_message(fixels, stamp_sec: int = 1) -> Fixels:
    return conv.fixels_message(fixels, "world", (stamp_sec, 0))


def pose_message(x: float, y: float, theta: float, sec: int) -> PoseStamped:
    import math

    msg = PoseStamped()
    msg.header.frame_id = "world"
    msg.header.stamp.sec = sec
    msg.pose.position.x, msg.pose.position.y = x, y
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(theta / 2), math.cos(theta / 2)
    return msg


def pawl_parameters() -> list[Parameter]:
    """The pawl's workpiece as parameters (no scene_file: the user's own inputs)."""
    from wrenchcone_ros.core import load_scene

    wp = load_scene(PAWL).workpiece
    return [Parameter("workpiece.shape", value="polygon"),
            Parameter("workpiece.vertices", value=[float(c) for v in wp.shape.vertices
                                                   for c in v]),
            Parameter("workpiece.mass", value=float(wp.mass)),
            Parameter("workpiece.inertia", value=float(wp.inertia)),
            Parameter("workpiece.com", value=[float(c) for c in wp.com]),
            Parameter("input_timeout", value=0.0)]


# --- endpoints: remaps, namespace, listed by node ----------------------------------------
def test_every_endpoint_follows_remaps_and_is_listed_as_the_nodes(ros_context):
    ns = unique_ns()
    remaps = {"check_wrench": "/my/check", "get_cone": "/my/cone",
              "classify_wrench": "/my/classify", "force_directions": "/my/directions",
              "plan_seating": "/my/plan"}
    args = ["--ros-args"]
    for name, target in remaps.items():
        args += ["-r", f"{ns}/wrenchcone/{name}:={target}"]
    args += ["-p", f"scene_file:={ROOT / 'examples' / 'paper_disc.yaml'}"]
    node = WrenchConeNode(namespace=ns, context=ros_context, cli_args=args)
    probe = Node("probe", namespace=ns, context=ros_context)
    spun = Spun(ros_context, node, probe)
    try:
        for name, srv_type in SERVICES.items():
            call(probe, srv_type, remaps[name])  # answered under the remapped name
        wanted = {remaps[name] for name in SERVICES}
        wait_until(lambda: wanted <= set(dict(
            probe.get_service_names_and_types_by_node("wrenchcone", ns))),
            f"the node's services listed as {sorted(wanted)}")
        wait_until(lambda: "/my/plan" in dict(
            get_action_server_names_and_types_by_node(probe, "wrenchcone", ns)),
            "the action server listed as /my/plan")
        mine = [n for n, space in probe.get_node_names_and_namespaces() if space == ns]
        assert sorted(mine) == ["probe", "wrenchcone"], mine  # no hidden helper nodes
    finally:
        spun.close()


# --- safe defaults ---------------------------------------------------------------------
@pytest.mark.parametrize("workpiece", [False, True])
def test_without_scene_file_nothing_is_ok_until_the_users_inputs_arrive(ros_context,
                                                                        workpiece):
    """Neither the paper's disc (the parameters' own defaults) nor any other scene of the
    node's: without scene_file, NO_INPUTS until the workpiece, its pose and the fixels
    are the user's."""
    ns = unique_ns()
    overrides = pawl_parameters() if workpiece else [Parameter("input_timeout", value=0.0)]
    node = WrenchConeNode(namespace=ns, context=ros_context, parameter_overrides=overrides)
    probe = Node("probe", namespace=ns, context=ros_context)
    spun = Spun(ros_context, node, probe)
    try:
        for mode in ("na", "aaa"):
            req = CheckWrench.Request(mode=mode, wrench=Wrench())
            req.wrench.force.x, req.wrench.torque.z = 1.0, -1.0
            r = call(probe, CheckWrench, f"{ns}/wrenchcone/check_wrench", req)
            assert r.status == Status.NO_INPUTS and not r.consistent, r.message
            if workpiece:
                assert "workpiece_pose" in r.message and "fixels" in r.message, r.message
            else:
                assert "no workpiece" in r.message, r.message
    finally:
        spun.close()


def test_a_fixture_latched_before_the_node_starts_arrives(ros_context):
    """The fixture's fixels are published once, latched, before the node exists; the
    node (no scene_file: the user's workpiece as parameters) must hear them."""
    ns = unique_ns()
    fixture = Node("fixture", namespace=ns, context=ros_context)
    pub = fixture.create_publisher(Fixels, "fixels", LATCHED)
    pub.publish(fixels_message(pawl_fixels()))
    pose_pub = fixture.create_publisher(PoseStamped, "workpiece_pose",
                                        qos_profile_sensor_data)
    time.sleep(0.2)
    node = WrenchConeNode(namespace=ns, context=ros_context,
                          parameter_overrides=pawl_parameters())
    spun = Spun(ros_context, node, fixture)
    try:
        from wrenchcone_ros.core import load_scene

        x, y, theta = load_scene(PAWL).pose
        name = f"{ns}/wrenchcone/check_wrench"

        def answered():
            pose_pub.publish(pose_message(x, y, theta, 5))
            # the pawl rests on pins 2 and 3 (3 mm, from the message): 'a' is not
            # allowed there (a PoseArray gave them the built-in scene's radius, 0: points
            # 3 mm below the foot, and 'aaa' was answered)
            r = call(fixture, CheckWrench, name, CheckWrench.Request(mode="ass"))
            return r if r.status != Status.NO_INPUTS else None

        r = wait_until(answered, "the latched fixels and a pose")
        assert r.status == Status.OK, r.message  # three fixels: the user's 3-letter mode
        assert (r.fixels_stamp.sec, r.pose_stamp.sec) == (1, 5)
    finally:
        spun.close()


def test_stamps_that_jump_back_reset_the_inputs_history(harness_factory):
    h = harness_factory(stamp_reset_threshold=1.0)
    from helpers.node_harness import pose_message as hp

    h.pose_pub.publish(hp(100))
    wait_until(lambda: h.check("na").pose_stamp.sec == 100, "pose 100")
    h.pose_pub.publish(hp(99))  # back by 1 s, not more than the threshold: refused
    time.sleep(0.3)
    assert h.check("na").pose_stamp.sec == 100
    h.pose_pub.publish(hp(3))  # back by 97 s: a reset (a replayed bag, a sim reset)
    wait_until(lambda: h.check("na").pose_stamp.sec == 3, "the reset to stamp 3")
    h.pose_pub.publish(hp(4))  # and newer-but-smaller stamps are taken from then on
    wait_until(lambda: h.check("na").pose_stamp.sec == 4, "stamp 4 after the reset")


# --- lifecycle --------------------------------------------------------------------------
def test_lifecycle_transitions_over_dds(ros_context):
    ns = unique_ns()
    node = WrenchConeNode(namespace=ns, context=ros_context, autostart=False,
                          parameter_overrides=[Parameter(
                              "scene_file", value=str(ROOT / "examples" / "paper_disc.yaml"))])
    probe = Node("probe", namespace=ns, context=ros_context)
    spun = Spun(ros_context, node, probe)
    base = f"{ns}/wrenchcone"

    def state() -> str:
        return call(probe, GetState, f"{base}/get_state").current_state.label

    def change(transition: int) -> bool:
        req = ChangeState.Request()
        req.transition.id = transition
        return call(probe, ChangeState, f"{base}/change_state", req).success

    check = CheckWrench.Request(mode="na")
    check.wrench.force.x, check.wrench.torque.z = 1.0, -1.0
    try:
        assert state() == "unconfigured"
        assert not probe.get_service_names_and_types_by_node("wrenchcone", ns) or \
            f"{base}/check_wrench" not in dict(
                probe.get_service_names_and_types_by_node("wrenchcone", ns))
        assert change(Transition.TRANSITION_CONFIGURE) and state() == "inactive"
        r = call(probe, CheckWrench, f"{base}/check_wrench", check)
        assert r.status == Status.NOT_ACTIVE and "not active" in r.message, r.message
        assert change(Transition.TRANSITION_ACTIVATE) and state() == "active"
        r = call(probe, CheckWrench, f"{base}/check_wrench", check)
        assert r.status == Status.OK and r.consistent, r.message
        assert change(Transition.TRANSITION_DEACTIVATE) and state() == "inactive"
        r = call(probe, CheckWrench, f"{base}/check_wrench", check)
        assert r.status == Status.NOT_ACTIVE
        assert change(Transition.TRANSITION_CLEANUP) and state() == "unconfigured"
        wait_until(lambda: f"{base}/check_wrench" not in dict(
            probe.get_service_names_and_types_by_node("wrenchcone", ns)), "cleanup")
        assert change(Transition.TRANSITION_CONFIGURE) and change(
            Transition.TRANSITION_ACTIVATE)
        assert call(probe, CheckWrench, f"{base}/check_wrench", check).status == Status.OK
    finally:
        spun.close()


# --- a user's script: any executor, no process-wide change ----------------------------------
@pytest.mark.parametrize("kind", ["single", "multi"])
def test_a_users_executor_spins_it_and_the_process_is_unchanged(ros_context, kind):
    before = (sys.getswitchinterval(), gc.isenabled(), gc.get_freeze_count(),
              signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM),
              threading.active_count())
    ns = unique_ns()
    node = WrenchConeNode(namespace=ns, context=ros_context, parameter_overrides=[
        Parameter("scene_file", value=str(ROOT / "examples" / "paper_disc.yaml"))])
    probe = Node("probe", namespace=ns, context=ros_context)
    executor = (SingleThreadedExecutor(context=ros_context) if kind == "single"
                else MultiThreadedExecutor(num_threads=3, context=ros_context))
    spun = Spun(ros_context, node, probe, executor=executor)
    try:
        base = f"{ns}/wrenchcone"
        check = CheckWrench.Request(mode="na")
        check.wrench.force.x, check.wrench.torque.z = 1.0, -1.0
        assert call(probe, CheckWrench, f"{base}/check_wrench", check).status == Status.OK
        assert call(probe, GetCone, f"{base}/get_cone",
                    GetCone.Request(mode="na")).status == Status.OK
        assert call(probe, ClassifyWrench, f"{base}/classify_wrench",
                    ClassifyWrench.Request(wrench=check.wrench)).status == Status.OK
        assert call(probe, ForceDirections, f"{base}/force_directions",
                    ForceDirections.Request(mode="na")).status == Status.OK
    finally:
        spun.close()
    after = (sys.getswitchinterval(), gc.isenabled(), gc.get_freeze_count(),
             signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM))
    assert after == before[:5]
    # the node's own thread (the publishing worker) ended with it
    wait_until(lambda: not [t for t in threading.enumerate()
                            if t.name.startswith("wrenchcone")], "the node's threads to end")


def test_a_bad_start_configuration_raises_one_line_and_leaves_no_node(ros_context):
    from wrenchcone_ros.node import StartError

    with pytest.raises(StartError, match="scene_file|no such|not found|No such"):
        WrenchConeNode(namespace=unique_ns(), context=ros_context, parameter_overrides=[
            Parameter("scene_file", value="/nonexistent/scene.yaml")])


# --- the action's conventions ------------------------------------------------------------
def test_bad_goals_are_rejected_and_no_plan_aborts(ros_context):
    ns = unique_ns()
    node = WrenchConeNode(namespace=ns, context=ros_context, parameter_overrides=[
        Parameter("scene_file", value=str(PAWL)), Parameter("input_timeout", value=0.0)])
    client_node = Node("client", namespace=ns, context=ros_context)
    spun = Spun(ros_context, node, client_node)
    client = ActionClient(client_node, PlanSeating, f"{ns}/wrenchcone/plan_seating")
    try:
        assert client.wait_for_server(timeout_sec=DEADLINE_S)

        def send(goal):
            done = threading.Event()
            fut = client.send_goal_async(goal)
            fut.add_done_callback(lambda _f: done.set())
            assert done.wait(DEADLINE_S)
            return fut.result()

        assert not send(PlanSeating.Goal(target=[])).accepted  # empty target
        assert not send(PlanSeating.Goal(target=[1, 2, 3], actuator="jet")).accepted
        assert not send(PlanSeating.Goal(target=[1, 2, 3], friction=[0.1])).accepted
        # a fixel the scene does not have: rejected in the goal callback
        assert not send(PlanSeating.Goal(target=[7])).accepted
    finally:
        client.destroy()
        spun.close()


def _reply_for(reply, sec: int):
    """The reply if it was computed from the pose stamped ``sec``, else None."""
    return reply if reply.pose_stamp.sec == sec else None


# --- a pose from a sensor ------------------------------------------------------------------
@pytest.mark.parametrize("tolerance, answered", [(None, False), (2e-3, True)])
def test_a_noisy_pose_stream_needs_a_contact_tolerance_on_the_sensors_scale(
        harness_factory, tolerance, answered):
    """A vision pose of the pawl on its two pins, with up to 1 mm and 5 mrad of error.
    With the scene's own tolerance (1e-9 m) most such poses penetrate a pin (SCENE_ERROR)
    or leave it (MODE_NOT_ALLOWED); with contact_tolerance on the sensor's scale (2 mm)
    every one is answered, and each answer is the core's for exactly that pose and
    tolerance (the reply's stamp names the pose)."""
    import numpy as np

    from wrenchcone_ros.core import load_scene, wrench_cone
    from wrenchcone_ros.core.scene_yaml import scene_from_dict

    extra = {} if tolerance is None else {"contact_tolerance": tolerance}
    h = harness_factory(scene_file=str(PAWL), **extra)
    base = load_scene(PAWL).to_dict()
    if tolerance is not None:
        base["contact_tolerance"] = tolerance
    rng = np.random.default_rng(7)
    g = (0.0, -0.49, -0.0098)  # the pawl's weight: fy = -m g, about its com
    ok = 0
    for k in range(12):
        dx, dy = rng.uniform(-1e-3, 1e-3, 2)
        dth = rng.uniform(-5e-3, 5e-3)
        pose = (0.096 + dx, 0.2 + dy, dth)
        h.publish_pose(*pose, stamp=(10 + k, 0))
        r = wait_until(lambda sec=10 + k: _reply_for(h.check("arr", g), sec), f"pose {k}")
        if r.status == Status.OK:
            ok += 1
            scene = scene_from_dict({**base, "workpiece": {**base["workpiece"],
                                                            "pose": list(pose)}})
            cone = wrench_cone(scene, "arr")
            assert r.consistent == cone.contains(g)
            assert r.margin == pytest.approx(cone.margin(g), abs=1e-9)
        else:
            assert r.status in (Status.SCENE_ERROR, Status.MODE_NOT_ALLOWED), r.message
    assert (ok == 12) if answered else (ok < 6), ok


def test_check_wrench_says_whether_it_classified(harness):
    plain = harness.check("na", (1.0, 0.0, -1.0))
    assert plain.status == Status.OK and not plain.classified and not plain.only_mode
    classified = harness.check("na", (1.0, 0.0, -1.0), classify=True)
    assert classified.status == Status.OK and classified.classified
