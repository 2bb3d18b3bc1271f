"""The compiled kernel (kernel.py) against the numpy reference it transcribes.

* its 3-D conversions == cone3d's on every input family of test_cone3d.py (cone3d is
  itself checked against exact cddlib there), both raising / declining together;
* its ``nearly_parallel`` == constraints.nearly_parallel;
* whole cones: the kernel engine == the numpy reference engine on every scene family of
  the error-vs-runtime study (benchmarks/_common.py FAMILIES, the new shared-edge family
  included), and it declines exactly the modes the reference does not take in float.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from test_batch import assert_same_cone
from test_cone3d import FAMILIES as CONE3_FAMILIES
from test_cone3d import span_distance

from wrenchcone_ros.core import batch, cone3d, load_scene, planar, wrench_cones
from wrenchcone_ros.core.constraints import nearly_parallel
from wrenchcone_ros.core.scene import SceneError

kernel = pytest.importorskip("wrenchcone_ros.core.kernel", reason="numba not installed")

_BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
if str(_BENCH) not in sys.path:
    sys.path.insert(0, str(_BENCH))
from _common import FAMILIES  # noqa: E402

SEED = 20261123
CASES = 150


def _same3(ref: cone3d.Cone3, got: tuple) -> None:
    F, E, R, L = got
    for a, b in ((ref.F, F), (ref.rays, R)):
        assert a.shape == b.shape
        if a.size:
            p, q = np.sort(np.round(a, 9), axis=0), np.sort(np.round(b, 9), axis=0)
            assert np.abs(p - q).max() <= 2e-9
    for a, b in ((ref.E, E), (ref.lines, L)):
        assert a.shape == b.shape and span_distance(a, b) <= 1e-9


def _both(ref_fn, kern_fn, a, b):
    try:
        ref = ref_fn(a, b)
    except cone3d.Cone3Error:
        ref = None
    try:
        got = kern_fn(np.asarray(a, dtype=float).reshape(-1, 3),
                      np.asarray(b, dtype=float).reshape(-1, 3))
    except kernel.KernelCone3Error:
        got = None
    return ref, got


@pytest.mark.parametrize("family", sorted(CONE3_FAMILIES))
def test_conversions_equal_cone3d(family):
    rng = np.random.default_rng(SEED)
    for _ in range(CASES):
        R, L = CONE3_FAMILIES[family](rng)
        for ref_fn, kern_fn in ((cone3d.from_generators, kernel.from_generators),
                                (cone3d.from_inequalities, kernel.from_inequalities)):
            ref, got = _both(ref_fn, kern_fn, R, L)
            assert (ref is None) == (got is None)
            if ref is not None:
                _same3(ref, got)


def test_nearly_parallel_equals_reference():
    rng = np.random.default_rng(SEED)
    for k in range(400):
        rows = rng.normal(size=(int(rng.integers(0, 6)), 3))
        if rows.shape[0] >= 2:
            angle = 10.0 ** -rng.uniform(3, 12)
            w = rng.normal(size=3)
            rows[1] = np.cos(angle) * rows[0] + np.sin(angle) * np.linalg.norm(rows[0]) * (
                w / np.linalg.norm(w))
            if k % 3 == 0:
                rows[1] = rows[0] * (-2.0 if k % 2 else 3.0)  # exactly parallel
        assert kernel.nearly_parallel(rows, 1e-6) == nearly_parallel(rows)


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_kernel_equals_reference_on_every_family(family):
    rng = np.random.default_rng(SEED)
    cases = [c for c in FAMILIES[family](rng, 2) if not c.rejected]
    assert cases
    for case in cases[:24]:
        try:
            scene = load_scene(case.data)
        except SceneError:
            continue
        before = dict(planar.PLANAR_FALLBACKS)
        declined = batch.KERNEL_STATS["declined"]
        got = wrench_cones(scene, case.modes, engine="kernel")
        float_path = planar.PLANAR_FALLBACKS["exact_ill_conditioned"] == before[
            "exact_ill_conditioned"] and planar.PLANAR_FALLBACKS["exact_fallbacks"] == before[
            "exact_fallbacks"]
        # the kernel declines only where the reference leaves the float path
        assert float_path == (batch.KERNEL_STATS["declined"] == declined)
        ref = wrench_cones(load_scene(case.data), case.modes, engine="numpy")
        for a, b in zip(got, ref):
            assert_same_cone(a, b)
