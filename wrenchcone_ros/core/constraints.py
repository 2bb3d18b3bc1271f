"""The mode's constraints shared by every method, read from Table 2 (:data:`MODE_TABLE`).

* Acceleration conditions: a_i = J_i^T xdd for each fixel's normal and tangential
  direction, with the sign of Table 2. Their closure is the acceleration cone X.
* Feasibility of the *open* mode (READING_NOTES, "Closure versus the mode itself"): the
  strict conditions (a_in < 0 for a, a_in > 0 for s in contact, a_it > 0 for l,
  a_it < 0 for r) must hold together for some xdd in X. Since X is a convex cone this
  holds iff each strict row is positive on some generator of X (add those generators).
* Contact-force generators: the per-fixel force cone pos{n_i + s mu t_i : s in edges}.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .dynamics import Problem
from .modes import Sign
from .tolerances import FEASIBILITY_TOLERANCE


@dataclass(frozen=True)
class AccelerationConstraints:
    """Rows over xdd_hat: ``d . xdd >= 0`` (closure) for ``ineq``, ``e . xdd = 0`` for ``eq``."""

    ineq: list
    strict: list  # one bool per row of ineq
    eq: list


def acceleration_constraints(prob: Problem) -> AccelerationConstraints:
    """Table 2's acceleration columns as rows over xdd_hat (a = J_hat^T xdd_hat)."""
    ineq, strict, eq = [], [], []
    n = prob.n
    for i, inter in enumerate(prob.interactions):
        for sign, col in ((inter.a_n(prob.in_contact[i]), i), (inter.a_t, n + i)):
            row = list(prob.J[:, col])
            if sign is Sign.FREE:
                continue
            if sign is Sign.ZERO:
                eq.append(row)
                continue
            ineq.append(row if sign.direction > 0 else [-x for x in row])
            strict.append(sign.strict)
    return AccelerationConstraints(ineq, strict, eq)


def open_mode_feasible(cons: AccelerationConstraints, rays: list, lines: list,
                       exact: bool) -> bool:
    """Whether some xdd in X = pos(rays) + span(lines) meets every strict row strictly."""
    gens = [np.array(r, dtype=object if exact else float) for r in rays]
    lins = [np.array(r, dtype=object if exact else float) for r in lines]
    for row, is_strict in zip(cons.ineq, cons.strict):
        if not is_strict:
            continue
        d = np.array(row, dtype=object if exact else float)
        if exact:
            ok = any(d.dot(g) > 0 for g in gens) or any(d.dot(x) != 0 for x in lins)
        else:
            d = d / np.linalg.norm(d)
            ok = any(d.dot(g) / np.linalg.norm(g) > FEASIBILITY_TOLERANCE for g in gens) or any(
                abs(d.dot(x)) / np.linalg.norm(x) > FEASIBILITY_TOLERANCE for x in lins)
        if not ok:
            return False
    return True


def force_generators(prob: Problem) -> list:
    """Wrench-space generators -J_hat (n_i + s mu_i t_i) of the loaded fixels' force cones.

    g = M xdd - J c, so a contact force c_i = n_i + s mu t_i contributes -J_i c_i.
    """
    n = prob.n
    gens = []
    for i, inter in enumerate(prob.interactions):
        if not inter.loaded:
            continue
        for s in inter.c_t.edges:
            gens.append(list(-(prob.J[:, i] + s * prob.mu[i] * prob.J[:, n + i])))
    return gens
