# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Randomized cross-check: every cone method against the independent LP oracle.

A seeded sample of random (scene, mode, wrench) triples (test/helpers/strategies.py: discs,
convex and non-convex polygons, point fixels and pins, rotated and translated poses, com
offsets, mu = 0 and per-fixel friction, free and touching fixels, some extreme mass /
size / position ranges) is decided once by :mod:`wrenchcone_ros.core.lp_check`, which
writes Newton-Euler and Table 2 as an LP and never touches the paper's matrices. Then
for each method ("paper", "planar", and exact arithmetic on a subset):

* ``cone.feasible`` must equal the LP's verdict on whether any wrench realises the open
  mode (``lp_mode_feasible``);
* ``cone.contains(g)`` must equal the LP's verdict on the open mode;
* the closure: for a feasible mode ``contains(g)`` must equal the LP with non-strict
  inequalities (checked on one wrench per pair, to save time); for an infeasible one,
  ``cone.closure`` must (every wrench), while ``contains`` is False and the open-mode LP
  says "inconsistent" for every wrench.

Boundary band: a wrench is skipped for a method when the unit nondimensional direction of
g is within ``BAND`` (1e-6, dimensionless) of the cone's boundary, i.e. ``|cone.margin(g)|
< BAND``. Cones with an empty interior give margin 0 to all their members; for them the
band is applied to the *relative* margin (distance to the relative boundary within the
cone's linear span), so their relative interiors are checked too. Two more skips belong
to the LP, not the cone (``LPResult.decided``): a wrench whose LP slack is within the LP's
round-off (``LP_NOISE``, 1e-9), and a (scene, mode) whose possibility the float data do
not determine (feasibility slack within 100x of ``LP_FEASIBILITY_TOLERANCE``, or an
acceleration row within rounding of the span of the equalities). Every kind of skip is
counted and reported; together they must stay a small fraction
(``MAX_SKIP_FRACTION``). Disagreements outside the bands: none allowed.

Wrenches: two uniformly random nondimensional directions per (scene, mode) and one built
from Newton-Euler without any cone, ``g = lam M xdd - J c`` with ``c`` drawn from the
mode's force rules and ``xdd`` the LP's strict witness (consistent by construction, in the
relative interior even of cones with an empty interior); for an impossible mode
``xdd = 0``, a static equilibrium in the mode's closure, which is where a wrong
"consistent" would hide.

Also here: the same comparison on degenerate scenes (gaps at the contact tolerance,
nearly coincident fixels) and on regression cases found by long stress runs, both with
the cones computed in child processes so that a crash in native code fails the test
instead of killing the run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from helpers.strategies import (
    random_mode,
    random_scene,
    random_wrench,
    scenes_and_modes,
    wrench_from_witness,
)

from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_ros.core.batch import METHODS
from wrenchcone_ros.core.lp_check import lp_consistent, lp_mode_feasible

pytestmark = pytest.mark.slow  # the randomized cross-check against the LP: thousands of seeded triples

#: Seed and size; override for a longer stress run, e.g.
#: WRENCHCONE_XC_SEED=7 WRENCHCONE_XC_SCENES=3000 pytest test/core/test_crosscheck.py -s
SEED = int(os.environ.get("WRENCHCONE_XC_SEED", "20261121"))
N_SCENES = int(os.environ.get("WRENCHCONE_XC_SCENES", "380"))  # x 2 modes x 3 wrenches
MODES_PER_SCENE = 2
RANDOM_WRENCHES = 2  # plus one built from Newton-Euler (wrench_from_witness)
EXTREME_EVERY = 7  # every 7th scene uses the extreme ranges
EXACT_PAIRS = {"paper": 40, "planar": 100}  # (scene, mode) pairs also run with exact=True

#: Dimensionless boundary band: skip wrenches with |margin| < BAND.
BAND = 1e-6
#: Skips must stay below this fraction of the checked triples.
MAX_SKIP_FRACTION = 0.03


def _methods() -> list[str]:
    return [m for m in ("paper", "planar") if m in METHODS]


@dataclass
class Case:
    """One (scene, mode) with its wrenches and the LP verdicts."""

    gen: object  # strategies.GeneratedScene
    scene: object
    mode: str
    feas: object  # LPResult of lp_mode_feasible
    wrenches: list = field(default_factory=list)
    lp_open: list = field(default_factory=list)
    lp_closure: list = field(default_factory=list)  # bool, or None when not computed
    constructed: int | None = None  # index of the wrench built from Newton-Euler

    @property
    def feasible_lp(self) -> bool:
        return self.feas.consistent


def _relative_margin(cone, g) -> float:
    """cone.margin, except for members of a cone with an empty interior, where it is the
    distance of the unit direction to the relative boundary (within the cone's span)."""
    m = cone.margin(g)
    if not cone.feasible or cone.E_hat.shape[0] == 0:
        return m
    u = cone.nondimensional(g)
    u = u / np.linalg.norm(u)
    if np.max(np.abs(cone.E_hat @ u)) > 1e-12:
        return m
    if cone.F_hat.shape[0] == 0:
        return 1.0
    return float(np.min(-(cone.F_hat @ u)))


def _build_sample(seed: int, n_scenes: int, extreme_every: int, degenerate: bool):
    """Random (scene, mode) pairs with wrenches and LP verdicts; no cone is computed."""
    rng = np.random.default_rng(seed)
    cases = []
    for k in range(n_scenes):
        gen = random_scene(rng, extreme=(k % extreme_every == extreme_every - 1),
                           degenerate=degenerate)
        scene = load_scene(gen.data)
        assert scene.in_contact == gen.in_contact, gen.data  # geometry as built
        for _ in range(MODES_PER_SCENE):
            mode = random_mode(rng, scene.in_contact)
            case = Case(gen, scene, mode, lp_mode_feasible(scene, mode, witness=True))
            ws = [random_wrench(rng, scene.length_scale) for _ in range(RANDOM_WRENCHES)]
            # built from Newton-Euler: consistent by construction when the mode is
            # possible, a static-equilibrium member of the closure when it is not
            g = wrench_from_witness(rng, scene, mode,
                                    case.feas.witness if case.feas.consistent else None)
            if g is not None:
                ws.append(g)
                case.constructed = len(ws) - 1
            for j, g in enumerate(ws):
                case.wrenches.append(g)
                case.lp_open.append(lp_consistent(scene, mode, g, feasibility=case.feas))
                # the closure LP (to save time, not for every wrench): for an impossible
                # mode the static equilibrium and one random wrench (its closure cone is
                # compared), for a possible one a random wrench
                need = j == 0 or (not case.feas.consistent and j == case.constructed)
                case.lp_closure.append(
                    lp_consistent(scene, mode, g, closure=True).consistent if need else None)
            cases.append(case)
    return cases


@pytest.fixture(scope="module")
def sample():
    """The seeded sample with LP verdicts (computed once per module)."""
    t0 = time.perf_counter()
    cases = _build_sample(SEED, N_SCENES, EXTREME_EVERY, degenerate=False)
    n = sum(len(c.wrenches) for c in cases)
    print(f"\ncross-check sample: {len(cases)} (scene, mode) pairs, {n} triples, "
          f"LP verdicts in {time.perf_counter() - t0:.1f} s")
    return cases


def test_sample_is_large_and_covers_everything(sample):
    triples = sum(len(c.wrenches) for c in sample)
    assert triples >= 2000
    cov = Counter()
    for c in sample:
        k = len(c.wrenches)
        cov[c.gen.shape] += k
        cov["pins"] += k * c.gen.has_pins
        cov["extreme"] += k * bool(c.gen.notes["extreme"])
        cov["mu=0"] += k * any(c.scene.mu(i) == 0 for i in range(c.scene.n_fixels))
        cov["feasible" if c.feasible_lp else "infeasible"] += k
        cov["consistent"] += sum(r.consistent for r in c.lp_open)
        for letter in set(c.mode):
            cov[f"letter {letter}"] += k
            if c.feasible_lp:
                cov[f"letter {letter} consistent"] += sum(r.consistent for r in c.lp_open)
                cov[f"letter {letter} inconsistent"] += sum(not r.consistent
                                                            for r in c.lp_open)
    print("coverage:", dict(sorted(cov.items())))
    for key in ("disc", "convex", "nonconvex", "pins", "feasible", "infeasible"):
        assert cov[key] >= 200, (key, cov[key])
    assert cov["extreme"] >= 100 and cov["mu=0"] >= 100
    for letter in "aslrn":
        assert cov[f"letter {letter} consistent"] >= 30, letter
        assert cov[f"letter {letter} inconsistent"] >= 30, letter


def test_lp_oracle_is_self_consistent(sample):
    """An impossible mode is inconsistent with every wrench; open implies closure; a
    wrench built from Newton-Euler with a strict witness is consistent, and a static
    equilibrium is in the closure."""
    built = 0
    for c in sample:
        for k, (g, r, rc) in enumerate(zip(c.wrenches, c.lp_open, c.lp_closure,
                                           strict=True)):
            if not c.feasible_lp:
                assert not r.consistent, (c.gen.data, c.mode, g.tolist(), r.slack)
            if r.consistent and rc is not None:
                assert rc, (c.gen.data, c.mode, g.tolist())
            if k == c.constructed:
                assert rc in (True, None), (c.gen.data, c.mode, g.tolist())
                if c.feasible_lp and r.decided:
                    assert r.consistent, (c.gen.data, c.mode, g.tolist(), r.slack)
                    built += 1
    assert built >= 300


def _compare(sample, method: str, exact: bool = False, limit: int | None = None):
    """Compare one method with the LP verdicts; returns (stats, disagreements)."""
    stats = Counter()
    bad = []
    t_cone = 0.0
    for c in sample[:limit]:
        stats["pairs"] += 1
        if not c.feas.decided:  # s_f within round-off of the feasibility tolerance
            stats["triples"] += len(c.wrenches)
            stats["skipped (marginal mode)"] += len(c.wrenches)
            continue
        t = time.perf_counter()
        cone = wrench_cone(c.scene, c.mode, exact=exact, method=method)
        t_cone += time.perf_counter() - t
        if cone.feasible != c.feasible_lp:
            bad.append(("feasible", c.gen.data, c.mode, None, cone.feasible, c.feasible_lp))
            continue
        lowdim = bool(cone.feasible and cone.E_hat.shape[0])
        stats["empty-interior cones"] += lowdim
        for g, r, rc in zip(c.wrenches, c.lp_open, c.lp_closure, strict=True):
            stats["triples"] += 1
            got = cone.contains(g)
            if not cone.feasible:
                # the open mode: nothing; the closure cone: compared with the closure LP
                if got or r.consistent:
                    bad.append(("open", c.gen.data, c.mode, g.tolist(), got, r.consistent))
                cl = cone.closure
                if cl is not None:
                    if abs(_relative_margin(cl, g)) < BAND:
                        stats["skipped (closure)"] += 1
                    elif rc is not None and cl.contains(g) != rc:
                        bad.append(("closure", c.gen.data, c.mode, g.tolist(),
                                    cl.contains(g), rc))
                stats["checked"] += 1
                continue
            if abs(_relative_margin(cone, g)) < BAND:
                stats["skipped"] += 1
                continue
            if not r.decided:  # the LP's slack is within its round-off
                stats["skipped (LP noise)"] += 1
                continue
            stats["checked"] += 1
            stats["inside" if got else "outside"] += 1
            stats["inside, empty-interior cone"] += got and lowdim
            if got != r.consistent:
                bad.append(("open", c.gen.data, c.mode, g.tolist(), got,
                            (r.consistent, r.slack, cone.margin(g))))
            if rc is not None and got != rc:
                bad.append(("closure", c.gen.data, c.mode, g.tolist(), got, rc))
    for key in ("skipped", "skipped (LP noise)", "skipped (marginal mode)"):
        stats[key] += 0
    stats["cone seconds"] = round(t_cone, 3)
    return stats, bad


def _report(method, exact, stats, bad):
    print(f"\n{method}{' exact' if exact else ''}: {dict(stats)}; disagreements: {len(bad)}")
    for b in bad[:5]:
        print("  DISAGREEMENT", b)


@pytest.mark.parametrize("method", _methods())
def test_cone_agrees_with_lp(sample, method):
    stats, bad = _compare(sample, method)
    _report(method, False, stats, bad)
    assert not bad, bad[:3]
    assert stats["triples"] >= 2000
    skipped = (stats["skipped"] + stats["skipped (LP noise)"]
               + stats["skipped (marginal mode)"])
    assert skipped <= MAX_SKIP_FRACTION * stats["triples"], stats
    assert stats["inside"] >= 300 and stats["outside"] >= 300


@pytest.mark.parametrize("method", _methods())
def test_exact_cone_agrees_with_lp(sample, method):
    n = EXACT_PAIRS[method]
    stats, bad = _compare(sample, method, exact=True, limit=n)
    _report(method, True, stats, bad)
    assert not bad, bad[:3]
    assert stats["pairs"] == n and stats["checked"] >= 2 * n


def test_methods_agree_on_feasibility_and_membership(sample):
    """paper and planar give the same verdict on every sampled wrench (outside the band)."""
    methods = _methods()
    assert len(methods) >= 2, methods  # paper and planar
    diffs = []
    for c in sample:
        cones = [wrench_cone(c.scene, c.mode, method=m) for m in methods]
        if len({k.feasible for k in cones}) > 1:
            diffs.append((c.gen.data, c.mode, "feasible"))
            continue
        for g in c.wrenches:
            if min(abs(_relative_margin(k, g)) for k in cones) < BAND:
                continue
            if len({k.contains(g) for k in cones}) > 1:
                diffs.append((c.gen.data, c.mode, g.tolist()))
    assert not diffs, diffs[:3]


# --------------------------------------------------------------------------- hypothesis

try:
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st
except ImportError:  # pragma: no cover
    given = None

if given is not None:

    @settings(max_examples=30, deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow])
    @given(scenes_and_modes(), st.integers(0, 2**32 - 1))
    def test_hypothesis_cross_check(scene_and_mode, wrench_seed):
        gen, mode = scene_and_mode
        scene = load_scene(gen.data)
        assert scene.in_contact == gen.in_contact
        rng = np.random.default_rng(wrench_seed)
        g = random_wrench(rng, scene.length_scale)
        feas = lp_mode_feasible(scene, mode)
        r = lp_consistent(scene, mode, g, feasibility=feas)
        for method in _methods():
            cone = wrench_cone(scene, mode, method=method)
            if not feas.decided:
                continue
            assert cone.feasible == feas.consistent, (gen.data, mode)
            if abs(_relative_margin(cone, g)) >= BAND and r.decided:
                assert cone.contains(g) == r.consistent, (gen.data, mode, g.tolist())


