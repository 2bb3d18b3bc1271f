# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``~/plan_seating`` action over real DDS (node/plan_action.py): the result equals
the core's plan from the same inputs, feedback arrives, a cancel ends the goal CANCELED,
stale inputs give no plan, bad goals are refused with a reason, and the other services
answer while a plan is computed."""

from __future__ import annotations

import math
import os
import threading
import time

import pytest

pytest.importorskip("pymunk")

from action_msgs.msg import GoalStatus  # noqa: E402
from rclpy.action import ActionClient  # noqa: E402
from rclpy.qos import QoSProfile, ReliabilityPolicy  # noqa: E402

from wrenchcone_msgs.action import PlanSeating  # noqa: E402
from wrenchcone_msgs.msg import PlanSegment, Status  # noqa: E402
from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import plan_seating  # noqa: E402
from diagnostic_msgs.msg import DiagnosticStatus  # noqa: E402
from helpers.node_harness import Collector  # noqa: E402
from wrenchcone_ros.node.plan_action import REJECTIONS_QOS  # noqa: E402

R = PlanSeating.Result
SEATING = os.path.abspath("examples/pawl_seating.yaml")
POLYGON = os.path.abspath("examples/pawl_polygon.yaml")
DEADLINE_S = 120.0


class Goal:
    """One goal sent from the tester node: its handle, feedback and result."""

    def __init__(self, h, goal: PlanSeating.Goal, accept: bool = True) -> None:
        cli = getattr(h, "_plan_cli", None)
        if cli is None:
            cli = h._plan_cli = ActionClient(h.tester, PlanSeating,
                                             f"{h.ns}/wrenchcone/plan_seating")
            assert cli.wait_for_server(timeout_sec=30.0)
            # rclpy's ActionClient drops a goal's feedback callback once its result has
            # arrived, and the last feedback (a topic) may arrive after the result (a
            # service): the tester also reads the feedback topic itself, every goal's
            topic = f"{h.ns}/wrenchcone/plan_seating/_action/feedback"
            h._plan_feedback = []
            h.tester.create_subscription(
                PlanSeating.Impl.FeedbackMessage, topic,
                lambda m: h._plan_feedback.append((bytes(m.goal_id.uuid), m.feedback)),
                QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE))
            deadline = time.monotonic() + 30.0
            while h.tester.count_publishers(topic) < 1 and time.monotonic() < deadline:
                time.sleep(0.02)
            assert h.tester.count_publishers(topic) >= 1, f"no publisher on {topic}"
        self._h = h
        self.feedback: list = []
        self.got_feedback = threading.Event()
        accepted = threading.Event()
        fut = cli.send_goal_async(goal, feedback_callback=self._on_feedback)
        fut.add_done_callback(lambda _f: accepted.set())
        assert accepted.wait(30.0), "no answer to the goal"
        self.handle = fut.result()
        assert self.handle.accepted == accept, self.handle
        self._done = threading.Event()
        if not accept:
            return
        self._result = self.handle.get_result_async()
        self._result.add_done_callback(lambda _f: self._done.set())

    def _on_feedback(self, msg) -> None:
        self.feedback.append(msg.feedback)
        self.got_feedback.set()

    def wait_feedback(self, predicate) -> bool:
        """Whether a feedback message satisfying ``predicate`` arrives (feedback is a
        topic and the result a service: the last feedback may come after the result)."""
        deadline = time.monotonic() + DEADLINE_S
        while time.monotonic() < deadline:
            mine = bytes(self.handle.goal_id.uuid)
            seen = list(self.feedback) + [f for g, f in list(self._h._plan_feedback) if g == mine]
            if any(predicate(f) for f in seen):
                return True
            time.sleep(0.02)
        return False

    def result(self) -> R:
        assert self._done.wait(DEADLINE_S), "no result"
        return self._result.result().result

    def status(self) -> int:
        """The goal's final status (action_msgs/GoalStatus)."""
        assert self._done.wait(DEADLINE_S), "no result"
        return self._result.result().status

    def cancel(self) -> None:
        done = threading.Event()
        self.handle.cancel_goal_async().add_done_callback(lambda _f: done.set())
        assert done.wait(30.0)


@pytest.fixture
def seating(harness_factory):
    return harness_factory(scene_file=SEATING)


