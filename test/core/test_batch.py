# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrench_cones: one pass over many modes of a pose (batch.py).

Independent references: the per-mode numpy reference engine (planar.planar_cone, itself
cross-checked against the paper method and the LP in test_crosscheck.py) and exact
rational arithmetic (cddlib GMP) on sampled wrenches outside the documented band.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from helpers.strategies import random_scene, shared_edge_scene

from wrenchcone_ros.core import (
    ModeError,
    ModeSyntaxError,
    default_scene,
    enumerate_modes,
    load_scene,
    wrench_cone,
    wrench_cones,
)
from wrenchcone_ros.core import WrenchSet, engines, planar

from helpers.cones import assert_same_cone
from helpers.families import band_for, exact_contains, sample_directions, si_wrench

SEED = 20261123


def _scenes(kind: str, count: int):
    rng = np.random.default_rng(SEED + {"random": 1, "extreme": 2, "shared_edge": 3}[kind])
    for _ in range(count):
        if kind == "shared_edge":
            yield load_scene(shared_edge_scene(rng).data)
        else:
            yield load_scene(random_scene(rng, extreme=(kind == "extreme"),
                                          n_fixels=int(rng.integers(1, 5))).data)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["random", "extreme", "shared_edge"])
def test_batched_equals_per_mode_equals_exact(kind):
    """wrench_cones (kernel engine) == wrench_cone per mode (numpy reference), and both
    classify sampled wrenches like exact arithmetic outside the band."""
    rng = np.random.default_rng(SEED)
    checked = 0
    for scene in _scenes(kind, 6):
        modes = list(enumerate_modes(scene.in_contact))
        modes = [modes[k] for k in rng.permutation(len(modes))[:12]]
        got = wrench_cones(scene, modes, engine="kernel")
        assert [c.mode for c in got] == modes
        for mode, cone in zip(modes, got):
            assert_same_cone(cone, wrench_cone(scene, mode, engine="numpy"))
        for mode, cone in list(zip(modes, got))[:3]:  # exact is slow: a few per scene
            exact = wrench_cone(scene, mode, exact=True)
            assert cone.feasible == exact.feasible
            target = exact if exact.feasible else exact.closure
            band = band_for(scene)
            for u in sample_directions(rng, target, 15, 15):
                g = si_wrench(u, scene.length_scale)
                if exact.feasible and abs(exact.margin(g)) < band:
                    continue
                assert cone.contains(g) == exact_contains(exact, u), (mode, g)
                checked += 1
    assert checked > 100


def test_shared_edge_needs_no_exact_fallback():
    """Fixels on one edge: parallel rows by construction, so the float path is taken."""
    before = dict(planar.PLANAR_FALLBACKS)
    declined = engines.KERNEL_STATS["declined"]
    for scene in _scenes("shared_edge", 10):
        wrench_cones(scene, list(enumerate_modes(scene.in_contact)))
    assert planar.PLANAR_FALLBACKS["exact_ill_conditioned"] == before["exact_ill_conditioned"]
    assert planar.PLANAR_FALLBACKS["exact_fallbacks"] == before["exact_fallbacks"]
    assert engines.KERNEL_STATS["declined"] == declined


def test_order_duplicates_and_wildcards():
    s = default_scene()  # fixel 1 in contact, fixel 2 free
    modes = ["na", "*a", "na", "sa", "cs"]
    got = wrench_cones(s, modes)
    assert [c.mode for c in got] == modes
    assert isinstance(got[1], WrenchSet) and isinstance(got[4], WrenchSet)
    ref = wrench_cone(s, "*a", engine="numpy")
    assert got[1].modes == ref.modes and got[1].impossible == ref.impossible
    for a, b in zip(got[1].pieces, ref.pieces):
        assert_same_cone(a, b)
    assert_same_cone(got[0], got[2])
    assert wrench_cones(s, []) == []


