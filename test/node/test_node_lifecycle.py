# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node managed as nav2 manages its nodes, over real DDS with the ``lifecycle_msgs``
services: deactivate stops every timer, every publication and a running plan; configure
fails cleanly on a bad configuration; cleanup and shutdown leave none of what configure
made; and nav2's lifecycle manager, with the settings docs/node_reference.md gives (no bond:
``bond_timeout: 0.0``), brings the node up and down with its own sequence of
transitions."""

from __future__ import annotations

import re
import threading
import time
from pathlib import Path

import pytest
import yaml
from diagnostic_msgs.msg import DiagnosticArray
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.qos import QoSProfile

from helpers.node_harness import DEADLINE_S, Collector
from rclpy.node import Node
from rclpy.parameter import Parameter
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench
from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.node.executors import SpinThread

ROOT = Path(__file__).resolve().parents[2]
DISC = str(ROOT / "examples" / "paper_disc.yaml")
SEATING = str(ROOT / "examples" / "pawl_seating.yaml")
#: diagnostics_rate of these tests (Hz): a window of WINDOW_PERIODS periods would hold
#: that many /diagnostics messages if the timer still ran.
RATE_HZ = 50.0
WINDOW_PERIODS = 25
#: What configure creates and cleanup / shutdown must take away (the node's topics).
CONFIGURED_TOPICS = ("/diagnostics", "cone/na", "markers")


class Managed:
    """A node that starts unconfigured (``autostart`` false, as under a lifecycle
    manager) and a tester node, spun as the program spins them; the attributes the
    harness has (ns, node, tester, _call)."""

    def __init__(self, context, ns: str, **parameters) -> None:
        self.ns = ns
        self.node = WrenchConeNode(namespace=ns, context=context, autostart=False,
                                   parameter_overrides=[Parameter(k, value=v)
                                                        for k, v in parameters.items()])
        self.tester = Node("tester", namespace=ns, context=context)
        self.spinner = SpinThread([self.node, self.tester], None, "managed", context)

    def _call(self, client, request):
        done = threading.Event()
        future = client.call_async(request)
        future.add_done_callback(lambda _f: done.set())
        assert done.wait(DEADLINE_S), f"no reply from {client.srv_name}"
        return future.result()

    def check(self) -> int:
        cli = self.tester.create_client(CheckWrench, f"{self.ns}/wrenchcone/check_wrench")
        try:
            assert cli.wait_for_service(timeout_sec=DEADLINE_S)
            req = CheckWrench.Request(mode="na")
            req.wrench.force.x, req.wrench.torque.z = 1.0, -1.0
            return self._call(cli, req).status
        finally:
            self.tester.destroy_client(cli)

    def close(self) -> None:
        self.spinner.stop()
        self.tester.destroy_node()
        self.node.destroy_node()


_count = iter(range(100_000))


@pytest.fixture
def managed(ros_context):
    made = []

    def make(**parameters) -> Managed:
        m = Managed(ros_context, f"/lc{id(made)}_{next(_count)}", **parameters)
        made.append(m)
        return m

    yield make
    for m in made:
        m.close()


def change(h, transition: int) -> bool:
    """One ``change_state`` call from the tester; whether it succeeded."""
    cli = h.tester.create_client(ChangeState, f"{h.ns}/wrenchcone/change_state")
    try:
        assert cli.wait_for_service(timeout_sec=DEADLINE_S)
        req = ChangeState.Request()
        req.transition.id = transition
        return h._call(cli, req).success
    finally:
        h.tester.destroy_client(cli)


def state(h) -> str:
    cli = h.tester.create_client(GetState, f"{h.ns}/wrenchcone/get_state")
    try:
        assert cli.wait_for_service(timeout_sec=DEADLINE_S)
        return h._call(cli, GetState.Request()).current_state.label
    finally:
        h.tester.destroy_client(cli)


def running_timers(node) -> list:
    return [t for t in node.timers if not t.is_canceled()]


def node_topics(h) -> set[str]:
    """The topics the node publishes (as the ROS graph lists them)."""
    return {name for name, _types in
            h.tester.get_publisher_names_and_types_by_node("wrenchcone", h.ns)}


def my_diagnostics(h) -> Collector:
    """/diagnostics messages of this test's node only (the topic is global)."""
    mine = Collector()
    name = f"{h.ns}/wrenchcone"
    h.tester.create_subscription(
        DiagnosticArray, "/diagnostics",
        lambda m: mine(m) if m.status and m.status[0].hardware_id == name else None,
        QoSProfile(depth=100))
    return mine


