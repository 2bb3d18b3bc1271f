"""The node's ``uncertainty.*`` parameters: ``~/force_directions`` answers for every model of
the set they describe, equal to the core's robust answer, over real DDS; bad values are
refused with a message naming the parameter; the nominal answers when none is set."""

from __future__ import annotations

import math
import os

import pytest

from test_node_directions import PAWL, S, call
from wrenchcone_ros.core import Uncertainty, force_directions, load_scene


@pytest.fixture
def pawl(harness_factory):
    return harness_factory(scene_file=os.path.abspath(PAWL))


def test_force_directions_for_every_model_equals_the_core(pawl):
    scene = load_scene(PAWL)
    r = call(pawl, "arr")
    assert r.status == S.OK and r.message == ""
    assert r.lo[0] == pytest.approx(math.atan2(-10, 3), abs=1e-12)
    results = pawl.set_parameters(uncertainty__friction=[0.2, 0.4])
    assert all(x.successful for x in results), [x.reason for x in results]
    for mode, point, exclusive in [("arr", None, False), ("arr", None, True),
                                   ("arr", (0.0075, 0.035), False)]:
        r = call(pawl, mode, point, exclusive)
        assert r.status == S.OK, r.message
        core = force_directions(scene, mode, point=point, exclusive=exclusive,
                                uncertainty=Uncertainty(friction=(0.2, 0.4)))
        assert list(r.lo) == [iv.lo for iv in core] and list(r.hi) == [iv.hi for iv in core]
        assert list(r.margin) == [iv.margin for iv in core]
        assert "for every model of friction [0.2, 0.4]" in r.message and "exact" in r.message
    assert r.lo[0] != pytest.approx(math.atan2(-10, 3), abs=1e-6)
    results = pawl.set_parameters(uncertainty__friction=[0.2, 0.4], uncertainty__com_radius=1e-3)
    assert all(x.successful for x in results)
    r = call(pawl, "arr")
    assert r.status == S.OK and "scenario(eps=0.05, beta=0.001, N=220)" in r.message
    core = force_directions(scene, "arr", uncertainty=Uncertainty(friction=(0.2, 0.4),
                                                                   com_radius=1e-3))
    assert list(r.best) == [iv.best for iv in core]


def test_bad_uncertainty_is_refused(pawl):
    (res,) = pawl.set_parameters(uncertainty__friction=[0.4, 0.2])
    assert not res.successful and "uncertainty" in res.reason and "lo must be <= hi" in res.reason
    (res,) = pawl.set_parameters(uncertainty__normal_error=2.0)
    assert not res.successful and "[0, pi/2)" in res.reason
    r = call(pawl, "arr")
    assert r.status == S.OK and r.message == ""  # still the nominal answer
