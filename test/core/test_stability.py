# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Numerical stability: the default method agrees with exact arithmetic on extreme scenes.

For every scene family of docs/error_vs_runtime.md (the paper example,
random scenes, mass 1e-6..1e6 kg, I/(m L^2) 1e-8..1e6, mu in {0, 1e-9, 1e-3, 1, 1e3,
1e9}, nearly parallel normals 1e-3..1e-12 rad, nearly coincident fixels, world offsets
1e3..1e7 m, body sizes 1e-6..1e3 m, gaps at the contact tolerance), built by the same
seeded generators as the benchmark (test/helpers/families.py), each (scene, mode) is solved
by the DEFAULT method, ``wrench_cone(scene, mode)``, and by exact rational arithmetic
(``wrench_cone(scene, mode, exact=True, method="paper")``, cddlib GMP). Asserted:

* the same feasibility verdict (``cone.feasible``: can any wrench realise the open mode);
* the same classification of sampled wrenches (uniform directions of the nondimensional
  wrench space plus directions pushed 1e-14..1e-2 rad off the exact cone's faces),
  exact membership decided in Fractions, skipping only samples within the documented
  band of the exact boundary: ``BAND`` (1e-8, dimensionless), widened only where the
  inputs' own rounding is larger (``band_for``: 64 eps C / L for world coordinates up to
  C; matters only for the 1e6..1e7 m offsets).

No timing here; the benchmark reports times and the in-band behaviour.

Known failures of the default path (found by benchmarks/error_vs_runtime.py, reported to
the lead; the fix belongs in the core) are marked ``xfail(strict=True)`` one by one with
the reason, so they are visible in every run and turn into failures ("XPASS(strict)")
the moment the core is fixed, at which point the mark must be removed. Nothing is skipped
silently: the only pairs left out are those whose *exact* geometry refuses the scene
(world offsets >= 1e6 m, where one ulp of a coordinate exceeds the contact tolerance),
and the test asserts that this happens nowhere else.
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import families
from helpers.families import BAND, FAMILIES, band_for, exact_contains, sample_directions, si_wrench

from wrenchcone_ros.core import load_scene, wrench_cone  # noqa: E402
from wrenchcone_ros.core.geometry import SceneError  # noqa: E402

SEED = 20261122
#: Scenes per family parameter value, and (scene, mode) pairs checked per family (spread
#: over the parameter values).
SCENES_PER_VALUE = 2
PAIRS_PER_FAMILY = 32
N_UNIFORM, N_BOUNDARY = 40, 40

_LEAD = "default path disagrees with exact arithmetic (docs/error_vs_runtime.md); core fix pending"
#: Families on which the default method currently disagrees with exact arithmetic, with
#: the failure seen. Remove an entry when the core is fixed (strict: an unexpected pass
#: fails the run).
KNOWN_FAILURES: dict[str, str] = {}  # none since the core's PARALLEL_GUARD


def _pairs(family: str) -> list[tuple]:
    rng = np.random.default_rng(SEED)
    cases = [c for c in FAMILIES[family](rng, SCENES_PER_VALUE) if not c.rejected]
    pairs = [(c, m) for c in cases for m in c.modes]
    if len(pairs) > PAIRS_PER_FAMILY:  # spread over the parameter values
        keep = np.linspace(0, len(pairs) - 1, PAIRS_PER_FAMILY).round().astype(int)
        pairs = [pairs[k] for k in sorted(set(keep))]
    return pairs


def _describe(case, mode: str) -> str:
    return f"family {case.family} ({case.param}), mode {mode!r}, scene {case.data!r}"


def _check_pair(scene, mode: str, rng, describe: str) -> tuple[int, str | None]:
    """(samples checked, first disagreement or None) for one (scene, mode)."""
    exact = wrench_cone(scene, mode, exact=True, method="paper")
    cone = wrench_cone(scene, mode)
    if cone.feasible != exact.feasible:
        return 0, f"feasible: default {cone.feasible}, exact {exact.feasible}; {describe}"
    target = exact if exact.feasible else exact.closure
    L = scene.length_scale
    band = band_for(scene)
    checked = 0
    for u in sample_directions(rng, target, N_UNIFORM, N_BOUNDARY):
        g = si_wrench(u, L)
        if exact.feasible and abs(exact.margin(g)) < band:
            continue
        checked += 1
        want = exact_contains(exact, u)
        if cone.contains(g) != want:
            return checked, (f"g = {g.tolist()}: default {not want}, exact {want} (exact "
                             f"margin {exact.margin(g):.3g}); {describe}")
    return checked, None


def _family_param(family: str):
    marks = ()
    if family in KNOWN_FAILURES:
        marks = pytest.mark.xfail(strict=True, reason=f"{_LEAD}: {KNOWN_FAILURES[family]}")
    return pytest.param(family, marks=marks, id=family)


