# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Random 3-D cones and their exact reference: the families of the cone3d agreement tests.

Shared by ``test/core/test_cone3d.py``, ``test/core/test_kernel.py`` and
``benchmarks/cone3d_vs_cdd.py``: each family draws a generator set (or, read as rows, an
inequality set) with ``rng``; :func:`check_generators` / :func:`check_inequalities` convert
it with cone3d and with exact cddlib (Fractions of the same floats) and tally agreement
(:func:`agree` up to ``ANGLE``), Cone3Error and silent disagreements; :func:`run_family` runs
one family. Not a test module; importable as ``cone3d_cases`` once ``test/`` is on sys.path.
"""

from __future__ import annotations

from collections import Counter

import numpy as np
from scipy.optimize import linear_sum_assignment

from wrenchcone_ros.core.cone3d import Cone3, Cone3Error, from_generators, from_inequalities
from wrenchcone_ros.core.cones import (
    _orthonormal_rows,
    _to_float,
    _unit_rows_orthogonal_to,
    hrep_to_vrep,
    vrep_to_hrep,
)

#: Facets/rays of cone3d and exact cddlib must agree to this (unit vectors, radians). The
#: computed direction of a normal through two rays 1e-9 rad apart is good to ~1e-7.
ANGLE = 1e-6


# --- ground truth and comparison ------------------------------------------------------------
def exact_from_generators(rays, lines) -> Cone3:
    F, E = vrep_to_hrep(_lists(rays), _lists(lines), True)
    R, L = hrep_to_vrep([[-x for x in f] for f in F], E, True)
    return _normalise(F, E, R, L)


def exact_from_inequalities(ineq, eq) -> Cone3:
    R, L = hrep_to_vrep(_lists(ineq), _lists(eq), True)
    F, E = vrep_to_hrep(R, L, True)
    return _normalise(F, E, R, L)


def _lists(a):
    return [[float(x) for x in r] for r in np.asarray(a, dtype=float).reshape(-1, 3)]


def _normalise(F, E, R, L) -> Cone3:
    Eh = _orthonormal_rows(_to_float(E))
    Lh = _orthonormal_rows(_to_float(L))
    return Cone3(_unit_rows_orthogonal_to(_to_float(F), Eh), Eh,
                 _unit_rows_orthogonal_to(_to_float(R), Lh), Lh)


def row_distance(A: np.ndarray, B: np.ndarray) -> float:
    """Largest distance between paired rows of A and B under the best one-to-one pairing
    (nearly parallel rows may swap); inf when the counts differ."""
    if A.shape != B.shape:
        return float("inf")
    if A.shape[0] == 0:
        return 0.0
    D = np.linalg.norm(A[:, None, :] - B[None, :, :], axis=2)
    i, j = linear_sum_assignment(D)
    return float(D[i, j].max())


def span_distance(A: np.ndarray, B: np.ndarray) -> float:
    """Largest entry of the difference of the orthogonal projectors onto the row spaces of
    A and B (orthonormal rows); inf when the dimensions differ."""
    if A.shape != B.shape:
        return float("inf")
    return float(np.abs(A.T @ A - B.T @ B).max(initial=0.0))


def deviation(c: Cone3, g: Cone3) -> float:
    """How far cone3d's c is from the ground truth g (inf: a different structure)."""
    return max(span_distance(c.E, g.E), span_distance(c.lines, g.lines),
               row_distance(c.F, g.F), row_distance(c.rays, g.rays))


def agree(c: Cone3, g: Cone3, tol: float = ANGLE) -> bool:
    return deviation(c, g) <= tol