# --------------------------------------------------------------------------- regressions

#: (scene, mode) pairs on which a long stress run (a different WRENCHCONE_XC_SEED, more
#: scenes) once broke a method. Each is rerun here in a child process, so that a crash in
#: native code (cddlib) fails this test with a message instead of killing the test run.
REGRESSION_CASES = [
    {
        "found": "seed 7 stress run, paper method: cddlib float matrix_canonicalize aborted "
                 "the process (free(): invalid pointer / SIGSEGV) on a nearly flat closure "
                 "(two sliding fixels on one edge of a polygon)",
        "mode": "ssll",
        "scene": {
            "workpiece": {
                "mass": 103.38094552274407, "inertia": 3.787225356945383,
                "com": [0.17372046433953436, 0.3781792157353674],
                "shape": {"type": "polygon", "vertices": [
                    [0.15330252148671525, 0.6452459104127706],
                    [-1.2212836912395217, 0.19755164859867555],
                    [-0.5156770840907936, -0.8140045783654716],
                    [0.04469028235147656, -0.46571445141370393],
                    [0.7071372628570614, -0.7353764657104742]]},
                "pose": [-6.258242480220042, -2.310525996007363, 2.2629354966876267]},
            "friction": 0.15857183462738839,
            "contact_tolerance": 1e-09,
            "fixels": [
                {"position": [-6.32503988864871, -1.6315999735735889], "radius": 0.0},
                [-5.801041654146939, -2.021412594839351],
                {"position": [-5.469570030600555, -2.098167252598805],
                 "radius": 0.0322756548941496},
                [-5.4794310110285736, -2.128902104676802]]},
    },
    {'found': 'seed 202 degenerate stress: twin fixels on one polygon edge 1e-8 m apart, both '
              'sliding left; paper float accepts wrenches that exact arithmetic, planar and '
              'the LP reject (margin 0.36 vs exact -0.11)',
     'mode': 'll',
     'wrenches': [[-158.71414638025195, 101.1226033560103, -2.161797708955252],
                  [-4.284669181871082, 2.705272568118896, 0.33486477094861206]],
     'scene': {'workpiece': {'mass': 0.10311236844325677,
                             'inertia': 0.0014056534603733729,
                             'com': [0.0032049490778594705, 0.0009535930521519648],
                             'shape': {'type': 'polygon',
                                       'vertices': [[-0.008923100861948025,
                                                     0.014825991545088832],
                                                    [-0.016626699687652475,
                                                     0.004794226922472511],
                                                    [-0.014760227453543006,
                                                     -0.009031469415727347],
                                                    [-0.00553555149998694,
                                                     -0.01639479868368427],
                                                    [0.01519821432367504,
                                                     -0.008273211931238193],
                                                    [0.01682214430629723,
                                                     -0.0040555166410279776]]},
                             'pose': [12.347816234037367,
                                      -121.47803845651082,
                                      2.4972842965360993]},
               'friction': 0.45876977516922685,
               'contact_tolerance': 1e-09,
               'fixels': [[12.34407514553211, -121.48873781721502],
                          [12.344075142413145, -121.48873780678989]]}},
    {'found': 'seed 202 degenerate stress: twin fixels 7e-8 m apart on one edge, both '
              'separating; planar float returns a plane (one equality) instead of the exact '
              'two-face cone, rejecting wrenches with exact margin 0.83',
     'mode': 'ss',
     'wrenches': [[-0.007167000046301338, 0.007533746534261263, 0.00013939241062963604],
                  [0.05785369449047183, -0.4006256984803786, 0.001184297416887079]],
     'scene': {'workpiece': {'mass': 1.5676445815578217,
                             'inertia': 3.3235308242723675e-08,
                             'com': [0.0017606118352208732, -0.0018789977060788444],
                             'shape': {'type': 'polygon',
                                       'vertices': [[0.003213350697946675,
                                                     0.005614703426155974],
                                                    [0.0009441296832710783,
                                                     0.006399932531898166],
                                                    [-0.003182027337842954,
                                                     0.005632514473385941],
                                                    [-0.006410908401209864,
                                                     0.0008664702781854688],
                                                    [-0.006054301450290222,
                                                     -0.0022794629237378986],
                                                    [0.005769453316374234,
                                                     -0.0029264185794004895],
                                                    [0.006369300879292592,
                                                     -0.0011324855763870144]]},
                             'pose': [0.0017883403571995462,
                                      -0.0005194166934703582,
                                      0.31474236112558485]},
               'friction': 0.05899280732339969,
               'contact_tolerance': 1e-09,
               'fixels': [{'position': [0.008190206824904097, -0.00027071474777754184],
                           'radius': 0.0},
                          [0.008190206735660337, -0.00027077577985056456]]}},
    {'found': 'seed 202 degenerate stress: nearly coincident fixels, roll + separate (barely '
              'possible mode, s_f 1.8e-7); paper float accepts a wrench with exact margin '
              '-0.87',
     'mode': 'ns',
     'wrenches': [[-213.0433827610827, -193.61325271302323, -18710.806477279617]],
     'scene': {'workpiece': {'mass': 0.2387478741982162,
                             'inertia': 16471.862380833598,
                             'com': [7.079837595445068, 0.52492760730447],
                             'shape': {'type': 'polygon',
                                       'vertices': [[26.406910860951903, 7.282317607871236],
                                                    [23.577656857733125, 13.944575578308621],
                                                    [7.593225821619164, 26.31919475557843],
                                                    [-27.38165493766592, 0.7759277252208995],
                                                    [-15.6096991242991, -22.509873038491953],
                                                    [-4.45606738716586, -27.027773759620082],
                                                    [25.134835586528023, -10.890230989211176]]},
                             'pose': [16.319613012085835,
                                      -6.202049541497571,
                                      -3.0289795088393117]},
               'friction': 0.16689876812535276,
               'contact_tolerance': 1e-09,
               'fixels': [{'position': [-9.263449207222756, -12.621938154955682],
                           'radius': 0.0,
                           'friction': 1.0506027805304885},
                          {'position': [-9.263448949283834, -12.621944195530432],
                           'radius': 0.0}]}},
    {'found': 'seed 202 degenerate stress: nearly coincident rolling fixels; paper float '
              'accepts a wrench with exact margin -0.37',
     'mode': 'nnn',
     'wrenches': [[0.09247365203138483, 0.03235440516671344, -5.48943521158932e-05]],
     'scene': {'workpiece': {'mass': 0.03854718291483429,
                             'inertia': 9.859715515607807e-09,
                             'com': [0.00021046693160083123, 0.00019593332956275135],
                             'shape': {'type': 'disc', 'radius': 0.0012660688737794136},
                             'pose': [0.1779831827531415,
                                      0.29296685564934677,
                                      2.1790433674771013]},
               'friction': 0.04821953542325988,
               'contact_tolerance': 1e-09,
               'fixels': [[0.17865544477405787, 0.2940396998699814],
                          {'position': [0.17802975993315914, 0.29170164394710557],
                           'radius': 0.0,
                           'friction': 0.0},
                          {'position': [0.1786554452983932, 0.29403969928352874],
                           'radius': 0.0}]}},
    {'found': 'seed 202 degenerate stress: nearly coincident rolling fixels; paper float '
              'accepts wrenches with exact margins -0.13 and -0.89',
     'mode': 'nn',
     'wrenches': [[0.025365949996611372, -0.009800956487800695, 0.00021370866771476464],
                  [-1.347212125722408, 1.9734903587145582, 0.02748989555550579]],
     'scene': {'workpiece': {'mass': 0.0269854860664669,
                             'inertia': 7.882496096864725e-10,
                             'com': [0.0013317056961984859, 0.0016676555900812721],
                             'shape': {'type': 'disc', 'radius': 0.005721155584514197},
                             'pose': [0.29651404140324866,
                                      -0.3403075890046565,
                                      0.582004840114339]},
               'friction': 5.146646209887367,
               'contact_tolerance': 1e-09,
               'fixels': [[0.2991618799498091, -0.34537913410222854],
                          [0.2991618815321643, -0.3453791335301361]]}},
    {'found': 'seed 606 degenerate stress: disc, twin fixels 1.2e-5 L apart; paper float '
              'flattens the thin exact three-face cone into a plane (one equality) and rejects '
              'wrenches with exact margin 7e-6',
     'mode': 'ssrsr',
     'wrenches': [[16.63061349661245, 89.41047268192192, 2.2164398574711406]],
     'scene': {'workpiece': {'mass': 304.55498526504743,
                             'inertia': 0.0008323975473354724,
                             'com': [-0.0015615678988544644, -0.0009489463879276416],
                             'shape': {'type': 'disc', 'radius': 0.005810061471613159},
                             'pose': [-0.0015343765675364688,
                                      -0.0033947764139734284,
                                      0.8212867389685217]},
               'friction': 0.020855955868274493,
               'contact_tolerance': 1e-09,
               'fixels': [{'position': [-0.004702667768224786, 0.0017542471033558022],
                           'radius': 0.0},
                          [-0.005772603213986774, -0.007786978085162995],
                          {'position': [-0.0069626410869927415, -0.0013233605840565345],
                           'radius': 0.0},
                          {'position': [0.0021468933087159317, 0.0011002349979066556],
                           'radius': 0.0},
                          [-0.006962607469308936, -0.0013232736790087544]]}},
    {'found': 'seed 606 stress: disc, three well separated contacts all sliding right, I/(m '
              'L^2) = 8e-5; paper float returns wrong faces: 41% of random wrenches '
              'misclassified vs exact arithmetic',
     'mode': 'rrr',
     'wrenches': [[0.00034084799651587695, 0.0003214597544230315, 0.002196226805094961]],
     'scene': {'workpiece': {'mass': 0.0001633048466451746,
                             'inertia': 4.095760533323402e-06,
                             'com': [-3.614210218739037, 2.1042969158002474],
                             'shape': {'type': 'disc', 'radius': 13.169183983847063},
                             'pose': [0.07193452459176547,
                                      -0.2080377612085238,
                                      1.4080097052657683]},
               'friction': 0.03708479302863758,
               'contact_tolerance': 1e-09,
               'fixels': [{'position': [4.253849265493019, 13.449028103377945],
                           'radius': 1.1138079621641128},
                          {'position': [5.776692512917199, 12.328953188966178],
                           'radius': 0.6047190864567645,
                           'friction': 0.0},
                          [-8.32361009247238, -10.354083167340868]]}},
    {'found': 'seed 606 degenerate stress: disc, twin fixels 5e-6 L apart, far from the '
              'origin; paper float flattens the thin exact cone into a plane (one equality)',
     'mode': 'lsl',
     'wrenches': [[-4.040698139795904, 14.24075749344399, -0.9784237122711729]],
     'scene': {'workpiece': {'mass': 5.67652631830441,
                             'inertia': 0.006670347865159729,
                             'com': [-0.0005742857946545609, 0.01193438398388063],
                             'shape': {'type': 'disc', 'radius': 0.05288730305633659},
                             'pose': [-0.34190926927197,
                                      0.2489471960824674,
                                      1.3875287117826325]},
               'friction': 0.9362753031847022,
               'contact_tolerance': 1e-09,
               'fixels': [{'position': [-0.39400418964926637, 0.25806783611206824],
                           'radius': 0.0},
                          {'position': [-0.36184610124854344, 0.19996158272729805],
                           'radius': 0.0,
                           'friction': 0.1600740586457718},
                          {'position': [-0.39400424772160997, 0.2580675055566211],
                           'radius': 0.0}]}},
]

