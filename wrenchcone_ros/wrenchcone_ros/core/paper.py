# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The paper's algorithm (sections 2-5), one function per step, in float or exact arithmetic.

The paper: Devin J. Balkcom and Jeffrey C. Trinkle, "Computing wrench cones for planar
rigid body contact tasks", The International Journal of Robotics Research,
21(12):1053-1066, 2002. docs/theory.md restates the model, the sign fixes and the
worked example.

    a = A c + B g,  A = J^T M^-1 J,  B = J^T M^-1                      (eq. 6)
    C y = B g,      C = [I_2n, -A],  y = [a_n; a_t; c_n; c_t]           (eq. 7)
    K = E C N R S V,  P = E B,  K z = P g,  z >= 0                      (section 5)
    F = K^F P                                                          (Theorem 1, k = 0)

All matrices are built in the nondimensional variables of :mod:`.dynamics`; the
variable constraints (Table 3 of the example, generally Table 2 per fixel) come from
:data:`~wrenchcone_ros.core.modes.MODE_TABLE` via :func:`mode_constraints`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import stats
from .cones import Cone, as_float, cone_from_hrep, hrep_to_vrep, infeasible_cone, vrep_to_hrep
from .constraints import acceleration_constraints, ill_conditioned, open_mode_feasible
from .dynamics import Problem, exact_problem
from .modes import Friction, Sign
from .planar import planar_cone  # the independent formulation, used only as a check
from .tolerances import VERIFY_TOLERANCE


def _eye(n: int, exact: bool) -> np.ndarray:
    out = np.zeros((n, n), dtype=object if exact else float)
    if exact:
        out[:] = 0
    for i in range(n):
        out[i, i] = 1
    return out


