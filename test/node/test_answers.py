# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's per-snapshot answers (node/answers.py), without a ROS graph: every
monitored mode of a pose in ONE call of the core's batched engine, answers equal to the
reference engine mode by mode, and nothing computed for modes nobody monitors."""

from __future__ import annotations

import numpy as np
import pytest

from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_ros.node import answers as an
from wrenchcone_ros.node.store import Snapshot
from wrenchcone_ros.node.status import (
    INVALID_MODE,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    NO_INPUTS,
    OK,
)

PAWL = "examples/pawl_polygon.yaml"


def _snapshot(path: str = PAWL) -> Snapshot:
    return Snapshot(1, load_scene(path), OK, "", "world", None, None)


def test_monitored_modes_are_one_batched_call(monkeypatch):
    calls = []
    real = an.robust_cones

    def counting(scene, modes, *a, **kw):  # the real engine, with its calls counted
        calls.append(list(modes))
        return real(scene, modes, *a, **kw)

    monkeypatch.setattr(an, "robust_cones", counting)
    snap = _snapshot()
    modes = ["arr", "ann", "all", "aln", "arn", "ass", "sss", "snn", "a**", "ac*"]
    answers = an.monitored_answers(snap, modes)
    assert calls == [modes]  # one call for every monitored mode of the pose
    assert list(answers) == modes
    # nothing computed for modes nobody monitors: the cache holds exactly these
    assert set(k for k in snap.answers if isinstance(k, str)) == set(modes)
    an.monitored_answers(snap, modes)  # the same snapshot again: all cached
    assert len(calls) == 1


def test_batched_answers_equal_the_reference_engine_mode_by_mode():
    snap = _snapshot()
    modes = ["arr", "ann", "all", "nnn", "sss", "snn", "xrr", "nrr", "a*c", "rrr"]
    answers = an.monitored_answers(snap, modes)
    for mode in modes:
        try:
            ref = wrench_cone(snap.scene, mode, engine="numpy")
        except ValueError as exc:  # ModeSyntaxError / ModeError: not a cone
            assert answers[mode].status in (INVALID_MODE, MODE_NOT_ALLOWED), mode
            assert answers[mode].message == str(exc)
            continue
        ans = answers[mode]
        assert ans.status == (OK if ref.feasible else MODE_INFEASIBLE), mode
        if ans.cone is None:  # a wildcard mode: the union of its modes' cones
            assert ans.wrenches.modes == ref.modes
            continue
        for got, want in ((ans.cone.F, ref.F), (ans.cone.equalities, ref.equalities)):
            assert got.shape == want.shape, mode
            assert np.allclose(got, want, atol=1e-12), mode
    assert answers["xrr"].status == INVALID_MODE
    assert answers["nrr"].status == MODE_NOT_ALLOWED  # fixel 1 is not touched


def test_a_monitored_mode_over_a_limit_is_refused_without_computing(monkeypatch):
    seen = []
    real = an.robust_cones
    monkeypatch.setattr(an, "robust_cones",
                        lambda scene, modes, *a, **kw: seen.extend(modes)
                        or real(scene, modes, *a, **kw))
    snap = _snapshot()
    limits = an.Limits(max_mode_length=64, max_concrete_modes=2, max_classify_nodes=100)
    answers = an.monitored_answers(snap, ["arr", "***"], limits=limits)
    assert answers["***"].status == LIMIT_EXCEEDED
    assert answers["arr"].status == OK
    assert seen == ["arr"]


@pytest.mark.parametrize("path", [PAWL, "examples/paper_disc.yaml"])
def test_no_scene_no_computation(path, monkeypatch):
    monkeypatch.setattr(an, "robust_cones", lambda *a, **k: pytest.fail("computed"))
    snap = Snapshot(2, None, NO_INPUTS, "no input yet", "world", None, None)
    answers = an.monitored_answers(snap, ["arr", "na"])
    assert {a.status for a in answers.values()} == {NO_INPUTS}


def _rss_mib() -> float:
    """This process's resident set (the node runs in it), MiB, from /proc/self/status."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    raise AssertionError("no VmRSS in /proc/self/status")


