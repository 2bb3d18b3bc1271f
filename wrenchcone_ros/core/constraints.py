"""The mode's constraints shared by every method, read from Table 2 (:data:`MODE_TABLE`).

* Acceleration conditions: a_i = J_i^T xdd for each fixel's normal and tangential
  direction, with the sign of Table 2. Their closure is the acceleration cone X.
* Feasibility of the *open* mode (READING_NOTES, "Closure versus the mode itself"): the
  strict conditions (a_in < 0 for a, a_in > 0 for s in contact, a_it > 0 for l,
  a_it < 0 for r) must hold together for some xdd in X. Since X is a convex cone this
  holds iff each strict row is positive on some extreme ray of X (add those rays).
* Contact-force generators: the per-fixel force cone pos{n_i + s mu t_i : s in edges}.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .dynamics import Problem
from .modes import Sign
from .tolerances import FEASIBILITY_TOLERANCE, PARALLEL_GUARD


@dataclass(frozen=True)
class AccelerationConstraints:
    """Rows over xdd_hat: ``d . xdd >= 0`` (closure) for ``ineq``, ``e . xdd = 0`` for ``eq``.

    Arrays of shape (k, 3), float or object (Fractions) like the problem's J.
    """

    ineq: np.ndarray
    strict: np.ndarray  # one bool per row of ineq
    eq: np.ndarray


def acceleration_constraints(prob: Problem) -> AccelerationConstraints:
    """Table 2's acceleration columns as rows over xdd_hat (a = J_hat^T xdd_hat)."""
    n = prob.n
    signs = [inter.a_n(prob.in_contact[i]) for i, inter in enumerate(prob.interactions)]
    signs += [inter.a_t for inter in prob.interactions]
    rows = prob.J.T  # row k: a_k = rows[k] . xdd
    ineq_idx = [k for k, sg in enumerate(signs) if sg.direction != 0]
    eq_idx = [k for k, sg in enumerate(signs) if sg is Sign.ZERO]
    direction = np.array([signs[k].direction for k in ineq_idx], dtype=int)
    ineq = rows[ineq_idx] * direction[:, None] if ineq_idx else rows[:0]
    strict = np.array([signs[k].strict for k in ineq_idx], dtype=bool)
    assert len(signs) == 2 * n
    return AccelerationConstraints(ineq, strict, rows[eq_idx])


def open_mode_feasible(cons: AccelerationConstraints, rays, lines, exact: bool) -> bool:
    """Whether some xdd in X = pos(rays) + span(lines) meets every strict row strictly.

    Lines of X never help: l and -l both lie in X, so d . l >= 0 and -d . l >= 0 for every
    row d, i.e. d . l = 0. Hence the open mode is possible iff each strict row is
    positive on some extreme ray (then the sum of those rays meets all of them). In float,
    a cone that cddlib or cone3d reports as a line is at most a sliver of angle ~1e-10
    around it, on which the strict rows are at most ~1e-10 positive: below
    FEASIBILITY_TOLERANCE either way. ``lines`` is accepted for the signature's sake.
    """
    del lines
    strict_rows = cons.ineq[cons.strict]
    if strict_rows.shape[0] == 0:
        return True
    if exact:
        gens = [np.array(r, dtype=object) for r in rays]
        return all(any(d.dot(g) > 0 for g in gens) for d in strict_rows)
    R = np.reshape(np.asarray(rays, dtype=float), (-1, 3))
    if R.shape[0] == 0:
        return False
    D = strict_rows / np.linalg.norm(strict_rows, axis=1, keepdims=True)
    R = R / np.linalg.norm(R, axis=1, keepdims=True)
    return bool((D @ R.T > FEASIBILITY_TOLERANCE).any(axis=1).all())


def force_generators(prob: Problem) -> np.ndarray:
    """Wrench-space generators -J_hat (n_i + s mu_i t_i) of the loaded fixels' force cones.

    g = M xdd - J c, so a contact force c_i = n_i + s mu_i t_i contributes -J_i c_i.
    Rows, shape (k, 3).
    """
    n = prob.n
    gens = []
    for i, inter in enumerate(prob.interactions):
        if not inter.loaded:
            continue
        for s in inter.c_t.edges:
            gens.append(-(prob.J[:, i] + s * prob.mu[i] * prob.J[:, n + i]))
    if not gens:
        return np.zeros((0, 3), dtype=prob.J.dtype)
    return np.array(gens, dtype=prob.J.dtype)


def nearly_parallel(rows: np.ndarray, angle: float = PARALLEL_GUARD) -> bool:
    """Whether two rows are closer than ``angle`` (rad, up to sign) but not exactly parallel.

    Nearly coincident fixels give such acceleration rows: the float geometry's rounding
    (~1e-16) is amplified by 1/angle in the acceleration cone and in the open mode's
    feasibility, so the float methods recompute such a cone exactly from the scene.
    Exactly equal rows (two fixels on one line of action) are harmless and excluded.
    """
    a = np.asarray(rows, dtype=float).reshape(-1, 3)
    if a.shape[0] < 2:
        return False
    n = np.linalg.norm(a, axis=1)
    u = a[n > 0] / n[n > 0, None]
    d = np.minimum(np.linalg.norm(u[:, None] - u[None], axis=2),
                   np.linalg.norm(u[:, None] + u[None], axis=2))
    np.fill_diagonal(d, np.inf)
    return bool(np.any((d > 0) & (d < angle)))


def ill_conditioned(prob: Problem, acc: AccelerationConstraints) -> bool:
    """Float problems whose acceleration rows are nearly parallel (see nearly_parallel)."""
    return (not prob.exact and prob.scene is not None
            and nearly_parallel(np.vstack([acc.ineq, acc.eq])))