def well_formed(c: Cone3) -> None:
    """The representation conventions of cones.py."""
    for a in (c.F, c.E, c.rays, c.lines):
        assert a.ndim == 2 and a.shape[1] == 3 and np.all(np.isfinite(a))
    for a in (c.F, c.rays):
        assert np.allclose(np.linalg.norm(a, axis=1), 1.0)
    for a in (c.E, c.lines):
        assert np.allclose(a @ a.T, np.eye(a.shape[0]), atol=1e-12)
    assert np.abs(c.F @ c.E.T).max(initial=0) <= 1e-12
    assert np.abs(c.rays @ c.lines.T).max(initial=0) <= 1e-12
    assert np.abs(c.lines @ c.E.T).max(initial=0) <= 1e-12  # lines lie in the hull
    assert c.lines.shape[0] + c.E.shape[0] <= 3
    # the generators satisfy the inequalities
    assert (c.rays @ c.F.T).max(initial=0) <= 1e-9
    assert np.abs(c.lines @ c.F.T).max(initial=0) <= 1e-9
    assert np.abs(c.rays @ c.E.T).max(initial=0) <= 1e-9


def _record(tally: Counter, c: Cone3, g: Cone3) -> None:
    dev = deviation(c, g)
    tally["agree" if dev <= ANGLE else "silent"] += 1
    if dev <= ANGLE:
        tally["max_deviation"] = max(tally.get("max_deviation", 0.0), dev)


def _check(convert, exact_convert, a, b, tally: Counter) -> None:
    """Convert (a, b) with cone3d and exactly; tally the agreement, keep a disagreement."""
    try:
        c = convert(a, b)
    except Cone3Error:
        tally["cone3error"] += 1
        return
    well_formed(c)
    g = exact_convert(a, b)
    _record(tally, c, g)
    if not agree(c, g):
        tally.setdefault("examples", []).append((np.asarray(a), np.asarray(b), c, g))


def check_generators(rays, lines, tally: Counter) -> None:
    _check(from_generators, exact_from_generators, rays, lines, tally)


def check_inequalities(ineq, eq, tally: Counter) -> None:
    _check(from_inequalities, exact_from_inequalities, ineq, eq, tally)


# --- random families -------------------------------------------------------------------------
def _unit(v):
    return v / np.linalg.norm(v)


def _rot_towards(r, rng, angle):
    """r turned by ``angle`` rad in a random direction."""
    w = rng.normal(size=3)
    w -= (w @ r) / (r @ r) * r
    w = _unit(w) * np.linalg.norm(r)
    return np.cos(angle) * r + np.sin(angle) * w


def fam_pointed(rng):
    axis = _unit(rng.normal(size=3))
    k = int(rng.integers(1, 13))
    return axis + rng.uniform(0.2, 1.2) * rng.normal(size=(k, 3)), np.zeros((0, 3))


def fam_sphere(rng):
    return rng.normal(size=(int(rng.integers(0, 9)), 3)), np.zeros((0, 3))


def fam_lines(rng):
    return rng.normal(size=(int(rng.integers(0, 7)), 3)), rng.normal(size=(int(rng.integers(1, 3)), 3))


def fam_integer(rng):
    """Small integers: exact degeneracies everywhere; power-of-two scaling keeps them exact."""
    R = rng.integers(-3, 4, size=(int(rng.integers(0, 9)), 3)).astype(float)
    L = rng.integers(-3, 4, size=(int(rng.choice([0, 0, 0, 1, 2])), 3)).astype(float)
    if R.shape[0] >= 2 and rng.random() < 0.3:  # r and -r
        R = np.vstack([R, -R[: int(rng.integers(1, R.shape[0] + 1))]])
    if R.shape[0] >= 2 and rng.random() < 0.3:  # three rays summing to zero
        R = np.vstack([R, -(R[0] + R[1])])
    if rng.random() < 0.2 and R.shape[0]:  # duplicates (scaled)
        R = np.vstack([R, 2.0 * R[: int(rng.integers(1, R.shape[0] + 1))]])
    s = 2.0 ** rng.integers(-10, 11, size=3)
    return R * s, L * s


