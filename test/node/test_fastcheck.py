"""The compiled check_wrench lane (src/fastcheck.c, node/fastcheck.py) and its boundary
(node/rclpy_boundary.py).

Its check is a port of the Python reference (cones._Query.check, itself checked against
an NNLS distance in test/core/test_cones.py), handed the reference's own margin
geometry: here every cone of every valid mode of the example scenes, on chosen and
random wrenches, must give the same membership and the same margin, bit for bit. The
rules handed to C as data are checked against the Python functions that define them
(freshness.freshness, conversions.wrench_to_planar, the pose window). Over DDS, the
node's replies with the lane on must equal its replies with the lane off (every request
then answered by the Python handler), field by field, and the lane must really have
answered them; what it cannot answer is forwarded and answered as before. Without the
lane (extension missing, another rclpy version, fast_check false) the node starts and
answers every service."""

from __future__ import annotations

import itertools
import math
import threading
import time

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as hs
from node_harness import DEADLINE_S, pose_message
from test_node_inputs import inbox_and_publisher, wait_for_message  # noqa: F401 - fixture
from rclpy.clock import Clock, ClockType

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.core.modes import enumerate_modes
from wrenchcone_ros.node import fastcheck, rclpy_boundary
from wrenchcone_ros.node.parameters import fast_check_default
from wrenchcone_ros.node.freshness import freshness
from wrenchcone_ros.node import status as S
from wrenchcone_msgs.srv import CheckWrench
from wrenchcone_ros.node import answers as st
from wrenchcone_ros.node.store import Snapshot

SCENES = ("examples/paper_disc.yaml", "examples/pawl_polygon.yaml")
_CLOCK = Clock(clock_type=ClockType.STEADY_TIME)
#: Why this run has no compiled lane (None: it has one): lane-only tests are skipped then
#: (CI runs the node tests a second time with WRENCHCONE_FAST_CHECK=0)
NO_LANE = fastcheck.unavailable(fast_check_default())
needs_lane = pytest.mark.skipif(NO_LANE is not None, reason=f"no compiled lane: {NO_LANE}")


def _lane_with(answers: dict[str, st.Answer], version: int = 1) -> fastcheck.CompiledLane:
    lane = fastcheck.CompiledLane(_CLOCK)
    snap = Snapshot(version, None, S.OK, "", "world", None, None)
    assert fastcheck.offer(lane, lane.generation(), snap, answers)
    return lane


def _every_mode(path: str) -> tuple[dict[str, st.Answer], fastcheck.CompiledLane]:
    scene = load_scene(path)
    snap = Snapshot(1, scene, S.OK, "", "world", None, None)
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


def _same(lane: fastcheck.CompiledLane, mode: str, ans: st.Answer, g) -> None:
    got = lane.check(mode, *g)
    if ans.status == S.MODE_INFEASIBLE or ans.cone is None:
        assert got == (False, -1.0)
        return
    want = ans.cone.check(g)
    # the same float operations on the same numbers (the reference's own geometry): the
    # same bits, outside the cone too
    assert got == want, (mode, g, got, want)


@needs_lane
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


@needs_lane
@settings(max_examples=300, deadline=None)
@given(g=hs.tuples(_finite, _finite, _finite), pick=hs.integers(0, 10**6),
       scale=hs.sampled_from([1e-6, 1.0, 1e6]))
def test_random_wrenches_on_random_modes(g, pick, scale):
    answers, lane = _CACHE.setdefault("pawl", _every_mode(SCENES[1]))
    modes = [m for m, a in answers.items() if fastcheck.entry(m, a) is not None]
    mode = modes[pick % len(modes)]
    _same(lane, mode, answers[mode], tuple(v * scale for v in g))


_CACHE: dict = {}