_CHILD = r"""
import json, sys
import numpy as np
from wrenchcone_ros.core import load_scene, wrench_cone

def rel_margin(cone, g):
    m = cone.margin(g)
    if not cone.feasible or cone.E_hat.shape[0] == 0:
        return m
    u = cone.nondimensional(g)
    u = u / np.linalg.norm(u)
    if np.max(np.abs(cone.E_hat @ u)) > 1e-12:
        return m
    return 1.0 if cone.F_hat.shape[0] == 0 else float(np.min(-(cone.F_hat @ u)))

job = json.load(sys.stdin)
for k, (i, method, exact) in enumerate(job["items"]):
    if k < job["start"]:
        continue
    case = job["cases"][i]
    print(json.dumps({"start": k}), flush=True)
    cone = wrench_cone(load_scene(case["scene"]), case["mode"], method=method, exact=exact)
    out = {"item": k, "feasible": bool(cone.feasible),
           "contains": [bool(cone.contains(g)) for g in case["wrenches"]],
           "margin": [float(rel_margin(cone, g)) for g in case["wrenches"]]}
    cl = getattr(cone, "closure", None)
    if not cone.feasible and cl is not None:
        out["closure_contains"] = [bool(cl.contains(g)) for g in case["wrenches"]]
        out["closure_margin"] = [float(rel_margin(cl, g)) for g in case["wrenches"]]
    print(json.dumps(out), flush=True)
"""


