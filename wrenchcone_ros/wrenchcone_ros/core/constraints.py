# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The mode's constraints shared by every method, read from Table 2 (:data:`MODE_TABLE`).

* Acceleration conditions: a_i = J_i^T xdd for each fixel's normal and tangential
  direction, with the sign of Table 2. Their closure is the acceleration cone X.
* Feasibility of the *open* mode (docs/theory.md, "Closure versus the mode itself"): the
  strict conditions (a_in < 0 for a, a_in > 0 for s in contact, a_it > 0 for l,
  a_it < 0 for r) must hold together for some xdd in X. Since X is a convex cone this
  holds iff each strict row is positive on some extreme ray of X (add those rays).
* Contact-force generators: the per-fixel force cone pos{n_i + s mu t_i : s in edges}.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import stats
from .dynamics import Problem
from .modes import Sign
from .tolerances import FEASIBILITY_TOLERANCE, PARALLEL_GUARD


@dataclass(frozen=True)
class AccelerationConstraints:
    """Rows over xdd_hat: ``d . xdd >= 0`` (closure) for ``ineq``, ``e . xdd = 0`` for ``eq``.

    Arrays of shape (k, 3), float or object (Fractions) like the problem's J.

    Parameters
    ----------
    ineq : numpy.ndarray
        The rows d with ``d . xdd_hat >= 0``, shape (k, 3).
    strict : numpy.ndarray
        One bool per row of ``ineq``: whether the open mode needs the row strictly positive.
    eq : numpy.ndarray
        The rows e with ``e . xdd_hat = 0``, shape (k', 3).
    """

    ineq: np.ndarray
    strict: np.ndarray  # one bool per row of ineq
    eq: np.ndarray


_PLANS = stats.PLANS  # the cache lives in .stats (reset there)


def plan_for(mode: str, in_contact: tuple[bool, ...], inters: tuple) -> tuple:
    """Table 2 for this mode and contact state, as index arrays (cached).

    (ineq rows of J^T, their signs, strict flags, eq rows, loaded fixels, edge signs). The
    key is the mode string and contact state, which determine the interactions (also for
    the relaxations of .classify, whose letters '?' always mean all allowed letters).
    Depends on no pose: shared by every scene with this contact state.

    Parameters
    ----------
    mode : str
        The mode (relaxations included).
    in_contact : tuple of bool
        Which fixels touch the workpiece.
    inters : tuple of Interaction
        The fixels' interactions parsed from ``mode``.

    Returns
    -------
    tuple
        (ineq row indices, their directions as a (k, 1) int array, strict flags, eq row
        indices, the loaded fixels' indices, the edge signs of their friction cones).
    """
    key = (mode, in_contact)
    plan = _PLANS.get(key)
    if plan is None:
        signs = [inter.a_n(c) for inter, c in zip(inters, in_contact)]
        signs += [inter.a_t for inter in inters]
        ineq_idx = [k for k, sg in enumerate(signs) if sg.direction != 0]
        eq_idx = [k for k, sg in enumerate(signs) if sg is Sign.ZERO]
        direction = np.array([signs[k].direction for k in ineq_idx], dtype=int)[:, None]
        strict = np.array([signs[k].strict for k in ineq_idx], dtype=bool)
        pairs = [(i, s) for i, inter in enumerate(inters) if inter.loaded
                 for s in inter.c_t.edges]
        plan = (ineq_idx, direction, strict, eq_idx, [i for i, _ in pairs],
                np.array([s for _, s in pairs], dtype=float))
        stats.remember(_PLANS, key, plan)
    return plan


def _plan(prob: Problem) -> tuple:
    """:func:`plan_for` of a problem."""
    return plan_for(prob.mode, prob.in_contact, prob.interactions)


def acceleration_constraints(prob: Problem) -> AccelerationConstraints:
    """Table 2's acceleration columns as rows over xdd_hat (a = J_hat^T xdd_hat).

    Parameters
    ----------
    prob : Problem
        The nondimensional problem.

    Returns
    -------
    AccelerationConstraints
        The rows of X, the closure of the mode's accelerations.
    """
    ineq_idx, direction, strict, eq_idx = _plan(prob)[:4]
    rows = prob.J.T  # row k: a_k = rows[k] . xdd
    ineq = rows[ineq_idx] * direction if ineq_idx else rows[:0]
    return AccelerationConstraints(ineq, strict, rows[eq_idx])