@needs_lane
def test_a_clear_refuses_cones_computed_before_it():
    answers, _ = _every_mode(SCENES[0])
    lane = _lane_with(answers)
    mode = next(m for m, a in answers.items() if a.status == S.OK)
    assert lane.check(mode, 0.0, 1.0, 0.0) is not None
    before = lane.generation()
    lane.clear()
    assert lane.check(mode, 0.0, 1.0, 0.0) is None  # forgotten at once
    snap = Snapshot(2, None, S.OK, "", "world", None, None)
    assert not fastcheck.offer(lane, before, snap, answers)  # computed before the clear
    assert lane.check(mode, 0.0, 1.0, 0.0) is None
    assert fastcheck.offer(lane, lane.generation(), snap, answers)
    assert lane.check(mode, 0.0, 1.0, 0.0) is not None


@needs_lane
def test_entries_are_only_concrete_ok_or_infeasible_answers():
    answers, _ = _every_mode(SCENES[1])
    kinds = {a.status for m, a in answers.items() if fastcheck.entry(m, a) is not None}
    assert kinds <= {S.OK, S.MODE_INFEASIBLE}
    scene = load_scene(SCENES[1])
    anything = "*" * scene.n_fixels
    union = st.monitored_answers(Snapshot(1, scene, S.OK, "", "world", None, None),
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


@needs_lane
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
    assert not off.node.lane and "fast_check" in off.node.lane.why  # no compiled lane
    statuses = set()
    for (mode, g, x), (_, _, y) in zip(a, b):
        statuses.add(x.status)
        for name in FIELDS:
            assert getattr(x, name) == getattr(y, name), (mode, g, name)
        assert x.margin == y.margin, (mode, g)  # the same bits
        assert x.pose_stamp.sec == 7 and x.fixels_stamp.sec == 5
        assert 0 <= x.inputs_age < 60 and x.inputs_version == version
    assert {S.OK} <= statuses
    assert any(x.consistent for _, _, x in a) and not all(x.consistent for _, _, x in a)


@needs_lane
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


@needs_lane
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
    node.worker.stop(DEADLINE_S)
    assert not node.worker.thread.is_alive()


@needs_lane
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


@needs_lane
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


@needs_lane
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
        step = node.worker.step(None)  # publishes the new snapshot; offer refused
    finally:
        node.lane = lane
    assert step[2] is False and lane.check("na", 0.1, -1.0, 0.0) is None
    again = node.worker.step(step)
    assert again == (step[0], step[1], True)
    assert lane.check("na", 0.1, -1.0, 0.0) is not None
    assert h.check("na", (0.1, -1.0, 0.0)).fixels_stamp.sec == 9


@needs_lane
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


# --- the rules handed to C as data, against the Python functions that define them -------
@settings(max_examples=300, deadline=None)
@given(received=hs.integers(0, 10**15), other=hs.one_of(hs.none(), hs.integers(0, 10**15)),
       timeouts=hs.tuples(hs.sampled_from([0.0, 1e-9, 0.001, 0.05, 0.1, 0.3, 1.0, 7.3, 1e6]),
                          hs.sampled_from([0.0, 1e-9, 0.02, 0.7, 3.0])))
def test_fresh_until_is_the_last_instant_freshness_calls_fresh(received, other, timeouts):
    snap = Snapshot(1, None, S.OK, "", "world", (1, 0), None, received, other)
    until = fastcheck.fresh_until_ns(snap, *timeouts)
    if until == fastcheck.NEVER_NS:
        assert all(t <= 0 for t, r in zip(timeouts, (received, other)) if r is not None)
        assert not freshness(snap, received + 10**18, *timeouts).stale
        return
    assert not freshness(snap, until, *timeouts).stale
    assert freshness(snap, until + 1, *timeouts).stale


def test_pose_until_is_the_stores_reuse_window():
    """store.InputStore.current reuses a snapshot for a pose received at most
    pose_reuse_window after the snapshot's own; the lane may answer for exactly those."""
    snap = Snapshot(1, None, S.OK, "", "world", (1, 0), None, 5_000, None)
    assert fastcheck.pose_until_ns(snap, 0) == 5_000  # only its own pose
    assert fastcheck.pose_until_ns(snap, 2_000_000) == 2_005_000
    scene_own = Snapshot(1, None, S.OK, "", "world", None, None, None, None)
    assert fastcheck.pose_until_ns(scene_own, 10**9) == -1  # any received pose is newer


_magnitude = hs.floats(0.0, 1e300, allow_nan=False)


@settings(max_examples=500, deadline=None)
@example(g=(fastcheck.AS_SENT[1], 0.0, 0.0), signs=(1.0, 1.0, 1.0))  # the bounds ...
@example(g=(0.0, fastcheck.AS_SENT[0], 0.0), signs=(1.0, -1.0, 1.0))
@example(g=(0.0, 0.0, math.nextafter(fastcheck.AS_SENT[1], math.inf)), signs=(1.0,) * 3)
@example(g=(math.nextafter(fastcheck.AS_SENT[0], 0.0), 0.0, 0.0), signs=(-1.0,) * 3)
@example(g=(1e-200, 3e-101, 0.0), signs=(1.0,) * 3)  # ... and just outside them
@given(g=hs.tuples(_magnitude, _magnitude, _magnitude),
       signs=hs.tuples(*[hs.sampled_from([1.0, -1.0])] * 3))
def test_a_wrench_the_lane_takes_is_the_one_the_python_conversion_keeps(g, signs):
    """The lane answers a wrench planar as sent (force.z, torque.x, torque.y zero) whose
    largest part is 0 or within AS_SENT, unchanged; conversions.wrench_to_planar must keep
    exactly those unchanged (never rescaled, never refused), and rescale the others."""
    from wrenchcone_ros.ros.conversions import planar_to_wrench, wrench_to_planar

    fx, fy, tz = (v * s for v, s in zip(g, signs))
    big = max(abs(fx), abs(fy), abs(tz))
    lo, hi = fastcheck.AS_SENT
    taken = big == 0.0 or lo <= big <= hi
    kept = wrench_to_planar(planar_to_wrench((fx, fy, tz)), 1.0, 0.0)
    assert (kept == (fx, fy, tz)) == taken


@needs_lane
def test_the_lane_answers_only_within_its_deadlines(inbox_and_publisher):  # noqa: F811
    """The lane's cones may answer while no pose newer than theirs was received, or one
    received at most pose_reuse_window after theirs, and while the inputs are fresh
    (the deadlines Python hands over); never once either has passed."""
    inbox, publisher = inbox_and_publisher
    lane = inbox.lane
    publisher.publish(pose_message(1))
    wait_for_message(inbox)
    _, received = inbox.take_newest()
    snap = Snapshot(3, None, S.OK, "", "world", (1, 0), None, received, None)

    def usable(window_ns: int, input_timeout: float = 0.0) -> bool:
        lane.configure({"pose_reuse_window": window_ns * 1e-9, "input_timeout": input_timeout,
                        "fixels_timeout": 0.0, "max_queued_requests": 64})
        assert fastcheck.offer(lane, lane.generation(), snap, {})
        return lane.usable()

    assert usable(0)  # no newer pose
    publisher.publish(pose_message(2))
    wait_for_message(inbox)
    _, newer = inbox.take_newest()
    assert not usable(0)  # window 0: a newer pose exists
    assert usable(newer - received)  # just within the window
    assert not usable(newer - received - 1)
    assert usable(10**9, input_timeout=60.0)
    time.sleep(0.01)
    assert not usable(10**9, input_timeout=1e-9)  # the pose is older than input_timeout


@needs_lane
def test_a_pose_the_check_wrench_thread_took_wakes_the_worker(harness):
    """The compiled lane takes the waiting pose at every check_wrench request (to know
    the newest); then nothing is waiting in the middleware any more, and only its
    trigger of the worker's guard condition ends the worker's wait."""
    h, node = harness, harness.node
    node.worker.stop(DEADLINE_S)
    assert not node.worker.thread.is_alive()
    node.inputs.pose_inbox.wait(0.05)  # consume a wake the worker left unconsumed
    before = node.lane.stats()["poses_taken"]
    deadline = time.monotonic() + DEADLINE_S
    while node.lane.stats()["poses_taken"] == before and time.monotonic() < deadline:
        h.publish_pose(0.0, 0.0, 0.1, stamp=(3, 0))  # (again: the input is best effort)
        time.sleep(0.01)
        h.check("na", (0.1, -1.0, 0.0))  # the lane's thread takes the pose if it arrived
    assert node.lane.stats()["poses_taken"] == before + 1
    wait_for_message(node.inputs.pose_inbox)  # ends at once: the lane woke it
    assert node.snapshot.pose_stamp == (3, 0)  # and the pose is in the lane for Python


# --- the boundary: another rclpy version, no extension, fast_check false ------------------
@pytest.mark.parametrize("version", ["7.2.0", "8.0.1", "7.10.0", "6.1.5", "rolling", None])
def test_another_rclpy_version_is_refused_in_one_line(monkeypatch, version):
    monkeypatch.setattr(rclpy_boundary, "INSTALLED", version)
    why = rclpy_boundary.refusal()
    assert why is not None and "\n" not in why
    assert (str(version) if version else "unknown") in why
    assert "Python handler" in why
    if version is not None:
        assert rclpy_boundary.WRITTEN_FOR in why
    assert not rclpy_boundary.accepted()
    with pytest.raises(RuntimeError, match="Python handler"):
        rclpy_boundary.handle_pointer(_CLOCK)  # no private access at all then
    with pytest.raises(RuntimeError, match="Python handler"):
        rclpy_boundary.convert_from_py(CheckWrench.Response)
    assert fastcheck.unavailable(True) == why or fastcheck._fastcheck is None


def test_the_version_it_was_written_for_and_its_series_are_accepted(monkeypatch):
    for version in (rclpy_boundary.WRITTEN_FOR, "7.1.0", "7.1.6", "7.1.5.post1"):
        monkeypatch.setattr(rclpy_boundary, "INSTALLED", version)
        assert rclpy_boundary.refusal() is None, version
    assert rclpy_boundary.installed_version() is not None  # this machine's rclpy is known


def _answers_every_service(h, *, pose_sec: int) -> None:
    """Every service of the node answers, from the inputs the test published."""
    from wrenchcone_msgs.srv import ForceDirections

    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline:  # (again: the inputs are best effort)
        h.publish_fixels([(0.0, -1.0), (1.001, 0.0)], stamp=(5, 0))
        h.publish_pose(0.0, 0.0, 0.0, stamp=(pose_sec, 0))
        time.sleep(0.02)
        r = h.check("na", (0.1, -1.0, 0.0))
        if r.pose_stamp.sec == pose_sec and r.fixels_stamp.sec == 5:
            break
    assert r.status == S.OK and r.consistent and r.pose_stamp.sec == pose_sec
    assert h.check("na", (0.1, -1.0, 0.0), classify=True).status == S.OK
    assert h.get_cone("na").status == S.OK
    assert h.classify((0.1, -1.0, 0.0)).status == S.OK
    cli = h.tester.create_client(ForceDirections, f"{h.ns}/wrenchcone/force_directions")
    assert cli.wait_for_service(timeout_sec=DEADLINE_S)
    assert h._call(cli, ForceDirections.Request(mode="na")).status == S.OK


def test_the_node_on_another_rclpy_version_answers_every_service(monkeypatch,
                                                                 harness_factory):
    """On an rclpy it was not written for the node touches no private name: no compiled
    lane, check_wrench by the Python handler, the pose taken by a subscription callback
    (public API); every service answers, from the pose published."""
    monkeypatch.setattr(rclpy_boundary, "INSTALLED", "7.2.0")
    h = harness_factory(modes=["na"], fast_check=True)
    assert not h.node.lane and "rclpy 7.2.0" in h.node.lane.why
    assert h.node.inputs.pose_inbox._wait is None  # the public fallback takes the pose
    _answers_every_service(h, pose_sec=11)
    names = h.node.list_parameters(["qos_overrides"], 0).names
    assert any("workpiece_pose" in n and n.endswith("reliability") for n in names), names


def test_fast_check_false_is_the_python_handler_and_read_only(harness_factory):
    h = harness_factory(modes=["na"], fast_check=False)
    assert not h.node.lane and "fast_check is false" in h.node.lane.why
    _answers_every_service(h, pose_sec=12)
    [res] = h.set_parameters(fast_check=True)
    assert not res.successful  # read at start only
    assert h.node.get_parameter("fast_check").value is False


def test_fast_check_defaults_to_the_environment():
    from wrenchcone_ros.node.parameters import FAST_CHECK_ENV

    assert fast_check_default({}) is True
    for text, value in (("0", False), ("false", False), (" OFF ", False), ("no", False),
                        ("1", True), ("True", True), ("on", True), ("", True)):
        assert fast_check_default({FAST_CHECK_ENV: text}) is value, text
    with pytest.raises(ValueError, match=f"{FAST_CHECK_ENV}='maybe' is not a boolean"):
        fast_check_default({FAST_CHECK_ENV: "maybe"})


_NO_EXTENSION = r"""
import json, sys, importlib.abc
sys.path.insert(0, "test/node")

class Blocker(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name == "wrenchcone_ros.node._fastcheck":
            raise ImportError("blocked by the test: the extension is not built")
        return None

sys.meta_path.insert(0, Blocker())
import conftest  # the node tests' isolation (domain id, localhost)
import rclpy
from node_harness import Harness
import test_fastcheck as t

context = rclpy.context.Context()
rclpy.init(context=context)
h = Harness(context, {"modes": ["na"]})
try:
    print(json.dumps({"why": h.node.lane.why, "lane": bool(h.node.lane)}))
    t._answers_every_service(h, pose_sec=13)
    print("every service answered")
finally:
    h.close()
    rclpy.shutdown(context=context)
"""


def test_the_node_without_the_extension_starts_and_answers_every_service():
    """The extension missing (its import fails: a sys.meta_path blocker in a process of
    its own): the node starts, says why in one log line, and answers every service."""
    import json
    import os
    import subprocess
    import sys

    from wrenchcone_ros.node.parameters import FAST_CHECK_ENV

    proc = subprocess.run([sys.executable, "-P", "-c", _NO_EXTENSION], capture_output=True,
                          text=True, timeout=120, env={**os.environ, FAST_CHECK_ENV: "1"})
    assert proc.returncode == 0, proc.stdout + proc.stderr
    first, last = proc.stdout.strip().splitlines()[0], proc.stdout.strip().splitlines()[-1]
    state = json.loads(first)
    assert state["lane"] is False and "not built" in state["why"]
    assert last == "every service answered"
    lines = [x for x in proc.stderr.splitlines() if "compiled check_wrench lane" in x]
    assert len(lines) == 1 and "blocked by the test" in lines[0], proc.stderr


def test_rclpy_internals_are_used_in_the_boundary_module_only():
    """Every rclpy-private name the package uses lives in node/rclpy_boundary.py (the
    module checked against the rclpy version): none anywhere else in the package."""
    from pathlib import Path

    import wrenchcone_ros

    private = ("handle.pointer", "_CONVERT_FROM_PY", "__import_type_support__",
               "rclpy_implementation", "rclpy.impl", "_declare_qos_parameters",
               "take_message", "_rclpy")
    root = Path(wrenchcone_ros.__file__).resolve().parent
    found = {(str(path.relative_to(root)), name)
             for path in root.rglob("*.py") if path.name != "rclpy_boundary.py"
             for name in private if name in path.read_text()}
    assert not found, sorted(found)
    boundary = (root / "node" / "rclpy_boundary.py").read_text()
    assert all(name in boundary for name in private if name != "_rclpy")