def _run_children(cases: list, items: list) -> tuple[list[dict], list[tuple[int, str]]]:
    """Compute the cones of ``items`` = [(case index, method, exact)] in child processes,
    restarting past any crash; returns (results, [(item, crash message)])."""
    job = {"cases": [{"scene": c.gen.data, "mode": c.mode,
                      "wrenches": [np.asarray(g, dtype=float).tolist() for g in c.wrenches]}
                     for c in cases],
           "items": items}
    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": str(root) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    results, crashes, start = [], [], 0
    while start < len(items):
        proc = subprocess.run([sys.executable, "-c", _CHILD],
                              input=json.dumps({**job, "start": start}), text=True,
                              capture_output=True, cwd=root, timeout=600, env=env)
        lines = [json.loads(x) for x in proc.stdout.splitlines() if x.startswith("{")]
        results += [x for x in lines if "item" in x]
        if proc.returncode == 0:
            break
        started = [x["start"] for x in lines if "start" in x]
        k = started[-1] if started else start
        tail = proc.stderr.strip().splitlines()[-1:] if proc.stderr.strip() else []
        crashes.append((k, f"exit {proc.returncode} {tail}"))
        start = k + 1
    return results, crashes


def _check_child_results(cases: list, items: list, results: list, crashes: list):
    """Compare child-process cones with the LP verdicts of ``cases`` (Case objects)."""
    stats = Counter()
    bad: dict[str, list[str]] = {}
    closure_bad: dict[str, list[str]] = {}  # closure cones of impossible modes
    for k, msg in crashes:
        i, method, exact = items[k]
        bad.setdefault(f"case {i} {method}{' exact' if exact else ''}", []).append(
            f"CRASH {msg}")
    for r in results:
        i, method, exact = items[r["item"]]
        c = cases[i]
        label = f"case {i} {method}{' exact' if exact else ''}"
        stats["pairs"] += 1
        stats["triples"] += len(c.wrenches)
        if not c.feas.decided:
            stats["skipped (marginal mode)"] += len(c.wrenches)
            continue
        if r["feasible"] != c.feas.consistent:
            bad.setdefault(label, []).append(
                f"feasible={r['feasible']}, LP {c.feas.consistent} (s_f {c.feas.slack:.3g})")
            continue
        for k, (g, got, m, want, rc) in enumerate(zip(
                c.wrenches, r["contains"], r["margin"], c.lp_open, c.lp_closure,
                strict=True)):
            if not r["feasible"]:
                if got or want.consistent:
                    bad.setdefault(label, []).append(f"g={list(g)} contains={got} (impossible)")
                if ("closure_contains" in r and abs(r["closure_margin"][k]) >= BAND
                        and rc is not None and r["closure_contains"][k] != rc):
                    closure_bad.setdefault(label, []).append(
                        f"g={list(g)} closure contains={r['closure_contains'][k]} (margin "
                        f"{r['closure_margin'][k]:.3g}), LP {rc}")
                stats["checked"] += 1
                continue
            if abs(m) < BAND:
                stats["skipped"] += 1
                continue
            if not want.decided:
                stats["skipped (LP noise)"] += 1
                continue
            stats["checked"] += 1
            if got != want.consistent or (rc is not None and got != rc):
                bad.setdefault(label, []).append(
                    f"g={list(g)} contains={got} (margin {m:.3g}), LP open "
                    f"{want.consistent} (slack {want.slack:.3g}), closure {rc}")
    return stats, bad, closure_bad