def test_per_mode_errors():
    """errors="raise": the first bad mode's exception, worded as wrench_cone words it;
    errors="return": the exception object in its place, the other modes computed."""
    s = default_scene()
    bad = ["xa", "aa", "n", 7, "cc"]
    for mode in bad:
        with pytest.raises(ModeError) as per_mode:
            wrench_cone(s, mode)
        with pytest.raises(ModeError) as batched:
            wrench_cones(s, ["na", mode, "sa"])
        assert type(batched.value) is type(per_mode.value)
        assert str(batched.value) == str(per_mode.value)
    got = wrench_cones(s, ["na", "xa", "aa", "sa", 7], errors="return")
    assert isinstance(got[1], ModeSyntaxError) and isinstance(got[4], ModeSyntaxError)
    assert isinstance(got[2], ModeError) and not isinstance(got[2], ModeSyntaxError)
    assert "fixel 1 is in contact" in str(got[2])
    assert_same_cone(got[0], wrench_cone(s, "na"))
    assert_same_cone(got[3], wrench_cone(s, "sa"))
    with pytest.raises(ValueError, match="errors must be"):
        wrench_cones(s, ["na"], errors="ignore")
    with pytest.raises(ValueError, match="unknown method"):
        wrench_cones(s, ["na"], method="nope")
    with pytest.raises(ValueError, match="unknown engine"):
        wrench_cones(s, ["na"], engine="gpu")


def test_engine_selection_and_other_methods():
    s = default_scene()
    for name in ("kernel", "numpy"):
        assert_same_cone(wrench_cones(s, ["na"], engine=name)[0], wrench_cone(s, "na"))
    paper = wrench_cones(s, ["na", "sa"], method="paper")
    assert [c.method for c in paper] == ["paper", "paper"]
    exact = wrench_cones(s, ["na"], exact=True)[0]
    assert exact.exact and exact.exact_rep is not None


def test_plans_are_shared_across_poses():
    s = default_scene()
    wrench_cones(s, ["na", "sa"])
    plan = engines.batch_plan(("na", "sa"), s.in_contact)
    moved = s.with_pose(0.0, 0.0, 0.3)
    assert moved.in_contact == s.in_contact
    assert engines.batch_plan(("na", "sa"), moved.in_contact) is plan
    assert_same_cone(wrench_cones(moved, ["na"])[0], wrench_cone(moved, "na", engine="numpy"))


def _run_python(code: str, env: dict) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**os.environ, **env}, timeout=300)


@pytest.mark.slow
def test_core_works_without_numba():
    """numba made unimportable: the core imports, warns once and uses the reference."""
    code = (
        "import sys, warnings; sys.modules['numba'] = None\n"
        "from wrenchcone_ros.core import default_scene, wrench_cone, wrench_cones, engines\n"
        "with warnings.catch_warnings(record=True) as w:\n"
        "    warnings.simplefilter('always')\n"
        "    c = wrench_cones(default_scene(), ['na', 'sa'])\n"
        "assert engines.resolve_engine() == 'numpy', engines.resolve_engine()\n"
        "assert any('kernel unavailable' in str(x.message) for x in w), [str(x.message) for x in w]\n"
        "assert c[0].feasible and engines.KERNEL_STATS['kernel_cones'] == 0\n"
        "print('ok', engines.kernel_unavailable())\n")
    out = _run_python(code, {})
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("ok")


@pytest.mark.slow
def test_engine_environment_variable():
    code = ("from wrenchcone_ros.core import default_scene, wrench_cone, engines\n"
            "wrench_cone(default_scene(), 'na')\n"
            "print(engines.resolve_engine(), engines.KERNEL_STATS['kernel_cones'])\n")
    out = _run_python(code, {"WRENCHCONE_ENGINE": "numpy"})
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["numpy", "0"]
    bad = _run_python(code, {"WRENCHCONE_ENGINE": "fast"})
    assert bad.returncode != 0 and "unknown engine 'fast'" in bad.stderr
