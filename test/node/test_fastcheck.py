"""The compiled check_wrench lane (src/fastcheck.c, node/fastcheck.py).

Its check is a port of the Python reference (cones._Query.check, itself checked against
an NNLS distance in test/core/test_cones.py): here every cone of every valid mode of the
example scenes, on chosen and random wrenches, must give the same membership exactly
and the same margin within MARGIN_ATOL. Over DDS, the node's replies with the lane on
must equal its replies with the lane off (every request then answered by the Python
handler), field by field, and the lane must really have answered them; what it cannot
answer is forwarded and answered as before."""

from __future__ import annotations

import itertools
import math
import threading
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs
from node_harness import DEADLINE_S
from rclpy.clock import Clock, ClockType

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.modes import enumerate_modes
from wrenchcone_ros.node import fastcheck
from wrenchcone_ros.node import status as S
from wrenchcone_ros.srv import CheckWrench
from wrenchcone_ros.node import store as st

#: Margins outside a cone: the lane projects with its own 3x3 products, numpy with BLAS
#: (whose summation order, and fused multiply-adds, may differ): a few ulps of 1.
MARGIN_ATOL = 1e-12
SCENES = ("examples/paper_disc.yaml", "examples/pawl_polygon.yaml")
_CLOCK = Clock(clock_type=ClockType.STEADY_TIME)


def _lane_with(answers: dict[str, st.Answer], version: int = 1) -> fastcheck.Lane:
    lane = fastcheck.Lane(_CLOCK.handle.pointer, fastcheck.CONE_TOLERANCE,
                          fastcheck.RANK_TOLERANCE, fastcheck.WRENCH_RESCALE_ABOVE, S.OK,
                          S.MODE_INFEASIBLE, S.INTERNAL_ERROR, S.LIMIT_EXCEEDED)
    snap = st.Snapshot(version, None, S.OK, "", "world", None, None)
    assert fastcheck.offer(lane, lane.generation(), snap, answers)
    return lane


def _every_mode(path: str) -> tuple[dict[str, st.Answer], fastcheck.Lane]:
    scene = load_scene(path)
    snap = st.Snapshot(1, scene, S.OK, "", "world", None, None)
    modes = list(enumerate_modes(scene.in_contact))
    answers = st.monitored_answers(snap, modes)
    return answers, _lane_with(answers)


@pytest.fixture(scope="module", params=SCENES)
def every_mode(request):
    return _every_mode(request.param)


def _wrenches(answers: dict[str, st.Answer]) -> list[tuple[float, float, float]]:
    """Wrenches on every kind of place: zero, axes, each cone's facet normals (outside),
    generators and their negatives (boundary, inside, opposite), and a grid."""
    out = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0)]
    for ans in answers.values():
        if ans.cone is None or not ans.cone.feasible:
            continue
        for rows in (ans.cone.F, ans.cone.G, ans.cone.lineality, ans.cone.equalities):
            for r in np.asarray(rows).reshape(-1, 3):
                out += [tuple(map(float, r)), tuple(map(float, -r))]
    grid = (-2.0, -0.5, 0.0, 0.25, 3.0)
    out += list(itertools.product(grid, grid, grid))
    return out


def _same(lane: fastcheck.Lane, mode: str, ans: st.Answer, g) -> None:
    got = lane.check(mode, *g)
    if ans.status == S.MODE_INFEASIBLE or ans.cone is None:
        assert got == (False, -1.0)
        return
    want = ans.cone.check(g)
    assert got[0] == want[0], (mode, g, got, want)
    assert math.isclose(got[1], want[1], rel_tol=0.0, abs_tol=MARGIN_ATOL), (mode, g, got,
                                                                              want)
    if want[1] >= 0:  # inside: the same float operations, the same bits
        assert got[1] == want[1], (mode, g, got, want)


def test_every_cone_of_the_examples_on_chosen_wrenches(every_mode):
    answers, lane = every_mode
    assert len([a for a in answers.values() if a.status == S.OK]) >= 8
    for mode, ans in answers.items():
        if fastcheck.entry(mode, ans) is None:
            assert lane.check(mode, 1.0, 0.0, 0.0) is None  # not offered: never answered
            continue
        for g in _wrenches({mode: ans}) + _wrenches(answers)[:40]:
            _same(lane, mode, ans, g)