def open_mode_feasible(cons: AccelerationConstraints, rays, lines, exact: bool) -> bool:
    """Whether some xdd in X = pos(rays) + span(lines) meets every strict row strictly.

    Lines of X never help: l and -l both lie in X, so d . l >= 0 and -d . l >= 0 for every
    row d, i.e. d . l = 0. Hence the open mode is possible iff each strict row is
    positive on some extreme ray (then the sum of those rays meets all of them). In float,
    a cone that cddlib or cone3d reports as a line is at most a sliver of angle ~1e-10
    around it, on which the strict rows are at most ~1e-10 positive: below
    FEASIBILITY_TOLERANCE either way. ``lines`` is accepted for the signature's sake.

    Parameters
    ----------
    cons : AccelerationConstraints
        The mode's acceleration rows.
    rays : sequence
        The extreme rays of X.
    lines : sequence
        The lines of X (not used, see above).
    exact : bool
        Whether ``rays`` and ``cons`` hold exact numbers.

    Returns
    -------
    bool
        True when the open mode is feasible.
    """
    del lines
    strict_rows = cons.ineq[cons.strict]
    if strict_rows.shape[0] == 0:
        return True
    if exact:
        gens = [np.array(r, dtype=object) for r in rays]
        return all(any(d.dot(g) > 0 for g in gens) for d in strict_rows)
    R = np.asarray(rays, dtype=float).reshape(-1, 3)
    if R.shape[0] == 0:
        return False
    # d . r > tol |d| |r| for some ray r, for every strict row d
    lhs = strict_rows @ R.T
    rhs = FEASIBILITY_TOLERANCE * np.sqrt((strict_rows * strict_rows).sum(1))[:, None] * (
        np.sqrt((R * R).sum(1))[None, :])
    return bool((lhs > rhs).any(axis=1).all())


def force_generators(prob: Problem) -> np.ndarray:
    """Wrench-space generators -J_hat (n_i + s mu_i t_i) of the loaded fixels' force cones.

    g = M xdd - J c, so a contact force c_i = n_i + s mu_i t_i contributes -J_i c_i.
    Rows, shape (k, 3).

    Parameters
    ----------
    prob : Problem
        The nondimensional problem.

    Returns
    -------
    numpy.ndarray
        The generators, shape (k, 3), of the problem's number type.
    """
    idx, sgn = _plan(prob)[4:]
    if not idx:
        return np.zeros((0, 3), dtype=prob.J.dtype)
    n = prob.n
    if prob.exact:
        return np.array([-(prob.J[:, i] + int(s) * prob.mu[i] * prob.J[:, n + i])
                         for i, s in zip(idx, sgn)], dtype=object)
    coef = sgn * np.asarray(prob.mu, dtype=float)[idx]
    JT = prob.J.T
    return -(JT[idx] + coef[:, None] * JT[[n + i for i in idx]])


def nearly_parallel(rows: np.ndarray, angle: float = PARALLEL_GUARD) -> bool:
    """Whether two rows are closer than ``angle`` (rad, up to sign) but not exactly parallel.

    Nearly coincident fixels give such acceleration rows: the float geometry's rounding
    (~1e-16) is amplified by 1/angle in the acceleration cone and in the open mode's
    feasibility, so the float methods recompute such a cone exactly from the scene.
    Exactly equal rows (two fixels on one line of action) are harmless and excluded.

    Parameters
    ----------
    rows : numpy.ndarray
        Rows, shape (k, 3).
    angle : float, optional
        The angle below which two rows count as nearly parallel (rad;
        :data:`~wrenchcone_ros.core.tolerances.PARALLEL_GUARD`).

    Returns
    -------
    bool
        True when two rows are within ``angle`` of each other (up to sign) but not parallel.
    """
    if rows.shape[0] < 2:
        return False
    u = rows / np.linalg.norm(rows, axis=1)[:, None]
    cos = np.abs(u @ u.T)
    np.fill_diagonal(cos, 0.0)
    if cos.max() <= 1.0 - angle * angle:  # 1 - cos ~ angle^2 / 2: no candidate pair
        return False
    # candidates decided by |u -+ v|, accurate for tiny angles where the cosine is not
    for i, j in zip(*np.nonzero(cos > 1.0 - angle * angle)):
        d = min(np.linalg.norm(u[i] - u[j]), np.linalg.norm(u[i] + u[j]))
        if 0 < d < angle:
            return True
    return False


def ill_conditioned(prob: Problem, acc: AccelerationConstraints) -> bool:
    """Float problems whose acceleration rows are nearly parallel (see nearly_parallel).

    Parameters
    ----------
    prob : Problem
        The problem.
    acc : AccelerationConstraints
        Its acceleration rows.

    Returns
    -------
    bool
        True for a float problem with a scene whose rows are nearly parallel.
    """
    return (not prob.exact and prob.scene is not None
            and nearly_parallel(np.concatenate([acc.ineq, acc.eq]).astype(float)))