def _case_from_dict(d: dict, rng) -> Case:
    scene = load_scene(d["scene"])
    case = Case(SimpleNamespace(data=d["scene"]), scene, d["mode"],
                lp_mode_feasible(scene, d["mode"]))
    ws = [np.array(g, dtype=float) for g in d.get("wrenches", [])]
    ws += [random_wrench(rng, scene.length_scale) for _ in range(30)]
    for g in ws:
        case.wrenches.append(g)
        case.lp_open.append(lp_consistent(scene, d["mode"], g, feasibility=case.feas))
        case.lp_closure.append(lp_consistent(scene, d["mode"], g, closure=True).consistent)
    return case


def test_regression_cases_in_child_process():
    """Scenes on which a method once failed, rerun in child processes (crash-safe)."""
    rng = np.random.default_rng(SEED)
    cases = [_case_from_dict(d, rng) for d in REGRESSION_CASES]
    items = [(i, m, ex) for i in range(len(cases)) for m in _methods() for ex in (False, True)]
    results, crashes = _run_children(cases, items)
    stats, bad, closure_bad = _check_child_results(cases, items, results, crashes)
    for label, v in closure_bad.items():
        bad.setdefault(label, []).extend(v)
    report = [f"{label}: {len(v)} failure(s), e.g. {v[0]} -- "
              f"{REGRESSION_CASES[int(label.split()[1])]['found']}"
              for label, v in sorted(bad.items())]
    print(f"\nregression cases: {len(cases)} x {_methods()} x float/exact: {dict(stats)}; "
          f"{sum(len(v) for v in bad.values())} failures")
    for line in report:
        print("  ", line)
    assert not bad, "\n".join(report)