_finite = hs.floats(-1e3, 1e3, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(g=hs.tuples(_finite, _finite, _finite), pick=hs.integers(0, 10**6),
       scale=hs.sampled_from([1e-6, 1.0, 1e6]))
def test_random_wrenches_on_random_modes(g, pick, scale):
    answers, lane = _CACHE.setdefault("pawl", _every_mode(SCENES[1]))
    modes = [m for m, a in answers.items() if fastcheck.entry(m, a) is not None]
    mode = modes[pick % len(modes)]
    _same(lane, mode, answers[mode], tuple(v * scale for v in g))


_CACHE: dict = {}


def test_a_clear_refuses_cones_computed_before_it():
    answers, _ = _every_mode(SCENES[0])
    lane = _lane_with(answers)
    mode = next(m for m, a in answers.items() if a.status == S.OK)
    assert lane.check(mode, 0.0, 1.0, 0.0) is not None
    before = lane.generation()
    lane.clear()
    assert lane.check(mode, 0.0, 1.0, 0.0) is None  # forgotten at once
    snap = st.Snapshot(2, None, S.OK, "", "world", None, None)
    assert not fastcheck.offer(lane, before, snap, answers)  # computed before the clear
    assert lane.check(mode, 0.0, 1.0, 0.0) is None
    assert fastcheck.offer(lane, lane.generation(), snap, answers)
    assert lane.check(mode, 0.0, 1.0, 0.0) is not None


def test_entries_are_only_concrete_ok_or_infeasible_answers():
    answers, _ = _every_mode(SCENES[1])
    kinds = {a.status for m, a in answers.items() if fastcheck.entry(m, a) is not None}
    assert kinds <= {S.OK, S.MODE_INFEASIBLE}
    scene = load_scene(SCENES[1])
    anything = "*" * scene.n_fixels
    union = st.monitored_answers(st.Snapshot(1, scene, S.OK, "", "world", None, None),
                                 [anything])[anything]
    assert union.union is not None and fastcheck.entry(anything, union) is None


# --- over DDS: the node with the lane on and off ------------------------------------------
WRENCHES = [(0.1, -1.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.3), (-0.2, -1.0, -0.05),
            (0.0, 0.0, 0.0), (3.0, -4.0, 1e-3)]
FIELDS = ("consistent", "status", "message", "other_modes", "other_margins", "only_mode",
          "frame_id", "pose_stamp", "fixels_stamp")


def _replies(h, modes, wrenches):
    return [(m, g, h.check(m, g)) for m in modes for g in wrenches]


def _received_inputs(h) -> int:
    """Publish a pose (stamp 7 s) and fixels (5 s); wait until replies use them and the
    worker published their cones (the lane has them then); return their version."""
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline:  # (again: the inputs are best effort)
        h.publish_fixels([(0.0, -1.0), (1.001, 0.0)], stamp=(5, 0))
        h.publish_pose(0.0, 0.0, 0.0, stamp=(7, 0))
        time.sleep(0.02)
        r = h.check("nn", (0.0, 1.0, 0.0))  # not monitored: the Python handler
        if r.pose_stamp.sec == 7 and r.fixels_stamp.sec == 5:
            break
    col = h.subscribe_cone("na")
    col.wait_for(lambda m: m.inputs_version >= r.inputs_version, "the cone of the inputs")
    while h.node.lane.check("na", 0.0, 1.0, 0.0) is None and time.monotonic() < deadline:
        time.sleep(0.005)  # a refused offer is made again by the worker's next step
    return r.inputs_version


def test_the_lane_answers_as_the_python_handler(harness_factory):
    modes = ["na", "ns", "ss", "aa"]
    on = harness_factory(modes=modes)
    off = harness_factory(modes=modes, fast_check=False)
    version = _received_inputs(on)
    _received_inputs(off)
    before = on.node.lane.stats()
    a, b = (_replies(h, modes, WRENCHES) for h in (on, off))
    after = on.node.lane.stats()
    answerable = [x for _, _, x in a if x.status in (S.OK, S.MODE_INFEASIBLE)]
    assert len(answerable) >= 12
    assert after["fast"] - before["fast"] == len(answerable)  # each by the lane itself
    assert off.node.lane.stats()["fast"] == 0
    statuses = set()
    for (mode, g, x), (_, _, y) in zip(a, b):
        statuses.add(x.status)
        for name in FIELDS:
            assert getattr(x, name) == getattr(y, name), (mode, g, name)
        assert math.isclose(x.margin, y.margin, rel_tol=0, abs_tol=MARGIN_ATOL), (mode, g)
        assert x.pose_stamp.sec == 7 and x.fixels_stamp.sec == 5
        assert 0 <= x.inputs_age < 60 and x.inputs_version == version
    assert {S.OK} <= statuses
    assert any(x.consistent for _, _, x in a) and not all(x.consistent for _, _, x in a)


def test_what_the_lane_cannot_answer_is_forwarded(harness):
    harness.subscribe_cone("na").wait_for(lambda m: True, "the first cone")
    stats = harness.node.lane.stats()
    r = harness.check("na", (0.1, -1.0, 0.0))  # monitored, planar: the lane
    assert r.status == S.OK and r.consistent
    cases = [
        (("ns", (0.1, -1.0, 0.0)), S.OK),  # not monitored
        (("n*", (0.1, -1.0, 0.0)), S.OK),  # wildcards
        (("na", (float("nan"), 0.0, 0.0)), S.INVALID_WRENCH),
        (("na", (0.1, -1.0, 0.0), (1.0, 0.0, 0.0)), S.INVALID_WRENCH),  # out of plane
        (("na", (1e200, -1e201, 0.0)), S.OK),  # rescaled by the Python conversion
        (("nax", (0.1, -1.0, 0.0)), S.INVALID_MODE),
    ]
    for args, status in cases:
        assert harness.check(*args).status == status, args
    r = harness.check("na", (0.1, -1.0, 0.0), classify=True)
    assert r.status == S.OK and r.consistent and "na" not in r.other_modes
    now = harness.node.lane.stats()
    assert now["fast"] - stats["fast"] == 1
    assert now["forwarded"] - stats["forwarded"] == len(cases) + 1
    assert now["failed"] == 0


def test_stale_inputs_are_answered_by_the_python_handler(harness_factory):
    h = harness_factory(input_timeout=0.05)
    deadline = time.monotonic() + DEADLINE_S
    while h.node.store.pose.stamp != (3, 0) and time.monotonic() < deadline:
        h.publish_pose(0.0, 0.0, 0.0, stamp=(3, 0))  # (again: the input is best effort)
        time.sleep(0.02)
        h.get_cone("na")  # a request pulls the pose into the store
    time.sleep(0.2)
    r = h.check("na", (0.1, -1.0, 0.0))
    assert r.status == S.STALE_INPUTS and not r.consistent and "input_timeout" in r.message


def test_the_diagnostics_count_the_lanes_replies(harness):
    from wrenchcone_ros.node.diagnostics import request_status

    harness.subscribe_cone("na").wait_for(lambda m: True, "the first cone")
    for _ in range(3):
        harness.check("na", (0.1, -1.0, 0.0))
    harness.check("ns", (0.1, -1.0, 0.0))  # not monitored: the Python handler
    values = {kv.key: kv.value for kv in request_status("n", harness.node.request_counts).values}
    assert int(values["check_wrench calls"]) == 4
    assert int(values["check_wrench OK"]) == 4
    assert int(values["check_wrench answered by the compiled lane"]) == 3
    assert values["compiled lane serving"] == "True"


def _stop_worker(node) -> None:
    node._stop.set()
    node.inputs.pose_inbox.wake()
    node._worker.join(DEADLINE_S)
    assert not node._worker.is_alive()


def test_new_fixels_or_parameters_make_the_lane_forget_its_cones_at_once(harness):
    """With the worker stopped (so nothing offers new cones), a fixel message or a
    parameter change must empty the lane as soon as the store holds it: the lane never
    answers from cones of inputs that are no longer the newest."""
    h, node = harness, harness.node
    h.subscribe_cone("na").wait_for(lambda m: True, "the first cone")
    assert node.lane.check("na", 0.1, -1.0, 0.0) is not None  # the worker offered it
    _stop_worker(node)
    deadline = time.monotonic() + DEADLINE_S
    while node.store.fixels.stamp != (9, 0) and time.monotonic() < deadline:
        h.publish_fixels([(0.0, -1.0), (1.001, 0.0)], stamp=(9, 0))  # (best effort)
        time.sleep(0.01)
    assert node.lane.check("na", 0.1, -1.0, 0.0) is None
    r = h.check("na", (0.1, -1.0, 0.0))  # answered by the Python handler, new inputs
    assert r.status == S.OK and r.fixels_stamp.sec == 9
    snap = node.snapshot
    fastcheck.offer(node.lane, node.lane.generation(), snap,
                    st.monitored_answers(snap, ["na"]))
    assert node.lane.check("na", 0.1, -1.0, 0.0) is not None
    assert h.set_parameters(friction=0.3)[0].successful
    assert node.lane.check("na", 0.1, -1.0, 0.0) is None


def test_a_long_forwarded_request_does_not_hold_up_the_lane(harness_factory):
    """A request the lane forwards (here a wildcard computing for up to 1 s under
    max_request_time) runs in the Python handler's thread; the lane's thread meanwhile
    answers the monitored modes. Before, the lane's thread called the handler itself and
    every check_wrench waited behind it."""
    from test_node_live import ring

    h = harness_factory(modes=["n" * 8], max_concrete_modes=100_000, max_request_time=1.0)
    h.publish_fixels(ring(8), stamp=(1, 0))
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline:  # until the worker offered the 8-fixel cone
        if h.node.lane.check("n" * 8, 0.0, 1.0, 0.0) is not None:
            break
        time.sleep(0.01)
    heavy = CheckWrench.Request(mode="c" * 7 + "n")
    heavy.wrench.force.y = 1.0
    done = threading.Event()
    future = h.check_cli.call_async(heavy)
    future.add_done_callback(lambda _f: done.set())
    before = h.node.lane.stats()["fast"]
    answered_meanwhile = 0
    while not done.is_set():
        r = h.check("n" * 8, (0.0, 1.0, 0.0))
        assert r.status in (S.OK, S.MODE_INFEASIBLE) and r.fixels_stamp.sec == 1
        answered_meanwhile += not done.is_set()
    assert done.wait(DEADLINE_S)
    assert future.result().status == S.LIMIT_EXCEEDED  # it computed for 1 s, then stopped
    assert answered_meanwhile >= 5
    assert h.node.lane.stats()["fast"] - before >= answered_meanwhile


class _GenerationReadEarly:
    """The lane, but its generation() is the one read before an input changed: what
    the worker sees when a fixel message is stored between its reading the generation
    and taking the snapshot (which then already holds the new fixels)."""

    def __init__(self, lane: fastcheck.Lane, generation: int) -> None:
        self._lane, self._generation = lane, generation

    def generation(self) -> int:
        return self._generation

    def __getattr__(self, name: str):
        return getattr(self._lane, name)


def test_a_refused_offer_is_made_again_for_the_same_snapshot(harness):
    """A flaky failure of test_the_lane_answers_as_the_python_handler (the lane answered
    0 of 18): the worker's offer was refused (a fixel message came between the lane's
    generation and the snapshot), the snapshot was published all the same, and the next
    step skipped it as published: the lane stayed empty until the next input."""
    h, node = harness, harness.node
    h.subscribe_cone("na").wait_for(lambda m: True, "the first cone")
    _stop_worker(node)
    early = node.lane.generation()
    deadline = time.monotonic() + DEADLINE_S
    while node.store.fixels.stamp != (9, 0) and time.monotonic() < deadline:
        h.publish_fixels([(0.0, -1.0), (1.001, 0.0)], stamp=(9, 0))  # (best effort)
        time.sleep(0.01)
    lane = node.lane
    node.lane = _GenerationReadEarly(lane, early)
    try:
        step = node._publish_step(None)  # publishes the new snapshot; offer refused
    finally:
        node.lane = lane
    assert step[2] is False and lane.check("na", 0.1, -1.0, 0.0) is None
    again = node._publish_step(step)
    assert again == (step[0], step[1], True)
    assert lane.check("na", 0.1, -1.0, 0.0) is not None
    assert h.check("na", (0.1, -1.0, 0.0)).fixels_stamp.sec == 9


def test_requests_for_the_python_handler_wait_in_a_bounded_queue(harness_factory):
    """The lane takes every request at once, so requests for the Python handler wait in
    its queue, not in the middleware's (which kept 10 and dropped the rest): without a
    bound, a flood of slow requests grew it without limit. Over max_queued_requests, a
    request is answered LIMIT_EXCEEDED at once; the monitored modes are still answered."""
    from test_node_live import ring

    h = harness_factory(modes=["n" * 8], max_concrete_modes=100_000, max_request_time=0.3,
                        max_queued_requests=2)
    h.publish_fixels(ring(8), stamp=(1, 0))
    deadline = time.monotonic() + DEADLINE_S
    while h.node.lane.check("n" * 8, 0.0, 1.0, 0.0) is None and time.monotonic() < deadline:
        h.publish_fixels(ring(8), stamp=(1, 0))  # (again: the input is best effort)
        time.sleep(0.01)
    heavy = CheckWrench.Request(mode="c" * 7 + "n")
    heavy.wrench.force.y = 1.0
    replies: list = []
    done = threading.Event()

    def got(future) -> None:
        replies.append(future.result())
        if len(replies) == 8:
            done.set()

    for _ in range(8):  # 0.3 s each in the handler's thread: at most 1 + 2 in it or queued
        h.check_cli.call_async(heavy).add_done_callback(got)
    r = h.check("n" * 8, (0.0, 1.0, 0.0))
    assert r.status in (S.OK, S.MODE_INFEASIBLE)  # the lane, meanwhile
    assert done.wait(DEADLINE_S)
    full = [x for x in replies if "max_queued_requests" in x.message]
    assert len(full) >= 8 - 3 and all(x.status == S.LIMIT_EXCEEDED for x in full)
    assert all(x.status == S.LIMIT_EXCEEDED for x in replies)  # the rest: over 0.3 s
    stats = h.node.lane.stats()
    assert stats["queued"] == 0 and stats["refused_queue_full"] == len(full)
