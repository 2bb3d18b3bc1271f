# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An independent LP check: is a wrench consistent with a contact mode?

This module answers the same question as :func:`wrenchcone_ros.core.wrench_cone` without
any of the paper's matrices (no C, E, N, R, S, V, K, P, no cone conversion). It writes
Newton-Euler and Table 2 (:data:`~wrenchcone_ros.core.modes.MODE_TABLE`) directly as
linear programmes and solves them with scipy's HiGHS. It serves two purposes:

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
one slack variable ``-1 <= s <= 1`` that an LP maximises; the non-strict conditions
(``a_in >= 0`` for *s* without contact, ``a_in = 0``, ``c_in >= 0``, the friction law)
are written as they are.

Preconditioning: the acceleration conditions are rows on ``u``. Before solving, the
equalities are replaced by an orthonormal basis of their span and every inequality row
is projected onto the orthogonal complement of that span and scaled to unit length
(``_Builder``). This changes neither the set of accelerations nor the verdict in exact
arithmetic, but it lets a solver with absolute tolerances see exact consequences of
nearly parallel rows (two nearly coincident fixels: ``a_n1 = a_n2 = 0`` forces
``alpha = 0``), and it makes the slacks below angles on the equality subspace, O(1)
for a robustly possible mode whatever the geometry.

Two LPs
-------
1. *Is the mode possible at all?* (:func:`lp_mode_feasible`, independent of g;
   docs/theory.md, "Closure versus the mode itself"). The strict conditions involve only
   xdd, and ``c = 0`` meets every force rule, so some wrench realises the mode iff some
   xdd meets its acceleration conditions with the strict ones strict. The LP maximises
   the slack ``s_f`` of the (preconditioned, unit) strict rows over ``u`` in the box
   ``|u_k| <= 1``. Possible iff ``s_f > LP_FEASIBILITY_TOLERANCE``.