def test_result_equals_the_core(seating):
    goal = PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=4, seed=2)
    g = Goal(seating, goal)
    r = g.result()
    assert r.status == Status.OK, r.message
    core = plan_seating(load_scene(SEATING), [1, 2, 3], uncertainty=(0.2, 0.4), runs=4,
                        seed=2, workers=1)
    assert [s.mode for s in r.segments] == [s.mode for s in core.segments] == ["arr", "nnn"]
    for got, want in zip(r.segments, core.segments, strict=True):
        assert got.direction == want.direction and got.margin == want.margin
        assert (got.interval_lo, got.interval_hi) == (want.interval.lo, want.interval.hi)
        assert (got.end.x, got.end.y, got.end.theta) == tuple(want.end_pose)
        assert (got.start.x, got.start.y, got.start.theta) == tuple(want.start_pose)
        assert got.event == want.event
        assert got.scale == want.scale and got.accuracy == want.accuracy
        assert got.tilt == pytest.approx(math.radians(core.tilt_deg(want)))
    assert r.feasible and r.nominal_success and r.guaranteed == core.guaranteed is True
    assert list(r.missing) == list(core.missing) == []
    assert r.runs == 4 and r.successes == 4 and r.success_rate == 1.0
    assert r.success_rate == core.success_rate
    assert r.inputs_version >= 1 and r.frame_id
    assert r.status == r.OK  # the result carries Status's constants
    assert (r.pose_source, r.fixels_source) == (r.SOURCE_SCENE_FILE, r.SOURCE_SCENE_FILE)
    assert PlanSegment.get_fields_and_field_types()["start"] == "wrenchcone_msgs/PlanarPose"
    assert (r.candidates, r.trials, r.out_of_time) == (core.candidates, core.trials, False)
    assert g.wait_feedback(lambda f: f.segments_planned == 2)
    assert g.wait_feedback(lambda f: f.simulations_total == 4 and f.simulations_run == 4)


def test_the_goal_bounds_the_search_by_work(harness_factory):
    """max_candidates in the goal reaches the planner: the pawl of pawl_polygon.yaml
    from its own pose (no guaranteed plan) with max_candidates 1 ends after one
    candidate and says so, as the core does with the same bound."""
    g = Goal(harness_factory(scene_file=POLYGON),
             PlanSeating.Goal(target=[1, 2, 3], runs=0, max_candidates=1))
    r = g.result()
    core = plan_seating(load_scene(POLYGON), [1, 2, 3], max_candidates=1)
    assert r.candidates == core.candidates == 1 and not r.out_of_time
    assert r.message == core.reason and "candidate limit (1) was reached" in r.message


def test_a_plan_whose_seating_is_not_guaranteed_says_so(harness_factory):
    """The pawl of pawl_polygon.yaml from its own pose: a plan exists, but no tilt holds
    the seat and drives a part lifted off a pin back onto it (the funnel is empty)."""
    g = Goal(harness_factory(scene_file=POLYGON), PlanSeating.Goal(target=[1, 2, 3], runs=0))
    r = g.result()
    assert r.status == Status.OK and r.feasible and not r.guaranteed
    assert "not guaranteed" in r.message and r.segments[-1].margin <= 0.0


def test_other_services_answer_during_a_plan(seating):
    g = Goal(seating, PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=30))
    answered = 0
    t0 = time.monotonic()
    while not g._done.is_set() and time.monotonic() - t0 < DEADLINE_S:
        assert seating.get_cone("arr").status == 0
        answered += 1
    assert g.result().status == Status.OK
    assert answered >= 3  # get_cone kept answering while the plan ran


def test_cancel(seating):
    g = Goal(seating, PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=400))
    assert g.got_feedback.wait(60.0)  # the plan has started
    g.cancel()
    r = g.result()
    assert r.status == Status.CANCELED and not r.segments
    # the lane is free again
    r = Goal(seating, PlanSeating.Goal(target=[1, 2, 3])).result()
    assert r.status == Status.OK and r.success_rate == 1.0  # nominal run only


def test_one_plan_at_a_time(seating, capfd):
    """The documented policy: a goal while another plan runs is rejected (the reason in
    the log), and the running one goes on; after it, goals are accepted again."""
    first = Goal(seating, PlanSeating.Goal(target=[1, 2, 3], friction=[0.2, 0.4], runs=400))
    assert first.got_feedback.wait(60.0)  # computing
    Goal(seating, PlanSeating.Goal(target=[1, 2, 3]), accept=False)
    assert "plan_seating goal rejected: another plan is being computed" in \
        capfd.readouterr().err
    first.cancel()
    assert first.result().status == Status.CANCELED
    assert first.status() == GoalStatus.STATUS_CANCELED
    assert Goal(seating, PlanSeating.Goal(target=[1, 2, 3])).status() == \
        GoalStatus.STATUS_SUCCEEDED


def test_stale_inputs_give_no_plan(harness_factory):
    h = harness_factory(scene_file=SEATING, input_timeout=1.0)
    v = h.get_cone("").inputs_version
    h.publish_pose(0.096, 0.2, 0.0, stamp=(21, 0))
    h.wait_version_above(v)
    time.sleep(1.2)  # the pose is now older than input_timeout
    r = Goal(h, PlanSeating.Goal(target=[1, 2, 3])).result()
    assert r.status == Status.STALE_INPUTS and "input_timeout" in r.message
    assert not r.segments and not r.feasible


