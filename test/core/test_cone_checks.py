# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The compiled checks of many cones (``Engine.cone_checks``: kernel.cone_checks through
engines.kernel_engine.PackedCones) against each cone's own ``check_many`` and scalar
``margin``, bit for bit (float.hex, so +0.0 and -0.0 differ), on every kind of cone
(feasible, infeasible, lower-dimensional, with lines, R^3) and awkward wrenches; and the
direction searches (directions._Request) giving the same margins and members with and
without them.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers.strategies import random_scene, random_wrench

from wrenchcone_ros.core import Uncertainty, default_scene, enumerate_modes, load_scene
from wrenchcone_ros.core import engines, wrench_cones
from wrenchcone_ros.core.cones import cone_from_vrep, margins_at

pytest.importorskip("wrenchcone_ros.core.kernel", reason="numba not installed")


def _hex(a) -> list[str]:
    return [float(v).hex() for v in np.asarray(a, dtype=float).ravel()]


def _packed(cones):
    eng = engines.get_engine("kernel")
    if eng.name != "kernel":
        pytest.skip("the kernel engine is not available")
    return eng.cone_checks(cones)


def _cases(rng, n_scenes: int = 10):
    for _ in range(n_scenes):
        s = load_scene(random_scene(rng, n_fixels=int(rng.integers(1, 4))).data)
        yield s, wrench_cones(s, list(enumerate_modes(s.in_contact)))
    kw = dict(mode="x", length_scale=0.05, method="t", exact=False)
    yield None, [cone_from_vrep([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [], **kw),
                 cone_from_vrep([], [[1, 0, 0], [0, 1, 0], [0, 0, 1]], **kw),  # R^3
                 cone_from_vrep([[0, 0, 1]], [[1, 0, 0], [0, 1, 0]], **kw),  # half-space
                 cone_from_vrep([[1, 0, 0]], [], **kw),  # a ray
                 cone_from_vrep([[1, 0, 0], [0, 1, 0]], [[0, 0, 1]], **kw)]  # wedge x line


def test_packed_checks_equal_each_cones_check_many_bit_for_bit():
    rng = np.random.default_rng(20261202)
    kinds = set()
    for s, cones in _cases(rng):
        L = 0.05 if s is None else s.length_scale
        G = [random_wrench(rng, L) for _ in range(40)]
        G += [np.zeros(3), np.array([1e150, 0.0, 0.0]), np.array([0.0, 1e-300, 0.0])]
        for c in cones:
            kinds.add((c.feasible, c.E_hat.shape[0], c.L_hat.shape[0]))
            if c.feasible:
                G += list(c.G[:2]) + [-r for r in c.lineality[:1]]
        G = np.array(G)
        contains, margins = _packed(cones).check(G)
        assert contains.shape == margins.shape == (len(G), len(cones))
        for k, c in enumerate(cones):
            inside, m = c.check_many(G)
            assert contains[:, k].tolist() == inside.tolist(), (k, c.mode)
            assert _hex(margins[:, k]) == _hex(m), (k, c.mode)
        for n in range(0, len(G), 7):  # the scalar path the searches used
            assert _hex(margins[n]) == _hex(margins_at(cones, G[n])), n
    assert len(kinds) >= 5


def test_packed_checks_refuse_a_wrench_that_is_not_finite():
    cones = wrench_cones(default_scene(), ["na", "la"])
    with pytest.raises(ValueError, match="must be finite"):
        _packed(cones).check(np.array([[1.0, 0.0, 0.0], [np.nan, 0.0, 0.0]]))
    c, m = _packed([]).check(np.zeros((2, 3)))
    assert c.shape == m.shape == (2, 0)


def test_direction_requests_give_the_same_margins_and_members_without_them():
    """A robust request of the pawl (mu in [0.2, 0.4], exclusive, so pieces and others):
    margin, margins and members with the compiled checks == without them (each cone's
    own methods), bit for bit."""
    from wrenchcone_ros.core.directions import _request

    scene = load_scene("examples/pawl_seating.yaml")
    unc = Uncertainty(friction=(0.2, 0.4))
    for mode, exclusive in (("arr", True), ("ann", False), ("srr", True)):
        fast = _request(scene, mode, None, exclusive, False, None, unc)
        if fast._checks is None:
            pytest.skip("the default engine has no compiled checks")
        slow = _request(scene, mode, None, exclusive, False, None, unc)
        slow.__dict__["_checks"] = None  # each cone's own methods
        phis = np.linspace(-np.pi, np.pi, 181)
        assert _hex(fast.margins(phis)) == _hex(slow.margins(phis)), mode
        assert _hex([fast.margin(float(p)) for p in phis[::5]]) == \
            _hex([slow.margin(float(p)) for p in phis[::5]]), mode
        dirs = [(np.cos(p), np.sin(p)) for p in phis]
        assert fast.members(dirs) == slow.members(dirs), mode