def test_distinct_long_refused_modes_do_not_grow_the_node(harness_factory):
    """300 distinct 100,000-letter modes, each refused as INVALID_MODE, sent to
    check_wrench, get_cone and force_directions: the node's memory grows by less than
    10 MiB, and stays so after a new pose. Before, the refusals were cached by the mode
    string (up to CACHE_LIMIT per snapshot: 30 MiB and more here, about 100 MiB at 1,000
    modes), and the memory stayed taken."""
    from wrenchcone_msgs.srv import ForceDirections

    # the time limit off: this is about memory, and a loaded machine may take more than
    # max_request_time's default to refuse a 100,000-letter mode (LIMIT_EXCEEDED then)
    h = harness_factory(max_mode_length=100_000, max_request_time=0.0)
    directions = h.tester.create_client(ForceDirections,
                                        f"{h.ns}/wrenchcone/force_directions")
    assert directions.wait_for_service(timeout_sec=30.0)

    def send(k: int) -> None:
        mode = "n" * 99_990 + f"x{k:09d}"  # 'x' and digits: no mode letters
        assert h.check(mode, (0.1, -1.0, 0.0)).status == INVALID_MODE
        assert h.get_cone(mode).status == INVALID_MODE
        assert h._call(directions, ForceDirections.Request(mode=mode)).status == INVALID_MODE

    for k in range(50):  # warm up: the allocators' and the middleware's buffers
        send(k)
    before = _rss_mib()
    for k in range(50, 350):
        send(k)
    after = _rss_mib()
    version = h.get_cone("na").inputs_version
    h.publish_pose(0.0, 0.0, 0.05)
    h.wait_version_above(version)
    for k in range(350, 360):
        send(k)
    after_pose = _rss_mib()
    print(f"RSS MiB: before {before:.1f}, after 300 modes {after:.1f}, "
          f"after a new pose {after_pose:.1f}")
    assert after - before < 10.0, (before, after)
    assert after_pose - before < 10.0, (before, after_pose)


def test_the_nominal_snapshot_is_the_zero_width_uncertainty():
    """A snapshot without uncertainty.* (NOMINAL) and one with zero-width friction
    intervals answer the same cones and classifications, through the one code path
    (robust_cones, the snapshot's classifier); both agree with the reference engine and
    the LP oracle; only the explicit set is named in the messages."""
    from types import SimpleNamespace

    from wrenchcone_ros.core import NOMINAL, Uncertainty
    from wrenchcone_ros.core.lp_check import lp_consistent
    from wrenchcone_ros.node import services

    scene = load_scene(PAWL)
    zero = Uncertainty(friction=[(scene.mu(i), scene.mu(i)) for i in range(scene.n_fixels)])
    nominal = Snapshot(1, scene, OK, "", "world", None, None)
    explicit = Snapshot(1, scene, OK, "", "world", None, None, uncertainty=zero)
    assert nominal.uncertainty is NOMINAL
    rng = np.random.default_rng(3)
    wrenches = [rng.normal(size=3) * (1.0, 1.0, scene.length_scale) for _ in range(4)]
    for mode in ["arr", "ann", "snn", "a**", "xrr", "nrr"]:
        a, b = an.compute_answer(nominal, mode), an.compute_answer(explicit, mode)
        assert a.status == b.status, mode
        assert not a.uncertainty and not a.guarantee and "model" not in a.message
        if a.wrenches is None:
            assert a.message in b.message
            continue
        assert b.uncertainty == zero.describe() and b.guarantee == "exact"
        ref = wrench_cone(scene, mode, engine="numpy")
        for x, y in zip(a.wrenches.pieces, b.wrenches.pieces):
            assert np.array_equal(x.F, y.F) and np.array_equal(x.equalities, y.equalities)
        assert list(a.wrenches.modes) == list(getattr(ref, "modes", [ref.mode]))
        for g in wrenches:
            inside = a.wrenches.check(g)[0]
            assert inside == b.wrenches.check(g)[0]
            lp = [lp_consistent(scene, m, g) for m in a.wrenches.modes]
            if all(r.decided for r in lp) and abs(a.wrenches.margin(g)) > 1e-6:
                assert inside == any(r.consistent for r in lp), (mode, g)
    node = SimpleNamespace(limits=an.Limits())
    for g in wrenches:
        c, d = services.classify(node, nominal, g), services.classify(node, explicit, g)
        def fields(x):
            return [(m.mode, m.certain, m.margin, m.margin_all) for m in x.matches]
        assert fields(c) == fields(d)
        assert not c.robust and d.robust and d.guarantee == "exact"
        assert all(m.certain and m.margin == m.margin_all for m in c.matches)
        for m in (m.mode for m in c.matches):
            assert lp_consistent(scene, m, g).consistent or \
                abs(wrench_cone(scene, m).margin(g)) < 1e-6
