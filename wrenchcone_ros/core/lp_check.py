"""An independent LP check: is a wrench consistent with a contact mode?

This module answers the same question as :func:`wrenchcone_ros.core.wrench_cone` without
any of the paper's matrices (no C, E, N, R, S, V, K, P, no cone conversion). It writes
Newton-Euler and Table 2 (:data:`~wrenchcone_ros.core.modes.MODE_TABLE`) directly as a
linear programme and solves it with scipy's HiGHS. It serves two purposes:

* the oracle of the randomized cross-check in the test suite, and
* the "LP per query" baseline of the benchmarks (what a user would otherwise write).

It imports no ROS module and reads from the scene only the contact points, normals,
tangents, contact states, friction coefficients, the centre of mass, mass, inertia and
length scale.

Formulation
-----------
Newton-Euler with the body at rest: ``M xdd = J c + g`` with ``M = diag(m, m, I)``,
``xdd = (a_x, a_y, alpha)``, ``J`` built here column by column (a unit force ``v`` at
``p_i`` contributes ``(v_x, v_y, r_i x v)``, ``r_i = p_i - com``; columns ``n_i`` and
``t_i``), contact accelerations ``a = J^T xdd``.

Nondimensionalisation (mass unit ``m``, length unit ``L = scene.length_scale``, force
unit ``|g_hat|``): with ``g_hat = (f_x, f_y, tau / L)`` scaled to unit Euclidean length,
``u = m (a_x, a_y, L alpha) / |g_hat|`` and ``c_hat = c / |g_hat|``, Newton-Euler reads::

    diag(1, 1, I / (m L^2)) u = J_hat c_hat + g_hat,    J_hat column = (v_x, v_y, (r/L) x v)

and ``m a / |g_hat| = J_hat^T u``: every sign condition of Table 2 on ``a`` holds for
``J_hat^T u`` unchanged. All LP data are then O(1) for any choice of units or magnitude
of g (only the geometry, ``I / (m L^2)`` and mu remain).

The open (strict) conditions of a mode (``a_in < 0`` for *a*, ``a_in > 0`` for *s* in
contact, ``a_it > 0`` for *l*, ``a_it < 0`` for *r*) are written ``sign * a >= s`` with
one slack variable ``s <= 1`` that the LP maximises. The non-strict conditions
(``a_in >= 0`` for *s* without contact, ``a_in = 0``, ``c_in >= 0``, the friction law)
are written as they are. Because a feasible set of ``(u, c)`` for fixed ``g`` has a
bounded ``u`` part (power argument: a homogeneous solution ``M u = J c`` with the mode's
signs has ``u^T M u = c^T a <= 0``), the optimum slack ``s*`` is a finite,
dimensionless measure of how strictly ``g`` realises the open mode, in units of the
nondimensional acceleration produced by a unit wrench.

Decision: g is consistent with the (open) mode iff the LP is feasible and
``s* > LP_SLACK_TOLERANCE``. With ``closure=True`` the strict conditions are replaced by
their closures (Theorem 1 with k = 0) and g is consistent iff the LP is feasible; the
reported slack is then 0.0 when feasible.

A mode without any strict condition (only *n*, and *s* on free fixels) has ``s* = 1``
(the cap) whenever the LP is feasible.

Whether a mode can be realised at all (READING_NOTES, "Closure versus the mode itself")
does not depend on g: the strict conditions involve only xdd, and ``c = 0`` meets every
force rule, so some wrench realises the mode iff some xdd meets its acceleration
conditions. :func:`lp_mode_feasible` decides that with a second small LP: maximise the
slack ``s`` of the strict conditions over ``u`` in the box ``|u_k| <= 1`` (rows of
``J_hat^T`` have length between 1 and ``sqrt(2)`` for contacts within ``L`` of the com,
so ``s`` is again O(1) and dimensionless); feasible iff ``s* > LP_SLACK_TOLERANCE``.

Tolerances (all dimensionless)
------------------------------
``LP_SLACK_TOLERANCE = 1e-7``: the optimum slack must exceed it. HiGHS is run with
primal/dual feasibility tolerances of ``HIGHS_FEASIBILITY_TOLERANCE = 1e-10`` (its
defaults are 1e-7), so an impossible mode, whose exact optimum is ``s* <= 0``, cannot
reach the threshold by solver round-off. Wrenches whose true slack lies within about
the tolerance of 0 (the boundary of the consistent set) are decided either way; callers
comparing against another method should skip a band around the boundary.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from wrenchcone_ros.core.modes import Sign, parse_mode

#: Dimensionless: minimum optimum slack of the strict conditions for "consistent".
LP_SLACK_TOLERANCE: float = 1e-7

#: Dimensionless: HiGHS primal and dual feasibility tolerances used for the LP.
HIGHS_FEASIBILITY_TOLERANCE: float = 1e-10

#: Upper bound of the slack variable (the LP would otherwise be unbounded when a mode
#: has no strict condition).
SLACK_CAP: float = 1.0

__all__ = [
    "HIGHS_FEASIBILITY_TOLERANCE",
    "LP_SLACK_TOLERANCE",
    "SLACK_CAP",
    "LPResult",
    "contact_jacobian",
    "lp_consistent",
    "lp_mode_feasible",
]


@dataclass(frozen=True)
class LPResult:
    """Outcome of :func:`lp_consistent`.

    consistent: the decision.
    slack: optimum slack ``s*`` of the strict conditions (dimensionless, at most
        :data:`SLACK_CAP`); ``-inf`` when the LP is infeasible; 0.0 for a feasible
        closure check.
    status: scipy's ``linprog`` status (0 optimal, 2 infeasible, ...).
    message: solver message.
    """

    consistent: bool
    slack: float
    status: int
    message: str = ""

    def __bool__(self) -> bool:
        return self.consistent


def contact_jacobian(scene) -> np.ndarray:
    """J (3 x 2n), written from the contact frames: columns n_1..n_n, t_1..t_n.

    Dimensional (torque rows in N m per N); about the world centre of mass.
    """
    com = np.asarray(scene.com_world, dtype=float)
    cols_n, cols_t = [], []
    for ct in scene.contacts:
        p = np.asarray(ct.p, dtype=float)
        r = p - com
        for v, cols in ((np.asarray(ct.n, dtype=float), cols_n),
                        (np.asarray(ct.t, dtype=float), cols_t)):
            cols.append([v[0], v[1], r[0] * v[1] - r[1] * v[0]])
    cols = cols_n + cols_t
    if not cols:
        return np.zeros((3, 0))
    return np.array(cols, dtype=float).T


def _nondimensional(scene, g):
    """Return (M_hat diagonal, J_hat, g_hat unit) or g_hat = None when g = 0."""
    L = float(scene.length_scale)
    m = float(scene.workpiece.mass)
    inertia = float(scene.workpiece.inertia)
    J = contact_jacobian(scene)
    J_hat = J.copy()
    J_hat[2, :] /= L
    g = np.asarray(g, dtype=float).reshape(3)
    g_hat = np.array([g[0], g[1], g[2] / L])
    norm = float(np.linalg.norm(g_hat))
    m_hat = np.array([1.0, 1.0, inertia / (m * L * L)])
    return m_hat, J_hat, (g_hat / norm if norm > 0 else g_hat)


def lp_consistent(scene, mode: str, g, closure: bool = False) -> LPResult:
    """Decide with one LP whether wrench ``g = (f_x, f_y, tau)`` is consistent with ``mode``.

    ``closure=False`` (default): the open mode, strict conditions strict (maximised slack
    above :data:`LP_SLACK_TOLERANCE`). ``closure=True``: the closure of the consistent set,
    strict conditions relaxed to non-strict (plain feasibility).

    Raises :class:`~wrenchcone_ros.core.modes.ModeError` for a malformed mode or one the
    contact state does not allow.
    """
    contacts = list(scene.contacts)
    in_contact = [bool(ct.in_contact) for ct in contacts]
    gaps = [float(ct.gap) for ct in contacts]
    tol = getattr(scene, "contact_tolerance", None)
    inters = parse_mode(mode, in_contact, gaps, tol)
    n = len(contacts)

    m_hat, J_hat, g_hat = _nondimensional(scene, g)
    if not np.all(np.isfinite(g_hat)):
        raise ValueError(f"wrench must be finite, got {g!r}")

    # variable layout: u (3), c_n (n), c_t (n), s (1)
    nv = 3 + 2 * n + 1
    iu, icn, ict, isl = 0, 3, 3 + n, 3 + 2 * n

    a_eq, b_eq, a_ub, b_ub = [], [], [], []

    # Newton-Euler: diag(m_hat) u - J_hat c = g_hat
    for k in range(3):
        row = np.zeros(nv)
        row[iu + k] = m_hat[k]
        row[icn:icn + n] = -J_hat[k, :n]
        row[ict:ict + n] = -J_hat[k, n:]
        a_eq.append(row)
        b_eq.append(g_hat[k])

    bounds = [(None, None)] * 3 + [(None, None)] * (2 * n) + [(None, SLACK_CAP)]
    has_strict = False

    def add_sign(coef_u: np.ndarray, sign: Sign) -> None:
        """Constraint ``sign`` on the scalar ``coef_u . u`` (a contact acceleration)."""
        nonlocal has_strict
        if closure:
            sign = sign.closure
        if sign is Sign.FREE:
            return
        row = np.zeros(nv)
        row[iu:iu + 3] = coef_u
        if sign is Sign.ZERO:
            a_eq.append(row)
            b_eq.append(0.0)
            return
        d = sign.direction
        # d * a >= s (strict)  <=>  -d * a + s <= 0 ;  d * a >= 0  <=>  -d * a <= 0
        ub = -d * row
        if sign.strict:
            ub[isl] = 1.0
            has_strict = True
        a_ub.append(ub)
        b_ub.append(0.0)

    for i, inter in enumerate(inters):
        jn = J_hat[:, i]  # a_in (scaled) = jn . u
        jt = J_hat[:, n + i]
        add_sign(jn, inter.a_n(in_contact[i]))
        add_sign(jt, inter.a_t)

        # normal force
        cn_sign = inter.c_n
        if cn_sign is Sign.ZERO:
            bounds[icn + i] = (0.0, 0.0)
        elif cn_sign is Sign.NONNEG:
            bounds[icn + i] = (0.0, None)
        elif cn_sign is Sign.FREE:
            pass
        else:  # pragma: no cover - Table 2 has no other force sign
            raise ValueError(f"unsupported c_n condition {cn_sign!r}")

        # tangential force: c_t in [min(e) mu c_n, max(e) mu c_n] over the allowed edges
        edges = inter.c_t.edges
        mu = float(scene.mu(i))
        if not edges:
            bounds[ict + i] = (0.0, 0.0)
            continue
        hi, lo = max(edges) * mu, min(edges) * mu
        if hi == lo:
            row = np.zeros(nv)
            row[ict + i] = 1.0
            row[icn + i] = -hi
            a_eq.append(row)
            b_eq.append(0.0)
        else:
            row = np.zeros(nv)  # c_t - hi c_n <= 0
            row[ict + i] = 1.0
            row[icn + i] = -hi
            a_ub.append(row)
            b_ub.append(0.0)
            row = np.zeros(nv)  # lo c_n - c_t <= 0
            row[ict + i] = -1.0
            row[icn + i] = lo
            a_ub.append(row)
            b_ub.append(0.0)

    if not has_strict:
        bounds[isl] = (SLACK_CAP, SLACK_CAP)

    cost = np.zeros(nv)
    cost[isl] = -1.0
    res = linprog(
        cost,
        A_ub=np.array(a_ub) if a_ub else None,
        b_ub=np.array(b_ub) if b_ub else None,
        A_eq=np.array(a_eq),
        b_eq=np.array(b_eq),
        bounds=bounds,
        method="highs",
        options={
            "primal_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
            "dual_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
        },
    )
    if res.status == 2:
        return LPResult(False, float("-inf"), 2, res.message)
    if res.status != 0:
        raise RuntimeError(f"LP check failed (status {res.status}): {res.message}")
    slack = float(res.x[isl])
    if closure:
        return LPResult(True, 0.0, 0, res.message)
    return LPResult(slack > LP_SLACK_TOLERANCE, slack, 0, res.message)


def lp_mode_feasible(scene, mode: str) -> LPResult:
    """Decide with one LP whether any wrench realises the open ``mode`` (independent of g).

    Maximises the slack of the strict acceleration conditions over nondimensional
    accelerations ``u`` with ``|u_k| <= 1`` subject to the non-strict ones (module
    docstring). ``slack`` is the optimum, ``SLACK_CAP`` when the mode has no strict
    condition. (The LP itself is always feasible: ``u = 0``, ``s = 0`` meets every
    constraint; an impossible mode shows as ``s* <= 0``.)
    """
    contacts = list(scene.contacts)
    in_contact = [bool(ct.in_contact) for ct in contacts]
    inters = parse_mode(mode, in_contact, [float(ct.gap) for ct in contacts],
                        getattr(scene, "contact_tolerance", None))
    n = len(contacts)
    _, J_hat, _ = _nondimensional(scene, np.zeros(3))
    nv = 4  # u (3), s
    a_eq, b_eq, a_ub, b_ub = [], [], [], []
    has_strict = False
    for i, inter in enumerate(inters):
        for coef, sign in ((J_hat[:, i], inter.a_n(in_contact[i])),
                           (J_hat[:, n + i], inter.a_t)):
            if sign is Sign.FREE:
                continue
            row = np.zeros(nv)
            row[:3] = coef
            if sign is Sign.ZERO:
                a_eq.append(row)
                b_eq.append(0.0)
                continue
            ub = -sign.direction * row
            if sign.strict:
                ub[3] = 1.0
                has_strict = True
            a_ub.append(ub)
            b_ub.append(0.0)
    if not has_strict:
        return LPResult(True, SLACK_CAP, 0, "no strict condition")
    cost = np.array([0.0, 0.0, 0.0, -1.0])
    res = linprog(
        cost,
        A_ub=np.array(a_ub) if a_ub else None,
        b_ub=np.array(b_ub) if b_ub else None,
        A_eq=np.array(a_eq) if a_eq else None,
        b_eq=np.array(b_eq) if b_eq else None,
        bounds=[(-1.0, 1.0)] * 3 + [(None, SLACK_CAP)],
        method="highs",
        options={
            "primal_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
            "dual_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
        },
    )
    if res.status != 0:  # pragma: no cover - u = 0, s = 0 is always feasible
        raise RuntimeError(f"LP feasibility check failed (status {res.status}): {res.message}")
    slack = float(res.x[3])
    return LPResult(slack > LP_SLACK_TOLERANCE, slack, 0, res.message)