#: Degenerate scenes (the numerical extremes: gaps at the contact tolerance, nearly
#: coincident fixels with nearly parallel normals, every other one with extreme mass /
#: size / position ranges), float cones in child processes.
DEGENERATE_SCENES = int(os.environ.get("WRENCHCONE_XC_DEGENERATE", "60"))


@pytest.fixture(scope="module")
def degenerate_results():
    """{method: (stats, failures, closure failures, cases)} on the degenerate sample."""
    cases = _build_sample(SEED + 1, DEGENERATE_SCENES, 2, degenerate=True)
    out = {}
    for method in _methods():
        items = [(i, method, False) for i in range(len(cases))]
        results, crashes = _run_children(cases, items)
        out[method] = (*_check_child_results(cases, items, results, crashes), cases)
    return out


def _degenerate_report(cases, bad) -> list[str]:
    report = []
    for label, v in sorted(bad.items()):
        c = cases[int(label.split()[1])]
        report.append(f"{label} mode {c.mode}: {len(v)} failure(s), e.g. {v[0]}; "
                      f"scene {json.dumps(c.gen.data)}")
    return report


@pytest.mark.parametrize("method", _methods())
def test_degenerate_scenes_agree_with_lp(degenerate_results, method):
    """Feasibility and contains() on degenerate scenes: no disagreement outside the bands."""
    stats, bad, _, cases = degenerate_results[method]
    report = _degenerate_report(cases, bad)
    print(f"\n{method} degenerate: {dict(stats)}; {sum(len(v) for v in bad.values())} "
          f"failures in {len(bad)} (scene, mode) pairs")
    for line in report[:10]:
        print("  ", line)
    assert not bad, "\n".join(report[:5])
    assert stats["triples"] >= 300


@pytest.mark.parametrize("method", _methods())
def test_degenerate_closure_of_impossible_modes(degenerate_results, method):
    """``cone.closure`` of an impossible mode (kept for diagnostics) against the closure LP:
    a static equilibrium ``g = -J c`` is in it by construction."""
    _, _, closure_bad, cases = degenerate_results[method]
    report = _degenerate_report(cases, closure_bad)
    print(f"\n{method} degenerate, closure of impossible modes: "
          f"{sum(len(v) for v in closure_bad.values())} failures")
    for line in report[:10]:
        print("  ", line)
    assert not closure_bad, "\n".join(report[:5])