@pytest.mark.parametrize("goal, words", [
    (PlanSeating.Goal(target=[]), "target is empty"),
    (PlanSeating.Goal(target=[1], actuator="push"), "'tilt' or 'spring'"),
    (PlanSeating.Goal(target=[1], friction=[0.2, 0.3, 0.4]), "friction takes"),
    (PlanSeating.Goal(target=[1], friction=[0.2, 0.4], runs=10_001), "at most 10000"),
    (PlanSeating.Goal(target=[1], use_tilt=True, tilt=3.0), "(0, pi/2]"),
    (PlanSeating.Goal(target=[1], budget=-1.0), "budget must be 0 (no time cap)"),
    (PlanSeating.Goal(target=[1], budget=float("nan")), "budget must be 0 (no time cap)"),
])
def test_malformed_goals_are_rejected_with_the_reason_logged(seating, capfd, goal, words):
    Goal(seating, goal, accept=False)
    err = capfd.readouterr().err
    assert "plan_seating goal rejected" in err and words in err, err


@pytest.mark.parametrize("goal, words", [
    (PlanSeating.Goal(target=[1], friction=[0.4, 0.2]), "friction"),
])
def test_goals_the_planner_refuses_are_aborted_with_the_reason(seating, goal, words):
    g = Goal(seating, goal)
    r = g.result()
    assert r.status == Status.INVALID_GOAL and words in r.message, r.message
    assert g.status() == GoalStatus.STATUS_ABORTED


def test_no_plan(harness_factory):
    # the original pawl 12 mm from its seat tips (and no constant tilt seats it): no
    # plan, and the reason
    h = harness_factory(scene_file=os.path.abspath("examples/pawl_polygon.yaml"))
    v = h.get_cone("").inputs_version
    h.publish_pose(0.092, 0.2, 0.0, stamp=(5, 0))
    h.wait_version_above(v)
    g = Goal(h, PlanSeating.Goal(target=[1, 2, 3]))
    r = g.result()
    assert r.status == Status.NO_PLAN and r.message.startswith("step 1:") and not r.feasible
    assert g.status() == GoalStatus.STATUS_ABORTED


def rejections(h) -> Collector:
    """The node's ``~/plan_seating/rejections`` (latched: the last ones arrive)."""
    return h.subscribe(DiagnosticStatus, f"{h.ns}/wrenchcone/plan_seating/rejections",
                       REJECTIONS_QOS)


@pytest.mark.parametrize("target, bad", [([0, 99], "[0, 99]"), ([4], "[4]"),
                                         ([1, 2, 3, 4], "[4]")])
def test_a_target_fixel_the_fixture_lacks_is_rejected_with_the_reason(seating, capfd,
                                                                      target, bad):
    """The pawl's fixture has 3 fixels, numbered 1..3: a goal naming another is rejected
    in the goal callback (no result); the reason reaches the caller on the rejections
    topic, under the goal's id, and the log."""
    g = Goal(seating, PlanSeating.Goal(target=target), accept=False)
    seen = rejections(seating)
    goal_id = bytes(g.handle.goal_id.uuid).hex()
    msg = seen.wait_for(lambda m: dict((v.key, v.value) for v in m.values)["goal_id"]
                        == goal_id, f"the rejection of goal {goal_id}")
    assert f"target fixel(s) {bad} not in the fixture" in msg.message, msg.message
    assert "3 fixels, numbered 1..3" in msg.message, msg.message
    assert msg.level == DiagnosticStatus.ERROR
    assert msg.name == f"{seating.ns}/wrenchcone/plan_seating"
    assert "plan_seating goal rejected: target fixel(s)" in capfd.readouterr().err
    # the goal's target is named as the caller gave it
    assert dict((v.key, v.value) for v in msg.values)["target"] == str(target)


def test_a_target_on_the_fixture_received_is_checked_against_it(harness_factory):
    """No scene file's count: the node's current fixture, the fixels received."""
    h = harness_factory(scene_file=SEATING)
    fixels = load_scene(SEATING).fixels
    h.publish_fixels([f.position for f in fixels[:2]], radii=[f.radius for f in fixels[:2]],
                     frictions=[f.friction for f in fixels[:2]], stamp=(3, 0))

    def fixels_now() -> int:
        scene = h.node.request_snapshot().scene
        return 0 if scene is None else scene.n_fixels

    deadline = time.monotonic() + DEADLINE_S
    while fixels_now() != 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    assert fixels_now() == 2
    Goal(h, PlanSeating.Goal(target=[1, 2, 3]), accept=False)
    msg = rejections(h).wait_for(lambda m: "[3] not in the fixture" in m.message,
                                 "the rejection of fixel 3 of 2")
    assert "2 fixels, numbered 1..2" in msg.message, msg.message


