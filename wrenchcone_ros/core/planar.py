"""The planar formulation: a Minkowski sum of cones in 3-D wrench space (DESIGN.md).

Newton-Euler, g = M xdd - J c, makes the consistent set

    W = M X + (-J) C_c,

X = {xdd : J^T xdd meets the mode's acceleration conditions} (closure: a 3-D cone given
by at most 2n rows), C_c the product of the loaded fixels' friction-cone edges. Both
representations of W come from two 3-D conversions instead of the paper's conversion in
up to 2n dimensions; mu = 0 needs no special case. The paper's method stays as the
reference this is tested against (test/core/test_crosscheck.py).

Float conversions use :mod:`.cone3d` (vectorised, self-checking); when its self-check
fails (:class:`~.cone3d.Cone3Error`) the same conversion is redone with exact cddlib on
the same float data (counted in ``PLANAR_FALLBACKS``). ``exact=True`` uses cddlib GMP
throughout.
"""

from __future__ import annotations

import numpy as np

from . import cone3d
from .cones import (
    Cone,
    _sorted_rows,
    as_float,
    cone_from_vrep,
    hrep_to_vrep,
    infeasible_cone,
)
from .constraints import (
    AccelerationConstraints,
    acceleration_constraints,
    force_generators,
    ill_conditioned,
    open_mode_feasible,
)
from .dynamics import Problem, problem

#: How often a cone3d conversion failed its self-check and exact cddlib was used instead.
PLANAR_FALLBACKS: dict[str, int] = {"conversions": 0, "exact_fallbacks": 0,
                                    "exact_ill_conditioned": 0}


def _float_hrep_to_vrep(acc: AccelerationConstraints) -> tuple[np.ndarray, np.ndarray]:
    PLANAR_FALLBACKS["conversions"] += 1
    try:
        c = cone3d.from_inequalities(acc.ineq, acc.eq)
        return c.rays, c.lines
    except cone3d.Cone3Error:
        PLANAR_FALLBACKS["exact_fallbacks"] += 1
        rays, lines = hrep_to_vrep(acc.ineq.tolist(), acc.eq.tolist(), True)
        return np.array(rays, float).reshape(-1, 3), np.array(lines, float).reshape(-1, 3)


def acceleration_cone(prob: Problem):
    """The mode's acceleration rows and generators (rays, lines) of the closed cone X."""
    acc = acceleration_constraints(prob)
    if prob.exact:
        return acc, *hrep_to_vrep(acc.ineq.tolist(), acc.eq.tolist(), True)
    return acc, *_float_hrep_to_vrep(acc)


def _float_cone(gens: np.ndarray, lines: np.ndarray, prob: Problem) -> Cone:
    PLANAR_FALLBACKS["conversions"] += 1
    try:
        c = cone3d.from_generators(gens, lines)
    except cone3d.Cone3Error:
        PLANAR_FALLBACKS["exact_fallbacks"] += 1
        exact = cone_from_vrep(gens.tolist(), lines.tolist(), mode=prob.mode,
                               length_scale=prob.length_scale, method="planar", exact=True)
        return as_float(exact)
    return Cone(prob.mode, True, _sorted_rows(c.F + 0.0), c.E + 0.0, _sorted_rows(c.rays + 0.0),
                c.lines + 0.0, float(prob.length_scale), "planar", False)


def planar_cone(prob: Problem) -> Cone:
    """W = M X + (-J) C_c, canonical; infeasible when the open mode is impossible.

    A float problem with nearly parallel acceleration rows (constraints.ill_conditioned)
    is computed exactly from its scene and returned as floats (PLANAR_FALLBACKS).
    """
    if not prob.exact and ill_conditioned(prob, acceleration_constraints(prob)):
        PLANAR_FALLBACKS["exact_ill_conditioned"] += 1
        return as_float(planar_cone(problem(prob.scene, prob.mode, exact=True)))
    acc, rays, lines = acceleration_cone(prob)
    if prob.exact:
        M = prob.M
        gens = [list(M.dot(np.array(r, dtype=object))) for r in rays]
        gens += force_generators(prob).tolist()
        lin = [list(M.dot(np.array(v, dtype=object))) for v in lines]
        cone = cone_from_vrep(gens, lin, mode=prob.mode, length_scale=prob.length_scale,
                              method="planar", exact=True)
    else:
        M = np.asarray(prob.M, dtype=float)
        gens = np.vstack([np.reshape(rays, (-1, 3)) @ M.T, force_generators(prob)])
        cone = _float_cone(gens, np.reshape(lines, (-1, 3)) @ M.T, prob)
    if not open_mode_feasible(acc, rays, lines, prob.exact):
        return infeasible_cone(cone)
    return cone