def test_deactivate_stops_every_timer_and_publication(harness_factory):
    h = harness_factory(scene_file=DISC, diagnostics_rate=RATE_HZ, publish_markers=True)
    diag = my_diagnostics(h)
    cone = h.subscribe_cone("na")
    diag.wait_for(lambda m: True, "diagnostics while active")
    cone.wait_for(lambda m: m.status == Status.OK, "a cone while active")
    assert running_timers(h.node)  # sanity: the node has timers while active

    assert change(h, Transition.TRANSITION_DEACTIVATE) and state(h) == "inactive"
    assert running_timers(h.node) == []
    assert h.node.worker is None
    seen_diag, seen_cone = len(diag.messages), len(cone.messages)
    # a change of inputs while inactive publishes nothing either
    h.publish_pose(0.0, 0.0, 0.0, stamp=(7, 0))
    time.sleep(WINDOW_PERIODS / RATE_HZ)  # the timer, if it ran, would publish here
    assert len(diag.messages) == seen_diag and len(cone.messages) == seen_cone

    assert change(h, Transition.TRANSITION_ACTIVATE) and state(h) == "active"
    assert running_timers(h.node)
    diag.wait_for(lambda m: True, "diagnostics after reactivation", since=seen_diag)
    cone.wait_for(lambda m: m.header.stamp.sec == 7, "the pose received while inactive",
                  since=seen_cone)


def test_deactivate_stops_a_running_plan(harness_factory):
    pytest.importorskip("pymunk")
    from rclpy.action import ActionClient
    from action_msgs.msg import GoalStatus
    from wrenchcone_msgs.action import PlanSeating

    h = harness_factory(scene_file=SEATING)
    client = ActionClient(h.tester, PlanSeating, f"{h.ns}/wrenchcone/plan_seating")
    assert client.wait_for_server(timeout_sec=DEADLINE_S)
    started = threading.Event()
    sent = client.send_goal_async(
        PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=10_000),
        feedback_callback=lambda _m: started.set())
    done = threading.Event()
    sent.add_done_callback(lambda _f: done.set())
    assert done.wait(DEADLINE_S) and sent.result().accepted
    assert started.wait(120.0), "the plan never started"
    result = sent.result().get_result_async()

    # deactivate returns once the plan has ended: stopped, not left running
    assert change(h, Transition.TRANSITION_DEACTIVATE)
    assert h.node.plan_action.running() is False
    finished = threading.Event()
    result.add_done_callback(lambda _f: finished.set())
    assert finished.wait(DEADLINE_S)
    r = result.result()
    assert r.status == GoalStatus.STATUS_ABORTED
    assert r.result.status == Status.CANCELED and "deactivated" in r.result.message
    assert not r.result.segments
    # active again, the next goal is planned (the stop does not stick)
    assert change(h, Transition.TRANSITION_ACTIVATE)
    sent = client.send_goal_async(PlanSeating.Goal(target=[1, 2, 3]))
    done = threading.Event()
    sent.add_done_callback(lambda _f: done.set())
    assert done.wait(DEADLINE_S) and sent.result().accepted
    result = sent.result().get_result_async()
    finished = threading.Event()
    result.add_done_callback(lambda _f: finished.set())
    assert finished.wait(120.0)
    assert result.result().result.status == Status.OK
    client.destroy()