@pytest.mark.slow
@pytest.mark.parametrize("family", [_family_param(f) for f in FAMILIES])
def test_default_method_agrees_with_exact(family: str) -> None:
    pairs = _pairs(family)
    assert pairs, f"family {family} produced no (scene, mode) pair"
    rng = np.random.default_rng(SEED + 1)
    failures, refused = [], []
    checked = 0
    for case, mode in pairs:
        scene = load_scene(case.data)
        try:
            n, bad = _check_pair(scene, mode, rng, _describe(case, mode))
        except SceneError as exc:  # the exact geometry refuses what the float one accepts
            refused.append(f"{case.param}: {exc}")
            continue
        checked += n
        if bad:
            failures.append(bad)
    assert checked > 0
    assert not failures, f"{len(failures)} disagreement(s) with exact arithmetic:\n" + \
        "\n".join(failures[:5])
    if refused:  # only one ulp of a huge coordinate may exceed the contact tolerance
        assert family == "offset" and all(r.startswith(("offset=1e+06", "offset=1e+07"))
                                          for r in refused), refused


#: Reproducers found by benchmarks/error_vs_runtime.py (full run, seed 5): scene, mode, a
#: wrench, and the exact verdict for it. The first three failed with the cddlib-based
#: planar method and pass since it uses cone3d; the last one (nearly coincident fixels)
#: passes since the core's PARALLEL_GUARD. Regression tests now; a reproducer that fails
#: again goes into KNOWN_REPRODUCERS (strict xfail) with the reason, never silently.
REPRODUCERS = {
    "kappa-1e-8": (
        {"workpiece": {"mass": 1.8387488261406897, "inertia": 1.5713628316463546e-10,
                       "com": [-0.012465795767522606, 0.0094529635279787],
                       "shape": {"type": "disc", "radius": 0.07679900486930823},
                       "pose": [-0.4202593598271952, 0.5495008668993936, 0.2237578106919771]},
         "friction": 4.160675945467918, "contact_tolerance": 1e-09,
         "fixels": [{"position": [-0.4460231641861785, 0.6226517899948618],
                     "radius": 0.0007563377240107205},
                    {"position": [-0.4906199865821551, 0.5114057557120696],
                     "radius": 0.0005448470626215549}]},
        "sa", [0.4834838285006763, -0.12107287619795534, -0.08014307698519174], True),
    "mu-1e9": (
        {"workpiece": {"mass": 0.06060428665534512, "inertia": 0.003270154738460297,
                       "com": [-0.03178444836283017, -0.02384405036465094],
                       "shape": {"type": "disc", "radius": 0.26123832480217396},
                       "pose": [-1.5178193767579637, 0.9723501405803012, 0.6721452093969913]},
         "friction": 1000000000.0, "contact_tolerance": 1e-09,
         "fixels": [{"position": [-1.6809565914422129, 0.7659836854458272],
                     "radius": 0.0018222473474807292},
                    {"position": [-1.2716698883194364, 0.879654496675786],
                     "radius": 0.0017864897256979634},
                    [-1.2572895050394206, 0.9915763801441251]]},
        "rrr", [0.9315529422112584, -0.36358579291606624, 0.0011455564210966264], False),
    "parallel-1e-5": (
        {"workpiece": {"mass": 1.0, "inertia": 0.9413045171522791,
                       "com": [-0.02606793360680254, 0.1454058547651798],
                       "shape": {"type": "polygon",
                                 "vertices": [[-1.0, -1.0], [0.0, -1.000005], [1.0, -1.0],
                                              [1.0, 1.0], [-1.0, 1.0]]},
                       "pose": [0.0, 0.0, 0.0]},
         "friction": 0.3, "contact_tolerance": 1e-09,
         "fixels": [[-0.2872171058676868, -1.0000035639144707],
                    [0.7767287277508309, -1.0000011163563614], [1.0, 0.43669281701291474],
                    [-1.2, 0.5]]},
        "nnns", [0.7637109667080587, -0.3949472018014764, 0.7852660570079661], False),
    "coincident-1e-10": (
        {"workpiece": {"mass": 1.0, "inertia": 0.7651294862286215,
                       "com": [-0.17021578048121203, -0.07545419429297745],
                       "shape": {"type": "polygon",
                                 "vertices": [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0],
                                              [-1.0, 1.0]]},
                       "pose": [0.0, 0.0, 0.0]},
         "friction": 1.0, "contact_tolerance": 1e-09,
         "fixels": [[0.6820702643401138, -1.0], [0.6820702644401138, -1.0],
                    [1.0, 0.30676427465120293], [-1.3, 0.0]]},
        "rrss", [0.706741651566208, -0.7067416515662253, 0.0510689827061006], False),
}


KNOWN_REPRODUCERS: set[str] = set()  # coincident-1e-10 fixed by PARALLEL_GUARD


@pytest.mark.parametrize("name", [
    pytest.param(k, id=k, marks=(pytest.mark.xfail(strict=True, reason=_LEAD)
                                 if k in KNOWN_REPRODUCERS else ()))
    for k in REPRODUCERS])
def test_reproducer(name: str) -> None:
    data, mode, g, want = REPRODUCERS[name]
    scene = load_scene(data)
    exact = wrench_cone(scene, mode, exact=True, method="paper")
    assert exact.contains(g) == want  # the recorded exact verdict (guards the reproducer)
    assert abs(exact.margin(g)) >= BAND
    cone = wrench_cone(scene, mode)
    assert cone.feasible == exact.feasible
    assert cone.contains(g) == want


def test_every_family_is_exercised() -> None:
    """Every family of docs/error_vs_runtime.md (and the shared edge) is exercised (and
    none silently dropped)."""
    assert set(FAMILIES) == {"paper", "random", "mass", "inertia", "mu", "parallel",
                             "coincident", "offset", "size", "gaps", "shared_edge"}
    assert families.BAND == 1e-8