def fam_planar(rng):
    """Rays (and maybe one line) exactly in the plane spanned by two integer vectors, plus
    sometimes a ray or a line off it."""
    a, b = rng.integers(-4, 5, size=(2, 3)).astype(float)
    k = int(rng.integers(1, 7))
    co = rng.integers(-64, 65, size=(k, 2)) / 64.0
    R = co[:, :1] * a + co[:, 1:] * b
    L = np.zeros((0, 3))
    u = rng.random()
    if u < 0.2:
        L = (a + b)[None] if rng.random() < 0.5 else a[None]
    elif u < 0.35:
        R = np.vstack([R, np.cross(a, b)])
    elif u < 0.45:
        L = np.cross(a, b)[None]
    s = 2.0 ** rng.integers(-10, 11, size=3)
    return R * s, L * s


def fam_collinear(rng):
    a = rng.integers(-4, 5, size=3).astype(float)
    R = np.outer(rng.choice([-2.0, -1.0, 0.5, 1.0, 3.0], size=int(rng.integers(1, 4))), a)
    L = np.zeros((0, 3)) if rng.random() < 0.7 else rng.integers(-3, 4, size=(1, 3)).astype(float)
    return R, L


def fam_near_parallel(rng):
    """A pointed cone plus a copy of one ray turned by 1e-3..1e-9 rad, in a direction at
    least 0.1 rad out of every plane through that ray and another one (so that the copy is
    1e-10 rad or more away from those planes too: no accidental sub-tolerance feature)."""
    R, L = fam_pointed(rng)
    angle = 10.0 ** rng.uniform(-9, -3)
    i = int(rng.integers(0, R.shape[0]))
    r = _unit(R[i])
    others = [_unit(np.cross(r, q)) for k, q in enumerate(R) if k != i
              and np.linalg.norm(np.cross(r, _unit(q))) > 1e-3]
    for _ in range(100):
        w = _rot_towards(r, rng, np.pi / 2)  # a random unit direction orthogonal to r
        if all(abs(w @ n) >= 0.1 for n in others):
            break
    turned = (np.cos(angle) * r + np.sin(angle) * w) * np.linalg.norm(R[i])
    return np.vstack([R, turned]), L


def fam_near_coplanar(rng):
    """Rays exactly in the plane of two integer vectors (dyadic combinations) and one ray
    1e-3..1e-9 rad off that plane, on a random side."""
    while True:
        a, b = rng.integers(-4, 5, size=(2, 3)).astype(float)
        if np.any(np.cross(a, b)):
            break
    n = _unit(np.cross(a, b))
    co = rng.integers(0, 65, size=(int(rng.integers(0, 4)), 2)) / 64.0
    R = [a, b] + list(co[:, :1] * a + co[:, 1:] * b)
    c = _unit(rng.uniform(-1, 1) * a + rng.uniform(-1, 1) * b)
    angle = 10.0 ** rng.uniform(-9, -3)
    R.append(np.cos(angle) * c + rng.choice([-1.0, 1.0]) * np.sin(angle) * n)
    return np.array(R), np.zeros((0, 3))


def fam_anisotropic(rng):
    R, L = [fam_pointed, fam_sphere, fam_lines][int(rng.integers(0, 3))](rng)
    s = 10.0 ** rng.uniform(-3, 3, size=3)
    return R * s, L * s


FAMILIES = {
    "pointed": fam_pointed,
    "sphere": fam_sphere,
    "lines": fam_lines,
    "integer": fam_integer,
    "planar": fam_planar,
    "collinear": fam_collinear,
    "near_parallel": fam_near_parallel,
    "near_coplanar": fam_near_coplanar,
    "anisotropic": fam_anisotropic,
}


def run_family(name: str, n: int, seed: int, inequalities: bool) -> Counter:
    rng = np.random.default_rng([seed, list(FAMILIES).index(name), int(inequalities)])
    tally: Counter = Counter()
    for _ in range(n):
        a, b = FAMILIES[name](rng)
        (check_inequalities if inequalities else check_generators)(a, b, tally)
    return tally
