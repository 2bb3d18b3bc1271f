# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The planar formulation: a Minkowski sum of cones in 3-D wrench space.

docs/theory.md, "The planar formulation (the default)", states it in full.

Newton-Euler, g = M xdd - J c, makes the consistent set

    W = M X + (-J) C_c,

X = {xdd : J^T xdd meets the mode's acceleration conditions} (closure: a 3-D cone given
by at most 2n rows), C_c the product of the loaded fixels' friction-cone edges. Both
representations of W come from two 3-D conversions instead of the paper's conversion in
up to 2n dimensions; mu = 0 needs no special case. The paper's method stays as the
reference this is tested against (test/core/test_crosscheck.py).

Float conversions use :mod:`.cone3d` (vectorised, self-checking); when its self-check
fails (:class:`~.cone3d.Cone3Error`), or the mode's acceleration rows are nearly parallel
(:func:`~.constraints.ill_conditioned`), the cone is recomputed exactly from the scene
and its floats returned (counted in ``PLANAR_FALLBACKS``). ``exact=True`` uses cddlib
GMP throughout.
"""

from __future__ import annotations

import numpy as np

from . import cone3d, stats
from .cones import (
    Cone,
    as_float,
    cone_from_vrep,
    from_cone3,
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
from .dynamics import Problem, exact_problem

#: How often a cone3d conversion failed its self-check and exact cddlib was used instead
#: (lives in :mod:`.stats`).
PLANAR_FALLBACKS = stats.PLANAR_FALLBACKS


def acceleration_cone(prob: Problem, acc: AccelerationConstraints | None = None):
    """The mode's acceleration rows and generators (rays, lines) of the closed cone X.

    Float: cone3d, which raises Cone3Error when its self-check fails.

    Parameters
    ----------
    prob : Problem
        The nondimensional problem.
    acc : AccelerationConstraints or None, optional
        Its acceleration rows, when already computed.

    Returns
    -------
    acc : AccelerationConstraints
        The acceleration rows.
    rays, lines : array_like
        The generators of X.

    Raises
    ------
    Cone3Error
        A float conversion failed its self-check.
    """
    acc = acceleration_constraints(prob) if acc is None else acc
    if prob.exact:
        return acc, *hrep_to_vrep(acc.ineq.tolist(), acc.eq.tolist(), True)
    c = cone3d.from_inequalities(acc.ineq, acc.eq)
    return acc, c.rays, c.lines


def _float_cone(gens: np.ndarray, lines: np.ndarray, prob: Problem) -> Cone:
    return from_cone3(cone3d.from_generators(gens, lines), prob.mode, prob.length_scale,
                      "planar")


def planar_cone(prob: Problem) -> Cone:
    """The wrench cone W = M X + (-J) C_c of the planar formulation, canonical.

    X is the mode's cone of accelerations, C_c its cone of contact forces (Table 2), M
    the mass matrix and J the contact Jacobian (section 2 of the paper). A float problem
    with nearly parallel acceleration rows (constraints.ill_conditioned) is computed
    exactly from its scene and returned as floats (PLANAR_FALLBACKS).

    Parameters
    ----------
    prob : Problem
        One scene and mode, nondimensionalised (:func:`.dynamics.problem`), float or
        exact.

    Returns
    -------
    Cone
        Method ``planar``; infeasible (with its closure) when the open mode is
        impossible.
    """
    acc = acceleration_constraints(prob)
    if ill_conditioned(prob, acc):
        PLANAR_FALLBACKS["exact_ill_conditioned"] += 1
        return as_float(planar_cone(exact_problem(prob)))
    if not prob.exact:
        PLANAR_FALLBACKS["float_cones"] += 1
        try:
            return _planar_float(prob, acc)
        except cone3d.Cone3Error:
            PLANAR_FALLBACKS["exact_fallbacks"] += 1
            return as_float(planar_cone(exact_problem(prob)))
    acc, rays, lines = acceleration_cone(prob, acc)
    M = prob.M
    gens = [list(M.dot(np.array(r, dtype=object))) for r in rays]
    gens += force_generators(prob).tolist()
    lin = [list(M.dot(np.array(v, dtype=object))) for v in lines]
    cone = cone_from_vrep(gens, lin, mode=prob.mode, length_scale=prob.length_scale,
                          method="planar", exact=True)
    if not open_mode_feasible(acc, rays, lines, True):
        return infeasible_cone(cone)
    return cone


def _planar_float(prob: Problem, acc: AccelerationConstraints) -> Cone:
    """The float path: cone3d for both conversions (raises Cone3Error on a failed check)."""
    acc, rays, lines = acceleration_cone(prob, acc)
    M = np.asarray(prob.M, dtype=float)
    gens = np.vstack([rays @ M.T, force_generators(prob)])
    cone = _float_cone(gens, lines @ M.T, prob)
    if not open_mode_feasible(acc, rays, lines, False):
        return infeasible_cone(cone)
    return cone
