# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's ``uncertainty.*`` parameters over real DDS: ``~/force_directions``, the cone
topic, ``~/check_wrench`` (compiled lane and Python handler) and ``~/get_cone`` answer for
every model of the set they describe, equal to the core's robust answer and named by the
topic's uncertainty and guarantee fields; bad values are refused with a message naming
the parameter; the nominal answers (empty fields) when none is set."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from helpers.node_harness import published_rows, same_rows

from helpers.node_directions import PAWL, S, call
from wrenchcone_ros.core import (
    Uncertainty,
    force_directions,
    load_scene,
    robust_cone,
    wrench_cone,
)
from wrenchcone_msgs.msg import Status
from wrenchcone_ros.ros import conversions as conv


@pytest.fixture
def pawl(harness_factory):
    return harness_factory(scene_file=os.path.abspath(PAWL))


@pytest.fixture
def pawl_arr(harness_factory):
    """The pawl monitoring 'arr' (a cone topic, and the compiled lane's mode)."""
    return harness_factory(scene_file=os.path.abspath(PAWL), modes=["arr"])


def test_force_directions_for_every_model_equals_the_core(pawl):
    scene = load_scene(PAWL)
    r = call(pawl, "arr")
    assert r.status == S.OK and r.message == ""
    assert r.intervals[0].lo == pytest.approx(math.atan2(-10, 3), abs=1e-12)
    results = pawl.set_parameters(uncertainty__friction=[0.2, 0.4])
    assert all(x.successful for x in results), [x.reason for x in results]
    for mode, point, exclusive in [("arr", None, False), ("arr", None, True),
                                   ("arr", (0.0075, 0.035), False)]:
        r = call(pawl, mode, point, exclusive)
        assert r.status == S.OK, r.message
        core = force_directions(scene, mode, point=point, exclusive=exclusive,
                                uncertainty=Uncertainty(friction=(0.2, 0.4)))
        assert [(iv.lo, iv.hi, iv.margin) for iv in r.intervals] == [
            (iv.lo, iv.hi, iv.margin) for iv in core]
        assert "for every model of friction [0.2, 0.4]" in r.message and "exact" in r.message
    assert r.intervals[0].lo != pytest.approx(math.atan2(-10, 3), abs=1e-6)
    results = pawl.set_parameters(uncertainty__friction=[0.2, 0.4], uncertainty__com_radius=1e-3)
    assert all(x.successful for x in results)
    r = call(pawl, "arr")
    assert r.status == S.OK and "scenario(eps=0.05, beta=0.001, N=220)" in r.message
    core = force_directions(scene, "arr", uncertainty=Uncertainty(friction=(0.2, 0.4),
                                                                   com_radius=1e-3))
    assert [iv.best for iv in r.intervals] == [iv.best for iv in core]


def test_bad_uncertainty_is_refused(pawl):
    (res,) = pawl.set_parameters(uncertainty__friction=[0.4, 0.2])
    assert not res.successful and "uncertainty" in res.reason and "lo must be <= hi" in res.reason
    (res,) = pawl.set_parameters(uncertainty__normal_error=2.0)
    # refused by rclpy itself (the parameter's declared range [0, pi/2))
    assert not res.successful and "out of range" in res.reason and "1.57" in res.reason
    r = call(pawl, "arr")
    assert r.status == S.OK and r.message == ""  # still the nominal answer


# --- the cone topic, check_wrench and get_cone under the uncertainty parameters ----------
U = Uncertainty(friction=(0.2, 0.4))
#: The nominal recommended tilt on the pawl (docs/tutorial.md): the load m g along it.
TILT = math.radians(-68.71)


def _tilt_wrench(scene):
    w = scene.workpiece.mass * 9.81
    return (math.cos(TILT) * w, math.sin(TILT) * w, 0.0)


def _clear_friction(h):
    """uncertainty.friction back to unset (an empty double array)."""
    from rcl_interfaces.msg import Parameter as ParameterMsg
    from rcl_interfaces.msg import ParameterType, ParameterValue
    from rcl_interfaces.srv import SetParameters

    value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[])
    req = SetParameters.Request(parameters=[ParameterMsg(name="uncertainty.friction",
                                                         value=value)])
    return list(h._call(h.param_cli, req).results)


def _answers(h, g, version):
    """check_wrench('arr', g) until a reply comes from inputs version ``version`` or
    newer (the parameter change has reached the snapshot)."""
    replies = []
    for _ in range(200):
        r = h.check("arr", g)
        if r.inputs_version >= version:
            replies.append(r)
            return replies
    raise AssertionError("no reply from the new inputs")


def _same_published_cone(msg, cone):
    F, E, status = published_rows(msg)
    return (status is None and same_rows(F, cone.F) and same_rows(E, cone.equalities)
            and same_rows(conv.rows_from_flat(msg.generators), cone.G)
            and msg.length_scale == cone.length_scale)