2. *Does g realise it?* (:func:`lp_consistent`). For a possible mode, the LP maximises the
   slack ``s*`` subject to Newton-Euler with the unit ``g_hat``. Because the ``u`` part
   of the feasible set is bounded for a fixed g (a homogeneous solution ``M u = J c``
   with the mode's signs has ``u^T M u = c^T a <= 0``), ``s*`` is finite. It is small
   either because g is near the boundary of the consistent set or because the mode is
   only barely possible. The decision therefore uses the relative slack ``s* / s_f``:
   g is consistent iff ``s_f > LP_FEASIBILITY_TOLERANCE`` and
   ``s* > LP_SLACK_TOLERANCE * s_f``. A mode without any strict condition (only *n*, and
   *s* on free fixels) has ``s_f = s* = 1`` whenever the LP is feasible.

With ``closure=True`` the strict conditions are replaced by their closures (Theorem 1 with
k = 0) and g is consistent iff the LP system is feasible (what a check with non-strict
inequalities would say; the cross-check compares it with the paper's closure cone).

Tolerances (all dimensionless)
------------------------------
* ``HIGHS_FEASIBILITY_TOLERANCE = 1e-10``: HiGHS's primal and dual feasibility
  tolerances (its defaults are 1e-7); presolve off (see ``_HIGHS_OPTIONS``). Slacks are
  accurate to about ``LP_NOISE = 1e-9`` in absolute terms (observed: impossible modes,
  whose exact optimum is ``s_f = 0``, come out below 2e-11).
* ``LP_FEASIBILITY_TOLERANCE = 1e-9``: a mode with ``s_f`` above it is possible.
* ``LP_SLACK_TOLERANCE = 1e-7``: relative slack ``s* / s_f`` above it is consistent; for a
  robustly possible mode (``s_f`` of order 1) that is an angular band of roughly 1e-7
  around the boundary of the cone.

* Rows built from world-frame points are accurate to about
  ``64 eps (1 + |com| / L)`` relative (``_row_accuracy``); singular values of the
  equalities and projected inequality rows below that are zero, and within a factor
  1e3 of it they leave the verdict undetermined (``LPResult.ill_conditioned``).

Near those thresholds the LP's verdict is decided by round-off; a caller comparing it
with another method should skip wrenches with ``|s*| < LP_NOISE`` and modes with ``s_f``
within a band around ``LP_FEASIBILITY_TOLERANCE`` (see :attr:`LPResult.decided`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog

from wrenchcone_ros.core.modes import Sign, parse_mode

#: Dimensionless: HiGHS primal and dual feasibility tolerances used for every LP.
HIGHS_FEASIBILITY_TOLERANCE: float = 1e-10

#: Dimensionless: absolute accuracy of the slacks the LPs return.
LP_NOISE: float = 1e-9

#: Dimensionless: a mode is possible when its acceleration slack s_f exceeds this.
LP_FEASIBILITY_TOLERANCE: float = 1e-9

#: Dimensionless: g is consistent when its slack s* exceeds this times s_f.
LP_SLACK_TOLERANCE: float = 1e-7

#: Bound of the slack variable: s in [-SLACK_CAP, SLACK_CAP].
SLACK_CAP: float = 1.0

__all__ = [
    "HIGHS_FEASIBILITY_TOLERANCE",
    "LP_FEASIBILITY_TOLERANCE",
    "LP_NOISE",
    "LP_SLACK_TOLERANCE",
    "SLACK_CAP",
    "LPResult",
    "contact_jacobian",
    "lp_consistent",
    "lp_mode_feasible",
]

#: HiGHS options. Presolve is off: on nearly coincident fixels (coefficients ~1e-8) it
#: declared feasible LPs infeasible, and for LPs this small it only costs time.
_HIGHS_OPTIONS = {
    "primal_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
    "dual_feasibility_tolerance": HIGHS_FEASIBILITY_TOLERANCE,
    "presolve": False,
}


@dataclass(frozen=True)
class LPResult:
    """Outcome of :func:`lp_consistent` or :func:`lp_mode_feasible`.

    Parameters
    ----------
    consistent : bool
        The decision (for :func:`lp_mode_feasible`: the mode is possible).
    slack : float
        Optimum slack of the strict conditions (dimensionless, in
        ``[-SLACK_CAP, SLACK_CAP]``); ``-inf`` when the LP is infeasible (or, for
        :func:`lp_consistent`, not solved because the mode is impossible); 0.0 for a
        feasible closure check.
    feasibility_slack : float
        ``s_f`` of the mode (:func:`lp_mode_feasible`).
    status : int
        scipy's ``linprog`` status of the last LP solved (0 optimal, 2 infeasible); -1
        when no LP was needed.
    message : str
        Solver message or reason.
    witness : tuple of 3 float or None
        (:func:`lp_mode_feasible` only) an acceleration ``xdd = (a_x, a_y, alpha)`` (SI
        units, arbitrary positive scale) meeting the mode's acceleration conditions,
        strictly; zero when the mode has no strict condition; None when it is
        impossible. Any ``g = M (lambda xdd) - J c`` with ``lambda > 0`` and c obeying
        the mode's force rules is then consistent: a way to construct consistent wrenches
        without a cone.
    ill_conditioned : bool
        The verdict hinges on a quantity within rounding of zero (an acceleration row
        nearly in the span of the equalities, or a nearly dependent set of equalities,
        compared with the accuracy of the rows built from world-frame points): the float
        data do not determine it; :attr:`decided` is then False.
    """

    consistent: bool
    slack: float
    feasibility_slack: float
    status: int
    message: str = ""
    witness: tuple[float, float, float] | None = None
    ill_conditioned: bool = False

    def __bool__(self) -> bool:
        return self.consistent

    @property
    def relative_slack(self) -> float:
        """``slack / feasibility_slack`` (``-inf`` for an impossible mode)."""
        if not self.feasibility_slack > 0:
            return float("-inf")
        return self.slack / self.feasibility_slack

    @property
    def decided(self) -> bool:
        """False when round-off may have decided the verdict (slacks within the noise) or
        when the solvers gave up (status other than optimal or infeasible)."""
        if self.status not in (-1, 0, 2) or self.ill_conditioned:
            return False
        fs = self.feasibility_slack
        if 0.01 * LP_FEASIBILITY_TOLERANCE < fs < 100 * LP_FEASIBILITY_TOLERANCE:
            return False
        if fs > LP_FEASIBILITY_TOLERANCE and abs(self.slack) < LP_NOISE:
            return False
        return True


def contact_jacobian(scene) -> np.ndarray:
    """J (3 x 2n), written from the contact frames: columns n_1..n_n, t_1..t_n.

    Dimensional (torque rows in N m per N); about the world centre of mass.

    Parameters
    ----------
    scene : Scene
        The scene.

    Returns
    -------
    numpy.ndarray
        J, 3 x 2n, SI units.
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
    """Return (M_hat diagonal, J_hat, unit g_hat) (g_hat = 0 stays 0)."""
    L = float(scene.length_scale)
    m = float(scene.workpiece.mass)
    inertia = float(scene.workpiece.inertia)
    J_hat = contact_jacobian(scene)
    J_hat[2, :] /= L
    g = np.asarray(g, dtype=float).reshape(3)
    g_hat = np.array([g[0], g[1], g[2] / L])
    if not np.all(np.isfinite(g_hat)):
        raise ValueError(f"wrench must be finite, got {g.tolist()!r}")
    norm = float(np.linalg.norm(g_hat))
    m_hat = np.array([1.0, 1.0, inertia / (m * L * L)])
    return m_hat, J_hat, (g_hat / norm if norm > 0 else g_hat)


def _interactions(scene, mode):
    contacts = list(scene.contacts)
    in_contact = [bool(ct.in_contact) for ct in contacts]
    gaps = [float(ct.gap) for ct in contacts]
    inters = parse_mode(mode, in_contact, gaps, getattr(scene, "contact_tolerance", None))
    return in_contact, inters


def _solve(cost, a_ub, b_ub, a_eq, b_eq, bounds):
    kw = {
        "A_ub": np.array(a_ub) if a_ub else None,
        "b_ub": np.array(b_ub) if b_ub else None,
        "A_eq": np.array(a_eq) if a_eq else None,
        "b_eq": np.array(b_eq) if b_eq else None,
        "bounds": bounds,
    }
    res = linprog(cost, method="highs", options=_HIGHS_OPTIONS, **kw)
    if res.status in (0, 2):
        return res
    # rare "unknown" model status on badly conditioned data (nearly coincident fixels):
    # retry with presolve, then with the interior-point solver
    for method, presolve in (("highs", True), ("highs-ipm", False), ("highs-ipm", True)):
        res = linprog(cost, method=method, options={**_HIGHS_OPTIONS, "presolve": presolve},
                      **kw)
        if res.status in (0, 2):
            return res
    return res


#: Safety factor on the relative rounding error of the contact rows (see
#: :func:`_row_accuracy`).
_ROUNDING_SAFETY = 64.0

#: A quantity within this factor of its rounding error makes the verdict undecided.
_AMBIGUITY_FACTOR = 1e3


def _row_accuracy(scene) -> float:
    """Relative accuracy of the rows of ``J_hat`` built from world-frame contact points.

    ``r = p - com`` loses about ``eps * |com| / L`` relative to ``L`` (world coordinates
    far from the origin); ``_ROUNDING_SAFETY`` covers the rest of the arithmetic.
    """
    L = float(scene.length_scale)
    far = float(np.max(np.abs(np.asarray(scene.com_world, dtype=float)))) / L
    return _ROUNDING_SAFETY * float(np.finfo(float).eps) * (1.0 + far)


class _Builder:
    """Rows of an LP over variables x = [u (3), extra...], the slack s last.

    The conditions on accelerations are preconditioned before solving, without changing
    the set they describe: the equalities (``a_in = 0``, ``a_it = 0``) are replaced by an
    orthonormal basis of their span (SVD), and every inequality row is projected onto the
    orthogonal complement of that span and scaled to unit length (on the equality
    subspace it takes the same values, up to that positive factor). Nearly coincident
    contacts give nearly parallel rows whose exact consequences (say ``alpha = 0``) a
    solver with an absolute tolerance would not see; the preconditioned rows state them
    with unit coefficients. An inequality row that vanishes on the equality subspace is
    dropped when non-strict and makes the slack ``<= 0`` when strict. Slacks are thus
    measured with unit rows on the equality subspace.
    """

    def __init__(self, nv: int, closure: bool, accuracy: float):
        self.nv, self.closure, self.accuracy = nv, closure, accuracy
        self.ill_conditioned = False
        self.a_eq, self.b_eq, self.a_ub, self.b_ub = [], [], [], []
        self.acc_eq: list[np.ndarray] = []
        self.acc_ineq: list[tuple[np.ndarray, bool]] = []  # (row with d . u >= 0, strict)
        self.has_strict = False

    def sign(self, coef_u: np.ndarray, sign: Sign) -> None:
        """Constraint ``sign`` on the scalar ``coef_u . u`` (a contact acceleration)."""
        if self.closure:
            sign = sign.closure
        if sign is Sign.FREE:
            return
        coef_u = np.asarray(coef_u, dtype=float)
        if sign is Sign.ZERO:
            if np.any(coef_u != 0):
                self.acc_eq.append(coef_u)
            return
        self.acc_ineq.append((sign.direction * coef_u, sign.strict))
        self.has_strict |= sign.strict

    def equality_basis(self) -> tuple[np.ndarray, float]:
        """Orthonormal basis (rows) of the span of the acceleration equalities, and the
        accuracy of projections onto its complement (relative).

        Singular values below ``accuracy`` (relative) are rounding: the rows are dependent.
        Singular values within ``_AMBIGUITY_FACTOR`` of that make the rank, hence the
        verdict, undetermined by the float data: the builder is flagged ill-conditioned.
        """
        if not self.acc_eq:
            return np.zeros((0, 3)), self.accuracy
        rows = np.array(self.acc_eq)
        rows = rows / np.linalg.norm(rows, axis=1, keepdims=True)
        _, sv, vt = np.linalg.svd(rows, full_matrices=False)
        keep = sv > self.accuracy * sv[0]
        rel = sv / sv[0]
        if np.any((rel > self.accuracy) & (rel < _AMBIGUITY_FACTOR * self.accuracy)):
            self.ill_conditioned = True
        cond = float(sv[0] / sv[keep][-1])
        return vt[keep], self.accuracy * cond

    def finish(self, nonstrict_slack: bool = False) -> None:
        """Append the preconditioned acceleration rows (class docstring).

        ``nonstrict_slack``: the slack also enters the non-strict rows (used to find a
        witness acceleration in the relative interior).
        """
        Q, acc = self.equality_basis()
        for q in Q:
            row = np.zeros(self.nv)
            row[:3] = q
            self.a_eq.append(row)
            self.b_eq.append(0.0)
        for r, strict in self.acc_ineq:
            rp = r - Q.T @ (Q @ r) if len(Q) else r
            norm = float(np.linalg.norm(rp))
            rel = norm / float(np.linalg.norm(r))
            if acc < rel < _AMBIGUITY_FACTOR * acc:
                self.ill_conditioned = True  # its sign on the subspace is not determined
            ub = np.zeros(self.nv)  # -r' . u + s <= 0  <=>  r' . u >= s
            if rel <= acc:
                if not strict:
                    continue  # 0 >= 0 on the equality subspace
            else:
                ub[:3] = -rp / norm
            if strict or nonstrict_slack:
                ub[-1] = 1.0
            self.a_ub.append(ub)
            self.b_ub.append(0.0)
        self.acc_eq, self.acc_ineq = [], []


def _acceleration_builder(scene, mode: str) -> _Builder:
    in_contact, inters = _interactions(scene, mode)
    n = len(inters)
    _, J_hat, _ = _nondimensional(scene, np.zeros(3))
    b = _Builder(4, closure=False, accuracy=_row_accuracy(scene))
    for i, inter in enumerate(inters):
        b.sign(J_hat[:, i], inter.a_n(in_contact[i]))
        b.sign(J_hat[:, n + i], inter.a_t)
    return b


def lp_mode_feasible(scene, mode: str, witness: bool = False) -> LPResult:
    """Decide with one LP whether any wrench realises the open ``mode`` (independent of g).

    Maximises the slack ``s_f`` of the strict acceleration conditions over nondimensional
    accelerations ``u`` with ``|u_k| <= 1``, subject to the non-strict ones (module
    docstring). The LP is always feasible (``u = 0``, ``s = 0``); an impossible mode
    shows as ``s_f <= 0`` up to round-off.

    Parameters
    ----------
    scene : Scene
        The workpiece at its pose and the fixels.
    mode : str
        A concrete mode, one letter per fixel.
    witness : bool
        Also return (in ``LPResult.witness``) an acceleration meeting every condition of
        the mode, strictly where possible: a second LP maximises the smallest slack over
        all inequality rows, strict and non-strict (the strict optimum is used when some
        non-strict row cannot be made positive). Without it, the witness is the first
        LP's optimum, which may lie on a non-strict face.

    Returns
    -------
    LPResult
        ``consistent``: the mode is possible; ``feasibility_slack``: ``s_f``.

    Raises
    ------
    ModeError
        A malformed mode or one the contact state does not allow.
    """
    b = _acceleration_builder(scene, mode)
    has_strict = b.has_strict
    box = [(-1.0, 1.0)] * 3 + [(-SLACK_CAP, SLACK_CAP)]
    cost = np.array([0.0, 0.0, 0.0, -1.0])
    if has_strict:
        b.finish()
        res = _solve(cost, b.a_ub, b.b_ub, b.a_eq, b.b_eq, box)
        if res.status != 0:
            return LPResult(False, float("nan"), float("nan"), res.status,
                            f"LP feasibility check failed: {res.message}")
        slack, message = float(res.x[3]), res.message
        u = res.x[:3]
    else:
        slack, message, u = SLACK_CAP, "no strict condition", np.zeros(3)
    feasible = slack > LP_FEASIBILITY_TOLERANCE
    ill = b.ill_conditioned
    if witness and feasible:
        b2 = _acceleration_builder(scene, mode)
        b2.finish(nonstrict_slack=True)
        if b2.a_ub:
            res2 = _solve(cost, b2.a_ub, b2.b_ub, b2.a_eq, b2.b_eq, box)
            if res2.status == 0 and res2.x[3] > LP_FEASIBILITY_TOLERANCE:
                u = res2.x[:3]
    L = float(scene.length_scale)
    wit = (float(u[0]), float(u[1]), float(u[2]) / L) if feasible else None
    return LPResult(feasible, slack, slack, 0 if has_strict else -1, message, wit, ill)


def lp_consistent(scene, mode: str, g, closure: bool = False,
                  feasibility: LPResult | None = None) -> LPResult:
    """Decide with LPs whether wrench ``g = (f_x, f_y, tau)`` is consistent with ``mode``.

    Written from Newton-Euler and Table 2 (Coulomb friction), not from the paper's
    matrices: an independent check of the cones.

    Parameters
    ----------
    scene : Scene
        The workpiece at its pose and the fixels.
    mode : str
        A concrete mode, one letter per fixel.
    g : sequence of 3 float
        (fx N, fy N, tz N m), fixture frame.
    closure : bool
        False (default): the open mode (the mode must be possible,
        ``s_f > LP_FEASIBILITY_TOLERANCE``, and g's slack must exceed
        ``LP_SLACK_TOLERANCE * s_f``). True: strict conditions relaxed to non-strict,
        plain feasibility.
    feasibility : LPResult, optional
        The result of :func:`lp_mode_feasible` for this (scene, mode), to save that LP
        on repeated queries.

    Returns
    -------
    LPResult
        ``consistent``: the decision; ``decided`` False when round-off may have made it.

    Raises
    ------
    ModeError
        A malformed mode or one the contact state does not allow.
    ValueError
        g is not finite.
    """
    in_contact, inters = _interactions(scene, mode)
    n = len(inters)
    m_hat, J_hat, g_hat = _nondimensional(scene, g)

    if closure:
        s_f = float("nan")
    else:
        if feasibility is None:
            feasibility = lp_mode_feasible(scene, mode)
        s_f = feasibility.feasibility_slack
        if feasibility.status not in (-1, 0, 2):
            return LPResult(False, float("nan"), s_f, feasibility.status, feasibility.message)
        if not feasibility.consistent:
            return LPResult(False, float("-inf"), s_f, -1, "the mode is impossible",
                            ill_conditioned=feasibility.ill_conditioned)

    # variables: u (3), c_n (n), c_t (n), s (1)
    nv = 3 + 2 * n + 1
    icn, ict = 3, 3 + n
    b = _Builder(nv, closure, accuracy=_row_accuracy(scene))

    # Newton-Euler: diag(m_hat) u - J_hat c = g_hat
    for k in range(3):
        row = np.zeros(nv)
        row[k] = m_hat[k]
        row[icn:icn + n] = -J_hat[k, :n]
        row[ict:ict + n] = -J_hat[k, n:]
        b.a_eq.append(row)
        b.b_eq.append(g_hat[k])

    bounds = [(None, None)] * (3 + 2 * n) + [(-SLACK_CAP, SLACK_CAP)]
    for i, inter in enumerate(inters):
        b.sign(J_hat[:, i], inter.a_n(in_contact[i]))
        b.sign(J_hat[:, n + i], inter.a_t)

        if inter.c_n is Sign.ZERO:
            bounds[icn + i] = (0.0, 0.0)
        elif inter.c_n is Sign.NONNEG:
            bounds[icn + i] = (0.0, None)
        elif inter.c_n is not Sign.FREE:  # pragma: no cover - Table 2 has no other
            raise ValueError(f"unsupported c_n condition {inter.c_n!r}")

        # tangential force: c_t in [min(e) mu c_n, max(e) mu c_n] over the allowed edges
        edges = inter.c_t.edges
        if not edges:
            bounds[ict + i] = (0.0, 0.0)
            continue
        mu = float(scene.mu(i))
        hi, lo = max(edges) * mu, min(edges) * mu
        row = np.zeros(nv)  # c_t - hi c_n (<= or ==) 0
        row[ict + i] = 1.0
        row[icn + i] = -hi
        if hi == lo:
            b.a_eq.append(row)
            b.b_eq.append(0.0)
            continue
        b.a_ub.append(row)
        b.b_ub.append(0.0)
        row = np.zeros(nv)  # lo c_n - c_t <= 0
        row[ict + i] = -1.0
        row[icn + i] = lo
        b.a_ub.append(row)
        b.b_ub.append(0.0)

    if not b.has_strict:
        bounds[-1] = (SLACK_CAP, SLACK_CAP)
    b.finish()
    ill = b.ill_conditioned or bool(feasibility is not None and feasibility.ill_conditioned)
    cost = np.zeros(nv)
    cost[-1] = -1.0
    res = _solve(cost, b.a_ub, b.b_ub, b.a_eq, b.b_eq, bounds)
    if res.status == 2:
        return LPResult(False, float("-inf"), s_f, 2, res.message, ill_conditioned=ill)
    if res.status != 0:  # the solvers gave up: no verdict (LPResult.decided is False)
        return LPResult(False, float("nan"), s_f, res.status, res.message)
    if closure:
        return LPResult(True, 0.0, s_f, 0, res.message, ill_conditioned=ill)
    slack = float(res.x[-1])
    return LPResult(slack > LP_SLACK_TOLERANCE * s_f, slack, s_f, 0, res.message,
                    ill_conditioned=ill)