def test_a_bad_configuration_fails_configure_and_leaves_it_unconfigured(managed, capfd):
    """A workpiece the scene's fixels are inside of (a disc of radius 2 m around the
    paper's fixels at 1 m) is accepted as a parameter while unconfigured (a workpiece
    alone can be right) but makes no scene: configure fails, says why, creates nothing."""
    m = managed(scene_file=DISC)
    assert state(m) == "unconfigured"
    assert m.node.set_parameters([Parameter("workpiece.radius", value=2.0)])[0].successful
    assert not change(m, Transition.TRANSITION_CONFIGURE)
    assert state(m) == "unconfigured"
    assert "configure failed" in capfd.readouterr().err
    assert list(m.node.timers) == [] and m.node.store is None
    assert not any(t.endswith("cone/na") for t in node_topics(m))
    assert m.node.set_parameters([Parameter("workpiece.radius", value=1.0)])[0].successful
    assert change(m, Transition.TRANSITION_CONFIGURE) and state(m) == "inactive"
    assert m.check() == Status.NOT_ACTIVE


@pytest.mark.parametrize("end", ["cleanup", "shutdown"])
def test_cleanup_and_shutdown_take_away_what_configure_made(harness_factory, end):
    h = harness_factory(scene_file=DISC, publish_markers=True)

    def made() -> set[str]:
        return {t for t in node_topics(h) if t.endswith(CONFIGURED_TOPICS)}

    deadline = time.monotonic() + DEADLINE_S
    while len(made()) < len(CONFIGURED_TOPICS) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert len(made()) == len(CONFIGURED_TOPICS), node_topics(h)
    if end == "cleanup":
        assert change(h, Transition.TRANSITION_DEACTIVATE)
        assert change(h, Transition.TRANSITION_CLEANUP) and state(h) == "unconfigured"
    else:  # from active, as a manager's shutdown may
        assert change(h, Transition.TRANSITION_ACTIVE_SHUTDOWN)
        assert state(h) == "finalized"
    assert list(h.node.timers) == []
    assert h.node.worker is None and h.node.plan_action is None and h.node.lane is None
    assert [t for t in threading.enumerate()
            if t.name.startswith(("wrenchcone-publish", "wrenchcone-lane"))] == []
    while made() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert made() == set()
    if end == "cleanup":  # and it can be configured again
        assert change(h, Transition.TRANSITION_CONFIGURE)
        assert change(h, Transition.TRANSITION_ACTIVATE)
        assert h.check("na").status == Status.OK


def _nav2_block() -> dict:
    """The lifecycle manager's parameters as docs/node_reference.md gives them."""
    text = (ROOT / "docs" / "node_reference.md").read_text()
    blocks = re.findall(r"```yaml\n(.*?)```", text, re.S)
    found = [yaml.safe_load(b) for b in blocks if "lifecycle_manager" in b]
    assert len(found) == 1, "docs/node_reference.md: one YAML block for nav2's lifecycle_manager"
    return found[0]


def test_nav2_lifecycle_manager_settings_bring_it_up_and_down(managed):
    """nav2's lifecycle_manager, as docs/node_reference.md configures it: no bond is offered (the
    node publishes nothing on /bond), so ``bond_timeout`` must be 0.0; the node starts
    unconfigured (``autostart: false``); the manager's startup (configure, then
    activate) and its shutdown (deactivate, cleanup, shutdown) succeed in its order."""
    block = _nav2_block()
    manager = next(iter(block.values()))["ros__parameters"]
    assert manager["bond_timeout"] == 0.0 and manager["autostart"] is True
    assert manager["node_names"] == ["wrenchcone"]
    node_params = block["wrenchcone"]["ros__parameters"]
    assert node_params["autostart"] is False  # Managed: constructed with autostart false
    h = managed(scene_file=DISC)
    assert state(h) == "unconfigured"
    for transition, label in ((Transition.TRANSITION_CONFIGURE, "inactive"),
                              (Transition.TRANSITION_ACTIVATE, "active")):
        assert change(h, transition) and state(h) == label
    assert h.check() == Status.OK
    assert not [t for t in node_topics(h) if "bond" in t]  # no bond is offered
    for transition, label in ((Transition.TRANSITION_DEACTIVATE, "inactive"),
                              (Transition.TRANSITION_CLEANUP, "unconfigured"),
                              (Transition.TRANSITION_UNCONFIGURED_SHUTDOWN, "finalized")):
        assert change(h, transition) and state(h) == label