@pytest.mark.parametrize("use_tilt, tilt, why", [
    (True, 0.0, "tilt must be in (0, pi/2] rad"),
    (True, math.nan, "tilt must be in (0, pi/2] rad"),
    (True, 2.0, "tilt must be in (0, pi/2] rad"),
    (False, 0.2, "use_tilt is false")])
def test_a_tilt_of_zero_is_zero_not_the_default(seating, use_tilt, tilt, why):
    """tilt 0 no longer means "the default": with use_tilt it is 0 rad, a level tray, and
    rejected with the reason; a tilt given without use_tilt is rejected, not ignored."""
    g = Goal(seating, PlanSeating.Goal(target=[1, 2, 3], use_tilt=use_tilt, tilt=tilt),
             accept=False)
    goal_id = bytes(g.handle.goal_id.uuid).hex()
    msg = rejections(seating).wait_for(
        lambda m: dict((v.key, v.value) for v in m.values)["goal_id"] == goal_id,
        f"the rejection of goal {goal_id}")
    assert why in msg.message, msg.message


def test_a_goal_with_a_start_region_returns_the_box_certified(seating):
    """use_start_region: the plan is certified over the box. The pawl at its seat
    (x = 0.104 m: its foot against the stop, on pins 2 and 3), the box 0.5 mm in y
    alone: of the cover's 5 values in y (-0.5, -0.25, 0, 0.25, 0.5 mm), the two below
    press the foot into the pins (no starts), the three others are starts (the part
    lifted up to 0.5 mm above its seat, it drops back onto it); the whole box holds."""
    v = seating.get_cone("").inputs_version
    seating.publish_pose(0.104, 0.2, 0.0, stamp=(7, 0))
    seating.wait_version_above(v)
    g = Goal(seating, PlanSeating.Goal(target=[1, 2, 3], use_start_region=True,
                                       start_region_dy=0.0005))
    r = g.result()
    assert r.status == Status.OK and r.feasible, r.message
    assert [s.mode for s in r.segments] == ["nnn"]
    assert r.start_region_certified and r.start_region_fraction == 1.0
    assert (r.certified_region_dx, r.certified_region_dy, r.certified_region_dtheta) == \
        (0.0, 0.0005, 0.0)
    assert r.start_region_failure == ""
    assert r.start_region_claim.startswith(
        "every one of the 3 cover points (a grid of 5 per axis; 2 more overlap a fixel "
        "and are no starts) seats the part under the nominal model"), r.start_region_claim
    assert "688 starts drawn uniformly in the box" in r.start_region_claim
    # the cones' lines: no pose of a box 0.5 mm in y alone rests lifted off one pin
    assert ("; cones: segment 1 at rest on fixel(s) 2 3, lifted off fixel 1, in the start "
            "box: no pose of the box rests there") in r.start_region_claim
    # without a region: the fraction says none was asked
    r = Goal(seating, PlanSeating.Goal(target=[1, 2, 3])).result()
    assert r.status == Status.OK and r.start_region_fraction == -1.0
    assert not r.start_region_certified and r.start_region_claim == ""


@pytest.mark.parametrize("use, half, why", [
    (True, (-0.001, 0.0, 0.0), "dx must be a finite number >= 0 (m), got -0.001"),
    (True, (0.0, math.nan, 0.0), "dy must be a finite number >= 0 (m), got nan"),
    (True, (0.0, 0.0, 4.0), "dtheta must be at most pi rad (a half-turn), got 4.0"),
    (False, (0.002, 0.0, 0.0), "use_start_region is false")])
def test_a_malformed_start_region_is_rejected_with_the_reason(seating, use, half, why):
    """A region with a negative or NaN half-width, or a turn of more than a half-turn, is
    rejected in the goal callback, its reason on the rejections topic; a region given
    without use_start_region is rejected too, never silently ignored."""
    dx, dy, dth = half
    g = Goal(seating, PlanSeating.Goal(
        target=[1, 2, 3], use_start_region=use, start_region_dx=dx, start_region_dy=dy,
        start_region_dtheta=dth), accept=False)
    goal_id = bytes(g.handle.goal_id.uuid).hex()
    msg = rejections(seating).wait_for(
        lambda m: dict((v.key, v.value) for v in m.values)["goal_id"] == goal_id,
        f"the rejection of goal {goal_id}")
    assert why in msg.message and "\n" not in msg.message, msg.message