def contact_matrices(J: np.ndarray, M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A = J^T M^-1 J and B = J^T M^-1 (eq. 6). M is diagonal (com reference point).

    Parameters
    ----------
    J : numpy.ndarray
        J_hat, 3 x 2n.
    M : numpy.ndarray
        M_hat, 3 x 3, diagonal.

    Returns
    -------
    A : numpy.ndarray
        J^T M^-1 J, 2n x 2n.
    B : numpy.ndarray
        J^T M^-1, 2n x 3.
    """
    Minv = np.zeros_like(M)
    if M.dtype == object:
        Minv[:] = 0
    for i in range(3):
        Minv[i, i] = 1 / M[i, i]
    B = J.T.dot(Minv)
    return B.dot(J), B


def constraint_matrix(A: np.ndarray) -> np.ndarray:
    """C = [I_2n, -A] (eq. 7), acting on y = [a_1n..a_nn, a_1t..a_nt, c_1n.., c_1t..].

    Parameters
    ----------
    A : numpy.ndarray
        A = J^T M^-1 J, 2n x 2n.

    Returns
    -------
    numpy.ndarray
        C, 2n x 4n, in A's number type.
    """
    m = A.shape[0]
    return np.hstack([_eye(m, A.dtype == object), -A])


@dataclass(frozen=True)
class VariableConstraint:
    """Constraint of one entry of y (Table 3): a sign, or a friction rule for c_it.

    Parameters
    ----------
    sign : Sign
        The sign the entry is constrained to.
    friction : Friction or None, optional
        For c_it only: the friction rule (cone, left or right edge, none).
    """

    sign: Sign
    friction: Friction | None = None  # only for c_it


def mode_constraints(prob: Problem) -> list[VariableConstraint]:
    """Table 3 for the mode: one constraint per entry of y, from MODE_TABLE (Table 2).

    Parameters
    ----------
    prob : Problem
        The nondimensional problem.

    Returns
    -------
    list of VariableConstraint
        4n constraints, in the order of y = [a_n; a_t; c_n; c_t].
    """
    inter, contact = prob.interactions, prob.in_contact
    a_n = [VariableConstraint(x.a_n(c)) for x, c in zip(inter, contact)]
    a_t = [VariableConstraint(x.a_t) for x in inter]
    c_n = [VariableConstraint(x.c_n) for x in inter]
    c_t = [VariableConstraint(Sign.FREE if x.c_t is Friction.CONE else Sign.ZERO, x.c_t)
           for x in inter]
    return a_n + a_t + c_n + c_t


def elimination_matrix(cons: list[VariableConstraint], exact: bool) -> np.ndarray:
    """E: keep the rows of eq. 7 whose acceleration is constrained (drop free a's).

    Parameters
    ----------
    cons : list of VariableConstraint
        The constraints of y (:func:`mode_constraints`).
    exact : bool
        Exact arithmetic (object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        E, one row of the identity per constrained acceleration.
    """
    m = len(cons) // 2
    keep = [j for j in range(m) if cons[j].sign is not Sign.FREE]
    return _eye(m, exact)[keep]


def negation_matrix(cons: list[VariableConstraint], exact: bool) -> np.ndarray:
    """N: diagonal, -1 for the variables constrained negative (a_in < 0, a_it < 0).

    Parameters
    ----------
    cons : list of VariableConstraint
        The constraints of y (:func:`mode_constraints`).
    exact : bool
        Exact arithmetic (object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        N, 4n x 4n.
    """
    N = _eye(len(cons), exact)
    for j, c in enumerate(cons):
        if c.sign.direction < 0:
            N[j, j] = -1
    return N


def rolling_matrix(cons: list[VariableConstraint], mu: tuple, exact: bool) -> np.ndarray:
    """R: for rolling, c_in = u + w, c_it = mu (u - w) with u, w >= 0.

    This is the paper's u = (mu c_in + c_it) / 2mu, w = (mu c_in - c_it) / 2mu written
    as old = R new, so no division by mu: mu = 0 gives u and w the same column.

    Parameters
    ----------
    cons : list of VariableConstraint
        The constraints of y (:func:`mode_constraints`).
    mu : tuple
        The friction coefficient of each fixel.
    exact : bool
        Exact arithmetic (object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        R, 4n x 4n.
    """
    R = _eye(len(cons), exact)
    n = len(cons) // 4
    for i in range(n):
        if cons[3 * n + i].friction is Friction.CONE:
            cn, ct = 2 * n + i, 3 * n + i
            R[cn, ct], R[ct, cn], R[ct, ct] = 1, mu[i], -mu[i]
    return R


def sliding_matrix(cons: list[VariableConstraint], mu: tuple, exact: bool) -> np.ndarray:
    """S: sliding folds c_it = s mu c_in into the c_in column (s = -1 left, +1 right).

    Parameters
    ----------
    cons : list of VariableConstraint
        The constraints of y (:func:`mode_constraints`).
    mu : tuple
        The friction coefficient of each fixel.
    exact : bool
        Exact arithmetic (object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        S, 4n x 4n.
    """
    S = _eye(len(cons), exact)
    n = len(cons) // 4
    for i in range(n):
        rule = cons[3 * n + i].friction
        if rule in (Friction.LEFT_EDGE, Friction.RIGHT_EDGE):
            S[3 * n + i, 2 * n + i] = rule.edges[0] * mu[i]
    return S


def selection_matrix(cons: list[VariableConstraint], exact: bool) -> np.ndarray:
    """V: keep the variables that remain (>= 0 after N, R, S); drop zero, folded, free.

    Parameters
    ----------
    cons : list of VariableConstraint
        The constraints of y (:func:`mode_constraints`).
    exact : bool
        Exact arithmetic (object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        V, 4n columns by one per kept variable.
    """
    n = len(cons) // 4
    keep = []
    for j, c in enumerate(cons):
        if j >= 3 * n:  # c_it: kept only as the rolling variable w
            if c.friction is Friction.CONE:
                keep.append(j)
        elif c.sign not in (Sign.ZERO, Sign.FREE):
            keep.append(j)
    return _eye(len(cons), exact)[:, keep]


def equilibrate(K: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positive row and column scalings of K z = P g that leave Theorem 1's set unchanged.

    Scaling a column of K rescales one z_j >= 0 (pos(K) is the same cone); scaling a row
    of [K | P] by a positive number rescales one equation. Unit columns, then unit rows,
    bring the float conversion's input to O(1) entries when I / (m L^2) is tiny or huge.
    Float only; exact arithmetic needs no scaling.

    Parameters
    ----------
    K : numpy.ndarray
        K = E C N R S V.
    P : numpy.ndarray
        P = E B.

    Returns
    -------
    K : numpy.ndarray
        K with unit columns, then K's and P's rows scaled together.
    P : numpy.ndarray
        P with the same row scaling.
    """
    if K.dtype == object or K.size == 0:
        return K, P
    cn = np.linalg.norm(K, axis=0)
    K = K / np.where(cn > 0, cn, 1.0)
    rn = np.linalg.norm(np.hstack([K, P]), axis=1)
    rn = np.where(rn > 0, rn, 1.0)[:, None]
    return K / rn, P / rn


def theorem1(K: np.ndarray, P: np.ndarray, exact: bool) -> tuple[list, list]:
    """Theorem 1 with k = 0: {g : exists z >= 0, K z = P g} = {g : K^F P g <= 0}.

    K^F is the face-normal form of pos(K) (cddlib), including its equality rows.

    Parameters
    ----------
    K : numpy.ndarray
        The matrix whose columns generate pos(K): the paper's K = E C N R S V
        (section 5).
    P : numpy.ndarray
        The matrix that maps g_hat into K's space: the paper's P = E B.
    exact : bool
        Convert in exact rational arithmetic (cddlib's GMP mode) rather than float.

    Returns
    -------
    tuple of (list, list)
        (F, E): inequality rows (F g_hat <= 0) and equality rows (E g_hat = 0) over
        g_hat, possibly redundant.
    """
    if K.shape[0] == 0:
        return [], []
    K, P = equilibrate(K, P)
    KF, KE = vrep_to_hrep([list(col) for col in K.T], [], exact)
    F = [list(np.array(r, dtype=P.dtype).dot(P)) for r in KF]
    E = [list(np.array(r, dtype=P.dtype).dot(P)) for r in KE]
    return F, E


def kp_matrices(prob: Problem) -> tuple[np.ndarray, np.ndarray]:
    """K = E C N R S V and P = E B (section 5).

    Parameters
    ----------
    prob : Problem
        The nondimensional problem.

    Returns
    -------
    K : numpy.ndarray
        E C N R S V.
    P : numpy.ndarray
        E B.
    """
    ex = prob.exact
    A, B = contact_matrices(prob.J, prob.M)
    C = constraint_matrix(A)
    cons = mode_constraints(prob)
    E = elimination_matrix(cons, ex)
    K = E.dot(C).dot(negation_matrix(cons, ex)).dot(rolling_matrix(cons, prob.mu, ex)).dot(
        sliding_matrix(cons, prob.mu, ex)).dot(selection_matrix(cons, ex))
    return K, E.dot(B)


def theorem1_holds(cone: Cone, K: np.ndarray, P: np.ndarray) -> bool:
    """Soundness check of a float result: every extreme ray and line g of the cone must
    satisfy Theorem 1's premise, P g in pos(K) (non-negative least squares, relative
    residual <= VERIFY_TOLERANCE). Catches float cddlib returning too large a cone,
    which happens when K is ill-conditioned (nearly coincident fixels, docs/numerics.md).

    Parameters
    ----------
    cone : Cone
        A float cone computed from ``K`` and ``P``.
    K : numpy.ndarray
        E C N R S V.
    P : numpy.ndarray
        E B.

    Returns
    -------
    bool
        True when every generator of the cone passes.
    """
    from scipy.optimize import nnls  # lazy: scipy.optimize takes 0.6 s to import

    K = np.asarray(K, dtype=float)
    P = np.asarray(P, dtype=float)
    tests = [*cone.G_hat, *cone.L_hat, *(-cone.L_hat)]
    for g in tests:
        b = P @ g
        nb = float(np.linalg.norm(b))
        if nb == 0:
            continue
        if K.shape[1] == 0:
            return False
        if nnls(K, b / nb, maxiter=50 * K.shape[1])[1] > VERIFY_TOLERANCE:
            return False
    return True


def same_cone(a: Cone, b: Cone, tol: float = VERIFY_TOLERANCE) -> bool:
    """Whether two canonical float cones agree: same dimensions, same facets (up to tol).

    Parameters
    ----------
    a, b : Cone
        Two canonical float cones.
    tol : float, optional
        The largest distance between matching unit facet rows (~ the angle in rad).

    Returns
    -------
    bool
        True when both cones have the same shape and facets within ``tol``.
    """
    if a.F_hat.shape != b.F_hat.shape or a.E_hat.shape != b.E_hat.shape or (
            a.L_hat.shape != b.L_hat.shape):
        return False
    if not np.allclose(a.E_hat.T @ a.E_hat, b.E_hat.T @ b.E_hat, atol=tol):
        return False
    if a.F_hat.shape[0] == 0:
        return True
    # every facet of a has a partner in b within tol (unit rows: distance ~ angle in rad)
    d = np.linalg.norm(a.F_hat[:, None, :] - b.F_hat[None, :, :], axis=2)
    return bool(np.all(d.min(axis=1) <= tol))


def _planar_closure(prob: Problem) -> Cone:
    c = planar_cone(prob)
    return c.closure if c.closure is not None else c


#: How often the float paper method failed its soundness check and was redone exactly
#: (lives in :mod:`.stats`).
PAPER_FALLBACKS = stats.PAPER_FALLBACKS


def paper_cone(prob: Problem) -> Cone:
    """The cone of consistent wrenches by the paper's algorithm (closure, then feasibility).

    In float, the closure is checked: soundness by :func:`theorem1_holds`, completeness by
    comparison with the planar formulation's closure (:func:`same_cone`; the paper's
    conversion in up to 2n dimensions silently merges nearly opposite facets into an
    equality when K is ill-conditioned, e.g. I / (m L^2) ~ 1e-9). If either check fails
    the closure is redone exactly on the same float data and its floats used (counted in
    PAPER_FALLBACKS), so the paper's answer never depends on the planar one. Feasibility
    is always decided in the problem's own arithmetic: in exact arithmetic on rounded
    float data, a mode that is impossible for the written numbers (an acceleration cone
    that is exactly a line) can turn into a sliver.

    Parameters
    ----------
    prob : Problem
        One scene and mode, nondimensionalised (:func:`.dynamics.problem`), float or
        exact.

    Returns
    -------
    Cone
        Method ``paper``; infeasible (with its closure) when the open mode is impossible.
    """
    if not prob.exact and ill_conditioned(prob, acceleration_constraints(prob)):
        PAPER_FALLBACKS["exact_ill_conditioned"] += 1
        return as_float(paper_cone(exact_problem(prob)))
    K, P = kp_matrices(prob)
    F, E = theorem1(K, P, prob.exact)
    closure = cone_from_hrep(F, E, mode=prob.mode, length_scale=prob.length_scale,
                             method="paper", exact=prob.exact)
    if not prob.exact:
        PAPER_FALLBACKS["float_cones"] += 1
        if not (theorem1_holds(closure, K, P) and same_cone(closure, _planar_closure(prob))):
            PAPER_FALLBACKS["exact_fallbacks"] += 1
            return as_float(paper_cone(exact_problem(prob)))
    acc = acceleration_constraints(prob)
    rays, lines = hrep_to_vrep(acc.ineq.tolist(), acc.eq.tolist(), prob.exact)
    if not open_mode_feasible(acc, rays, lines, prob.exact):
        return infeasible_cone(closure)
    return closure