def test_cone_topic_and_check_wrench_answer_for_every_model(pawl_arr):
    h, scene = pawl_arr, load_scene(PAWL)
    g = _tilt_wrench(scene)
    col = h.subscribe_cone("arr")
    nominal = col.wait_for(lambda m: m.feasible, "the nominal cone")
    assert nominal.uncertainty == "" and nominal.guarantee == "" and nominal.message == ""
    assert _same_published_cone(nominal, wrench_cone(scene, "arr"))
    replies = _answers(h, g, 0)
    assert all(r.status == S.OK and r.consistent and r.message == "" for r in replies)
    version = replies[-1].inputs_version

    results = h.set_parameters(uncertainty__friction=[0.2, 0.4])
    assert all(x.successful for x in results), [x.reason for x in results]
    msg = col.wait_for(lambda m: m.uncertainty != "", "the robust cone")
    robust = robust_cone(scene, "arr", U, "all")
    assert msg.status == Status.OK and msg.feasible
    assert _same_published_cone(msg, robust.cone)
    assert msg.uncertainty == U.describe() == "friction [0.2, 0.4]"
    assert msg.guarantee == "exact" == str(robust.guarantee)
    assert "for every model of friction [0.2, 0.4]" in msg.message
    # independent of the robust engine: every published generator is consistent with
    # 'arr' at mu_lo, mu_hi and interior mu (the nominal cone of each sampled model)
    G = conv.rows_from_flat(msg.generators)
    for mu in np.linspace(0.2, 0.4, 9):
        d = scene.to_dict()
        d["friction"] = float(mu)
        model = wrench_cone(load_scene(d), "arr")
        assert all(model.contains(row) for row in G), mu
    # the nominal recommendation is consistent nominally, not for every model
    assert wrench_cone(scene, "arr").contains(g) and not robust.cone.contains(g)
    replies = _answers(h, g, version + 1)
    for r in replies:
        assert r.status == S.OK and not r.consistent, r.message
        assert r.margin == pytest.approx(robust.cone.margin(g), abs=1e-9)
        assert r.message == "for every model of friction [0.2, 0.4] (guarantee exact)"
        assert r.inputs_version >= msg.inputs_version
    cone = h.get_cone("arr")
    assert cone.status == S.OK and cone.message == msg.message
    assert same_rows(conv.rows_from_flat(cone.inequalities), robust.cone.F)
    r = h.check("arr", g, classify=True)  # the Python handler: the same robust verdict
    assert r.status == S.OK and not r.consistent and "others: for some model" in r.message
    r = h.check("a*r", g)
    assert r.status == S.INVALID_MODE and "concrete modes only" in r.message
    assert "arr" in r.message and not r.consistent

    results = _clear_friction(h)  # back to the nominal model: never a robust answer
    assert all(x.successful for x in results), [x.reason for x in results]
    back = col.wait_for(lambda m: m.inputs_version > msg.inputs_version, "the nominal cone")
    assert back.uncertainty == "" and back.guarantee == "" and back.message == ""
    assert _same_published_cone(back, wrench_cone(scene, "arr"))
    replies = _answers(h, g, 0)
    assert all(r.status == S.OK and r.consistent and r.message == "" for r in replies)
    version = replies[-1].inputs_version


def test_a_scenario_guarantee_is_published(pawl_arr):
    h, scene = pawl_arr, load_scene(PAWL)
    col = h.subscribe_cone("arr")
    col.wait_for(lambda m: m.feasible, "the nominal cone")
    u = Uncertainty(friction=(0.2, 0.4), com_radius=1e-3)
    results = h.set_parameters(uncertainty__friction=[0.2, 0.4],
                               uncertainty__com_radius=1e-3)
    assert all(x.successful for x in results)
    msg = col.wait_for(lambda m: "com_radius" in m.uncertainty, "the scenario cone")
    core = robust_cone(scene, "arr", u, "all")
    assert msg.guarantee == str(core.guarantee) == "scenario(eps=0.05, beta=0.001, N=220)"
    assert msg.uncertainty == u.describe() and _same_published_cone(msg, core.cone)


def test_a_snapshots_answers_are_for_its_own_uncertainty():
    """No DDS: the batched monitored answers equal the one-mode answers, both the core's
    robust cone; a snapshot without uncertainty answers nominally; a wildcard refusal
    names the set and is not cached."""
    from wrenchcone_ros.node.answers import cached_answer, monitored_answers
    from wrenchcone_ros.node.store import Snapshot

    scene = load_scene(PAWL)
    robust = Snapshot(1, scene, S.OK, "", "world", None, None, uncertainty=U)
    nominal = Snapshot(2, scene, S.OK, "", "world", None, None)
    modes = ["arr", "snn", "a*r"]
    batch = monitored_answers(robust, modes)
    for mode in ("arr", "snn"):
        one = cached_answer(Snapshot(3, scene, S.OK, "", "world", None, None,
                                     uncertainty=U), mode)
        core = robust_cone(scene, mode, U, "all")
        for ans in (batch[mode], one):
            assert ans.uncertainty == "friction [0.2, 0.4]" and ans.guarantee == "exact"
            assert same_rows(ans.cone.F, core.cone.F), mode
            assert ans.message.endswith("for every model of friction [0.2, 0.4] "
                                        "(guarantee exact)")
        plain = cached_answer(nominal, mode)
        assert plain.uncertainty == plain.guarantee == ""
        assert same_rows(plain.cone.F, wrench_cone(scene, mode).F)
    wild = batch["a*r"]
    assert wild.status == S.INVALID_MODE and wild.uncertainty == "friction [0.2, 0.4]"
    assert "a*r" not in robust.answers and "arr" in robust.answers
    assert cached_answer(nominal, "a*r").status == S.OK  # nominally a union of cones
