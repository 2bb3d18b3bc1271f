"""The planar formulation: a Minkowski sum of cones in 3-D wrench space (DESIGN.md).

Newton-Euler, g = M xdd - J c, makes the consistent set

    W = M X + (-J) C_c,

X = {xdd : J^T xdd meets the mode's acceleration conditions} (closure: a 3-D cone given
by at most 2n rows), C_c the product of the loaded fixels' friction-cone edges. Both
representations of W come from two 3-D conversions instead of the paper's conversion in
up to 2n dimensions; mu = 0 needs no special case. The paper's method stays as the
reference this is tested against (test/core/test_planar.py).
"""

from __future__ import annotations

import numpy as np

from .cones import Cone, cone_from_vrep, infeasible_cone
from .constraints import acceleration_constraints, force_generators, open_mode_feasible
from .cones import hrep_to_vrep
from .dynamics import Problem


def acceleration_cone(prob: Problem):
    """Generators (rays, lines) of the closed acceleration cone X over xdd_hat."""
    acc = acceleration_constraints(prob)
    return acc, *hrep_to_vrep(acc.ineq, acc.eq, prob.exact)


def planar_cone(prob: Problem) -> Cone:
    """W = M X + (-J) C_c, canonicalised; infeasible when the open mode is impossible."""
    acc, rays, lines = acceleration_cone(prob)
    M = prob.M
    dt = M.dtype

    def image(v):
        return list(M.dot(np.array(v, dtype=dt)))

    gens = [image(r) for r in rays] + force_generators(prob)
    cone = cone_from_vrep(gens, [image(v) for v in lines], mode=prob.mode,
                          length_scale=prob.length_scale, method="planar", exact=prob.exact)
    if not open_mode_feasible(acc, rays, lines, prob.exact):
        return infeasible_cone(cone)
    return cone
