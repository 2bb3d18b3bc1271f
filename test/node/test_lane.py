# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""node/lane.py: check_wrench and get_cone served by the node's request lane, over DDS.

Which thread answered a request is read in the node's ``on_request`` hook (it runs in
the serving thread, before the reply is sent); nothing here is timed. A request held in
the hook stands for one that computes long: the cheap ones behind it must be answered
meanwhile.
"""

from __future__ import annotations

import threading
from pathlib import Path

import rclpy
from helpers.node_harness import DEADLINE_S
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.parameter import Parameter

from wrenchcone_msgs.msg import Status
from wrenchcone_ros.node import WrenchConeNode
from wrenchcone_ros.node.lane import LaneGroup

ROOT = Path(__file__).resolve().parents[2]
DISC = str(ROOT / "examples" / "paper_disc.yaml")
FAST = ("check_wrench", "get_cone")


class Threads:
    """The node's on_request hook: (service, status, thread name) of every reply; a
    reply of ``hold`` (a predicate on the service's name and thread) waits for
    :attr:`release`."""

    def __init__(self, node, hold=None) -> None:
        self.seen: list[tuple[str, int, str]] = []
        self.hold = hold
        self.held = threading.Event()
        self.release = threading.Event()
        node.on_request = self

    def __call__(self, timing) -> None:
        name = threading.current_thread().name
        self.seen.append((timing.service, timing.status, name))
        if self.hold is not None and self.hold(timing.service, name):
            self.held.set()
            self.release.wait(DEADLINE_S)


def lane_thread(name: str) -> bool:
    return name == "wrenchcone-lane"


def lane_pool(name: str) -> bool:
    return name.startswith("wrenchcone-lane-pool")


def test_the_fast_services_are_answered_by_the_lane_not_by_the_executor(harness_factory):
    h = harness_factory(scene_file=DISC)
    threads = Threads(h.node)
    for name in FAST:
        srv = h.node.endpoints[name]
        assert isinstance(srv.callback_group, LaneGroup)
        assert not h.spinner.executor.can_execute(srv)  # no executor takes its requests
    for name in ("classify_wrench", "force_directions"):  # the slow ones stay there
        assert h.spinner.executor.can_execute(h.node.endpoints[name])
    assert h.check("na", (0.1, -1.0, 0.0)).status == Status.OK  # computed at once
    assert h.check("na", (0.1, -1.0, 0.0)).status == Status.OK  # cached
    assert h.get_cone("na").status == Status.OK
    assert [(s, lane_thread(t)) for s, _, t in threads.seen] == [
        ("check_wrench", True), ("check_wrench", True), ("get_cone", True)]


def test_requests_that_compute_long_go_to_the_lane_pool(harness_factory):
    h = harness_factory(scene_file=DISC)
    threads = Threads(h.node)
    h.check("**", (0.1, -1.0, 0.0))  # a wildcard
    h.check("na", (0.1, -1.0, 0.0), classify=True)  # a classification
    h.check("na", (0.1, -1.0, 0.0))  # cached by the classification's snapshot? any: bounded
    assert [lane_pool(t) for _, _, t in threads.seen] == [True, True, False]


def test_a_long_request_does_not_hold_up_the_cheap_ones(harness_factory):
    h = harness_factory(scene_file=DISC)
    assert h.check("na").status == Status.OK  # cached from now on
    threads = Threads(h.node, hold=lambda service, name: lane_pool(name))
    done = threading.Event()
    replies = []

    def long_request() -> None:
        replies.append(h.check("**", (0.1, -1.0, 0.0)))
        done.set()

    caller = threading.Thread(target=long_request, daemon=True)
    caller.start()
    try:
        assert threads.held.wait(DEADLINE_S), "the wildcard check never reached the pool"
        # the wildcard request is held in its pool thread; the cheap ones are answered
        for _ in range(5):
            assert h.check("na", (0.1, -1.0, 0.0)).status == Status.OK
        assert h.get_cone("na").status == Status.OK
        assert not done.is_set()
    finally:
        threads.release.set()
    assert done.wait(DEADLINE_S) and replies[0].status in (Status.OK, Status.MODE_INFEASIBLE)
    caller.join(DEADLINE_S)


def test_request_lane_false_runs_them_on_the_executor(harness_factory):
    h = harness_factory(scene_file=DISC, request_lane=False)
    threads = Threads(h.node)
    assert h.node.lane is None
    for name in FAST:
        assert isinstance(h.node.endpoints[name].callback_group, ReentrantCallbackGroup)
    assert h.check("na").status == Status.OK
    assert h.get_cone("na").status == Status.OK
    assert len(threads.seen) == 2
    assert not any(t.startswith("wrenchcone-lane") for _, _, t in threads.seen)


def test_an_inactive_node_answers_not_active_from_the_lane(harness_factory):
    h = harness_factory(scene_file=DISC)
    threads = Threads(h.node)
    h.node.trigger_deactivate()
    assert h.check("na").status == Status.NOT_ACTIVE
    assert [(s, lane_thread(t)) for s, _, t in threads.seen] == [("check_wrench", True)]


def test_shutting_the_context_down_ends_the_lane():
    context = rclpy.Context()
    rclpy.init(context=context)
    node = WrenchConeNode(namespace=f"/lane{id(context)}", context=context,
                          parameter_overrides=[Parameter("scene_file", value=DISC)])
    try:
        lane = node.lane
        assert lane is not None and lane.thread.is_alive()
        context.try_shutdown()
        lane.thread.join(DEADLINE_S)
        assert not lane.thread.is_alive() and not lane.running
    finally:
        node.destroy_node()
        context.try_shutdown()
