# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Robust cones: the wrenches consistent with a mode for every model, or for some model.

For an :class:`~.uncertainty.Uncertainty` (a set of models around the scene) and a
concrete mode (docs/theory.md, "Uncertain models", has the proofs):

* ``robust_cone(scene, mode, U, "all")``: the wrenches consistent with the mode for
  *every* model of the set;
* ``robust_cone(scene, mode, U, "any")``: for *some* model (the modes a wrench might
  produce).

Friction intervals, exactly. With W(mu) = M X + (-J) C(mu) (:mod:`.planar`), X does not
depend on mu, and C(mu) is the product of the fixels' force cones: rolling
pos{n +- mu t}, sliding left the ray n - mu t, sliding right n + mu t, none for a/s.

* "any" = M X + (-J) prod_i U_i with U_i the union of fixel i's force cones over its
  interval: pos{n +- mu_hi t} when rolling, pos{n -+ mu_lo t, n -+ mu_hi t} when sliding.
  It is the cone of the scene with mu_hi at every fixel plus a copy of every uncertain
  sliding fixel with mu_lo (:func:`_any_block`).
* "all" = the intersection of the cones at the vertices of the box of the uncertain
  *sliding* fixels, rolling fixels at mu_lo (2^k cones for k uncertain l/r fixels).

Both are computed in float (the compiled engine, every vertex in one kernel call) or in
exact arithmetic (cddlib GMP). The open mode's feasibility does not depend on mu.

Other parameters (mass, inertia, centre of mass, contact-normal errors), by the scenario
approach: N = :meth:`~.uncertainty.Uncertainty.scenario_size` models are sampled; "all"
is the intersection of their (friction-exact) "all" cones, "any" the union of their
"any" cones. The answer carries ``guarantee`` = scenario(epsilon, beta, N): a wrench
chosen independently of the draw that lies in the "all" cone fails, with confidence
1 - beta, for at most a fraction epsilon of the models; one outside the "any" union is
consistent, with the same confidence, for at most a fraction epsilon. Every wrench in the
"any" union is consistent for some model (an inner approximation).

Frames. Wrenches are (f_x, f_y, tau) in the fixture frame with tau about the *nominal*
centre of mass (``frame="nominal"``), or about each model's own centre of mass
(``frame="com"``: a load through the centre of mass, such as a tilted tray's gravity,
has tau = 0 in every model). Without centre-of-mass uncertainty the two are the same.
Cones are stored in the nominal scene's nondimensional metric (its length scale).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from .batch import wrench_cones
from .budget import check_time_budget
from .cones import (
    Cone,
    as_float,
    cone_from_hrep,
    infeasible_cone,
)
from .dynamics import Problem, float_rows, problem
from .engines import SLIDING, Engine, get_engine, pose_arrays
from .modes import ModeError, is_wildcard, parse_mode
from .planar import planar_cone
from .geometry import Fixel
from .scene import Scene
from .tolerances import CONE3_FACET_TOLERANCE
from .uncertainty import NOMINAL, Model, Uncertainty, at_scene_friction
from .wrenchset import EXACT_GUARANTEE, Guarantee, WrenchSet, union_over

QUANTIFIERS = ("all", "any")
FRAMES = ("nominal", "com")


# --- the models' data ----------------------------------------------------------------------
@dataclass(frozen=True)
class _Data:
    """One model's nondimensional rows (J_hat^T: n normal rows, then n tangential),
    kappa = I / (m L^2) and the world offset d of its com from the nominal com (m)."""

    A: np.ndarray
    kappa: object
    offset: tuple[float, float]


def model_rows(scene: Scene, model: Model | None) -> _Data:
    """J_hat^T and kappa of one model, in the nominal length scale L: the com moved by
    d (world frame) changes each moment arm by -d x v; a normal turned by e turns its
    tangent with it (both rows mixed by the rotation); kappa = I / (m L^2).

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    model : Model or None
        The model (None: the nominal one).

    Returns
    -------
    _Data
        The rows A (2n x 3), kappa and the com's displacement (dx, dy) in m, world frame.
    """
    A, kappa, _ = float_rows(scene) if model is not None else pose_arrays(scene)
    if model is None:
        return _Data(A, kappa, (0.0, 0.0))
    L = scene.length_scale
    th = scene.pose[2]
    c0 = scene.workpiece.com
    wx, wy = model.com[0] - c0[0], model.com[1] - c0[1]
    dx, dy = math.cos(th) * wx - math.sin(th) * wy, math.sin(th) * wx + math.cos(th) * wy
    A = A.copy()
    if dx or dy:
        A[:, 2] -= (dx * A[:, 1] - dy * A[:, 0]) / L
    e = np.asarray(model.normal_error, dtype=float)
    if e.any():
        n = e.shape[0]
        c, s = np.cos(e)[:, None], np.sin(e)[:, None]
        An, At = A[:n].copy(), A[n:].copy()
        A[:n], A[n:] = c * An + s * At, -s * An + c * At
    return _Data(A, model.inertia / (model.mass * L * L), (dx, dy))


# --- blocks: one cone each (a vertex of the friction box, or the "any" cone) --------------
@dataclass(frozen=True)
class _Block:
    """A cone to compute: rows A (2k x 3), friction mu (k,), the mode's letters for the
    k fixels (the scene's fixels, then copies) and their contact state."""

    A: np.ndarray
    mu: tuple
    mode: str
    in_contact: tuple[bool, ...]
    fixels: tuple[int, ...]  # the scene's fixel each of the k fixels copies


def _vertex_mus(mode: str, intervals: Sequence[tuple]) -> list[tuple]:
    """mu at every vertex of the box of the uncertain sliding fixels (rolling and the
    rest at mu_lo): the "all" cone is the intersection of these cones."""
    choices = [(lo, hi) if ch in SLIDING and lo < hi else (lo,)
               for ch, (lo, hi) in zip(mode, intervals)]
    return list(itertools.product(*choices))


def _all_blocks(A, mode: str, in_contact, intervals) -> list[_Block]:
    idx = tuple(range(len(mode)))
    return [_Block(A, mu, mode, in_contact, idx) for mu in _vertex_mus(mode, intervals)]


def _any_block(A, mode: str, in_contact, intervals) -> _Block:
    """mu_hi everywhere plus a copy of each uncertain sliding fixel with mu_lo (its
    rows repeated: the same acceleration conditions, a second force generator)."""
    n = len(mode)
    dup = [i for i, (ch, (lo, hi)) in enumerate(zip(mode, intervals))
           if ch in SLIDING and lo < hi]
    idx = list(range(n)) + dup
    if dup:
        A = np.concatenate([A[idx], A[[n + i for i in idx]]])
    mu = tuple(hi for _, hi in intervals) + tuple(intervals[i][0] for i in dup)
    return _Block(A, mu, mode + "".join(mode[i] for i in dup),
                  tuple(in_contact) + tuple(in_contact[i] for i in dup), tuple(idx))


def block_scene(base: Scene, block: _Block) -> Scene:
    """The scene of a block of the nominal geometry: the fixels it copies (coinciding
    copies are independent contacts), each with the block's mu."""
    fixels = tuple(Fixel(base.fixels[i].position, base.fixels[i].radius, mu)
                   for i, mu in zip(block.fixels, block.mu))
    return replace(base, fixels=fixels, modes=())


def _reference(block: _Block, kappa, L: float, exact: bool, mode: str,
               base: Scene | None) -> Cone:
    """:func:`.planar.planar_cone` of a block (numpy reference, or exact). A block of the
    nominal geometry (``base``) goes through its own scene, as :func:`.batch.wrench_cone`
    does (exact: the scene's numbers as written; float: its exact recomputation of
    ill-conditioned modes); a sampled model's block through its rows."""
    if base is not None:
        return _renamed(planar_cone(problem(block_scene(base, block), block.mode, exact)),
                        mode)
    inters = parse_mode(block.mode, block.in_contact)
    M = np.diag([1.0, 1.0, float(kappa)])
    J = np.array(block.A, dtype=float).T.copy()
    prob = Problem(block.mode, inters, block.in_contact, J, M, tuple(block.mu), L, False)
    return _renamed(planar_cone(prob), mode)


def _renamed(cone: Cone, mode: str) -> Cone:
    closure = _renamed(cone.closure, mode) if cone.closure is not None else None
    return replace(cone, mode=mode, closure=closure)


def block_cones(blocks: Sequence[_Block], kappa, L: float, mode: str, exact: bool = False,
                engine: str | Engine | None = None, base: Scene | None = None) -> list[Cone]:
    """The cone of every block: blocks of one geometry and mode, differing in friction
    (the vertices of a friction box, or one "any" block).

    Float: the engine's vertex batch (:meth:`.engines.Engine.vertex_cones`; a block it
    does not compute by the reference); exact: the reference, block by block.

    Parameters
    ----------
    blocks : sequence of _Block
        Blocks of one geometry and mode.
    kappa : float or Fraction
        I / (m L^2).
    L : float
        The nominal length scale (m).
    mode : str
        The concrete mode.
    exact : bool, optional
        Exact rational arithmetic.
    engine : str, Engine or None, optional
        The engine of the float batch.
    base : Scene or None, optional
        The nominal scene, for an exact recomputation.

    Returns
    -------
    list of Cone
        One per block.

    Raises
    ------
    ValueError
        For blocks of different geometries or modes.
    """
    first = blocks[0]
    if not all(b.A is first.A and b.mode == first.mode for b in blocks):
        raise ValueError("block_cones takes blocks of one geometry and mode")

    def reference(j: int) -> Cone:
        return _reference(blocks[j], kappa, L, exact, mode, base)

    if exact:
        return [reference(j) for j in range(len(blocks))]
    return get_engine(engine).vertex_cones(first.A, float(kappa), L, first.mode,
                                           first.in_contact, [b.mu for b in blocks],
                                           reference)


# --- intersections and frames -----------------------------------------------------------
def _shift(offset: tuple[float, float], L: float) -> np.ndarray | None:
    """Tn (nondimensional): g_hat about a model's com = Tn g_hat about the nominal com
    (tau_c = tau_0 - d x f); None for d = 0."""
    dx, dy = offset
    if not (dx or dy):
        return None
    return np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [dy / L, -dx / L, 1.0]])


def _to_nominal(cone: Cone, T: np.ndarray | None, mode: str, L: float) -> Cone:
    """The cone {g_0 : T g_0 in cone} (rows F T, E T), canonical again."""
    if T is None or not cone.feasible:
        return cone
    return cone_from_hrep(cone.F_hat @ T, cone.E_hat @ T, mode=mode, length_scale=L,
                          method="planar", exact=False)


def _unique_rows(R: np.ndarray) -> np.ndarray:
    """R without repeated rows (equal to 12 decimals; unit rows), in lexicographic order."""
    if R.shape[0] < 2:
        return R
    Q = np.round(R, 12)
    order = np.lexsort(Q.T[::-1])
    Q = Q[order]
    keep = np.ones(Q.shape[0], dtype=bool)
    keep[1:] = (Q[1:] != Q[:-1]).any(axis=1)
    return R[order[keep]]


def intersection(cones: Sequence[Cone], mode: str, L: float, exact: bool,
                 transforms: Sequence[np.ndarray | None] | None = None,
                 engine: str | Engine | None = None) -> Cone:
    """The intersection of cones given by their facets and equalities (rows stacked, one
    conversion), each first moved to the nominal frame by its transform. Infeasible
    when any cone is (the closure is then the intersection of the closures).

    Parameters
    ----------
    cones : sequence of Cone
        The cones (at least one).
    mode : str
        The mode of the result.
    L : float
        The nominal length scale (m).
    exact : bool
        Exact rational arithmetic.
    transforms : sequence of numpy.ndarray or None, optional
        Per cone, the 3 x 3 map of its rows to the nominal frame (None: none).
    engine : str, Engine or None, optional
        The engine of the float conversion.

    Returns
    -------
    Cone
        The intersection.
    """
    transforms = transforms or [None] * len(cones)
    if not all(c.feasible for c in cones):
        closures = [c if c.feasible else c.closure for c in cones]
        return infeasible_cone(intersection(closures, mode, L, exact, transforms, engine))
    if len(cones) == 1 and transforms[0] is None:
        return cones[0]
    if exact:
        F = [list(r) for c in cones for r in c.exact_rep.F]
        E = [list(r) for c in cones for r in c.exact_rep.E]
        return cone_from_hrep(F, E, mode=mode, length_scale=L, method="planar", exact=True)
    Fs, Es = [], []
    for c, T in zip(cones, transforms):
        Fs.append(c.F_hat if T is None else c.F_hat @ T)
        Es.append(c.E_hat if T is None else c.E_hat @ T)
    return intersect_rows(np.vstack(Fs), np.vstack(Es), mode, L, engine)


def intersect_rows(F: np.ndarray, E: np.ndarray, mode: str, L: float,
                   engine: str | Engine | None = None) -> Cone:
    """The float cone {F g <= 0, E g = 0} of many (possibly repeated or redundant) rows."""
    eng = get_engine(engine)
    F, E = _unique_rows(F), _unique_rows(E)
    if F.shape[0] + E.shape[0] > _CUT:
        cone = _cutting_rows(F, E, mode, L, eng)
        if cone is not None:
            return cone
    while F.shape[0] > _CHUNK:  # drop redundant rows chunk by chunk (the work grows
        # faster than linearly with the rows of one conversion)
        parts = [eng.hrep_cone(F[k:k + _CHUNK], E, mode, L) for k in range(0, F.shape[0], _CHUNK)]
        if any(not p.feasible or p.E_hat.shape[0] for p in parts):
            break  # an empty interior: one conversion of everything decides it
        F = _unique_rows(np.vstack([p.F_hat for p in parts]))
        if len(parts) == 1:
            return parts[0]
    return eng.hrep_cone(F, E, mode, L)


def _unit(rows: np.ndarray) -> np.ndarray:
    return rows / np.linalg.norm(rows, axis=1, keepdims=True) if rows.shape[0] else rows


def _depth(rows: np.ndarray, cone: Cone, two_sided: bool) -> np.ndarray:
    """How far each unit row cuts into the cone pos(R) + span(L): the largest f . r over
    its unit rays (|f . r| for an equality row) and |f . l| over its unit lines; the row
    holds on the whole cone when this is <= 0 (the cone is its generators' hull)."""
    d = np.full(rows.shape[0], -np.inf)
    if cone.G_hat.shape[0]:
        x = rows @ _unit(cone.G_hat).T
        d = np.maximum(d, (np.abs(x) if two_sided else x).max(axis=1))
    if cone.L_hat.shape[0]:
        d = np.maximum(d, np.abs(rows @ _unit(cone.L_hat).T).max(axis=1))
    return d


def _cutting_rows(F: np.ndarray, E: np.ndarray, mode: str, L: float,
                  eng: Engine) -> Cone | None:
    """{F g <= 0, E g = 0} for many rows, adding only the rows that cut the current
    cone: start from the first :data:`_CUT` rows of each; a row that holds, within
    CONE3_FACET_TOLERANCE, at every unit generator of the current cone (:func:`_depth`)
    holds on all of it, and so on the final cone, which lies inside; the deepest cuts
    are added first, up to :data:`_CUT` rows per conversion (a conversion's work grows
    with the cube of its rows). None (then the chunked path) if a conversion fails to
    give a cone."""
    F, E = _unit(F), _unit(E)
    cone = eng.hrep_cone(F[:_CUT], E[:_CUT], mode, L)
    rest_f, rest_e = F[_CUT:], E[_CUT:]
    while True:
        if not cone.feasible:
            return None
        parts = []
        for rows, two_sided in ((rest_f, False), (rest_e, True)):
            depth = _depth(rows, cone, two_sided)
            cut = depth > CONE3_FACET_TOLERANCE
            rows, depth = rows[cut], depth[cut]
            order = np.argsort(-depth, kind="stable")
            room = max(_CUT - cone.F_hat.shape[0] - cone.E_hat.shape[0], 1)
            parts.append((rows[order[:room]], rows[order[room:]]))
        (take_f, rest_f), (take_e, rest_e) = parts
        if not (take_f.shape[0] or take_e.shape[0]):
            return cone
        cone = eng.hrep_cone(np.vstack([cone.F_hat, take_f]), np.vstack([cone.E_hat, take_e]),
                          mode, L)


#: Rows per conversion when many cones are intersected (:func:`intersection`).
_CHUNK = 48
#: Rows per conversion when the rows are added as cuts (:func:`_cutting_rows`).
_CUT = 16


# --- the public entry points --------------------------------------------------------------
class RobustWildcardError(ModeError):
    """A mode with wildcards asked for under an uncertainty of nonzero width: "for every
    model, some mode of the wildcard" is not the union of the modes' robust cones."""


def _check_mode(scene: Scene, mode: str) -> None:
    if isinstance(mode, str) and is_wildcard(mode):
        raise RobustWildcardError(
            f"mode {mode!r}: robust cones take concrete modes (no wildcards c, *): 'for "
            "every model' of a union is not the union of the modes' robust cones")
    parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)


def _nominal_sets(scene: Scene, modes: list[str], quantifier: str, exact: bool,
                  engine: str | Engine | None, frame: str,
                  nominal: Callable[[str], Cone] | None, errors: str,
                  method: str | None = None) -> list:
    """The sets of the zero-width uncertainty: the nominal cones (a wildcard mode: the
    union of its concrete modes' cones, :func:`.wrenchset.union_over`), exact guarantee.
    Float: ``nominal(mode)`` (a classifier's cache) when given, else the engine's batch
    (:func:`.batch.wrench_cones`, which validates the modes as :func:`robust_cone` does);
    exact: :func:`.batch.wrench_cones` in rational arithmetic."""
    if nominal is None or exact or method is not None:
        got = wrench_cones(scene, modes, exact=exact, method=method, engine=engine,
                           errors=errors)
    else:
        got = []
        for m in modes:
            try:
                got.append(union_over(scene, m, nominal) if is_wildcard(m) else nominal(m))
            except ModeError as exc:
                if errors == "raise":
                    raise
                got.append(exc)
    return [WrenchSet(m, (c,), EXACT_GUARANTEE, (), quantifier, frame) if isinstance(c, Cone)
            else replace(c, quantifier=quantifier, frame=frame) if isinstance(c, WrenchSet)
            else c for m, c in zip(modes, got)]


def _models(scene: Scene, uncertainty: Uncertainty, exact: bool, nonlinear: bool):
    """The models to compute (None: the nominal geometry, friction exact) and the
    guarantee they carry (``nonlinear``: :meth:`.uncertainty.Uncertainty.nonlinear`)."""
    if not nonlinear:
        return [None], EXACT_GUARANTEE
    if exact:
        raise ValueError("exact=True is available for friction intervals only; mass, "
                         "inertia, com and normal uncertainty use the float scenario "
                         "approach")
    n = uncertainty.scenario_size()
    return (uncertainty.sample(scene, n),
            Guarantee("scenario", uncertainty.epsilon, uncertainty.beta, n))


def robust_cones(scene: Scene, modes: Sequence[str], uncertainty: Uncertainty,
                 quantifier: str = "all", *, exact: bool = False,
                 engine: str | Engine | None = None, frame: str = "nominal",
                 nominal: Callable[[str], Cone] | None = None, errors: str = "raise",
                 method: str | None = None) -> list:
    """:func:`robust_cone` of every mode in ``modes`` (one pass over the models).

    The one place where a set of wrenches takes the nominal fast path: the zero-width
    uncertainty (:meth:`.uncertainty.Uncertainty.is_nominal`: the nominal model alone,
    e.g. :data:`.uncertainty.NOMINAL`) gives the nominal cones, both quantifiers, exact
    guarantee: in float by ``nominal(mode)`` when given (a classifier's cache of
    concrete modes' cones), else by the engine's nominal batch
    (:func:`.batch.wrench_cones`); exact by :func:`.batch.wrench_cones` in rational
    arithmetic. A mode with wildcards is allowed for it only (the union of its concrete
    modes' cones); under a wider uncertainty it raises :class:`RobustWildcardError`.

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    modes : sequence of str
        Concrete modes (wildcards only for the zero-width uncertainty).
    uncertainty : Uncertainty
        The model set.
    quantifier : str, optional
        "all" or "any" (:func:`robust_cone`).
    exact : bool, optional
        Rational arithmetic (friction intervals only).
    engine : str, Engine or None, optional
        The float engine (:func:`.engines.get_engine`).
    frame : str, optional
        Wrenches about the nominal com ("nominal") or about each model's own com ("com").
    nominal : callable or None, optional
        mode -> its nominal cone (a classifier's cache), used for the zero-width
        uncertainty in float; None: the engine's batch.
    errors : str, optional
        "raise" (the first invalid mode's ModeError, in the order of ``modes``) or
        "return" (the exception object in that mode's place, the others computed).
    method : str or None, optional
        The cone method of the zero-width uncertainty's cones (:data:`.batch.METHODS`;
        None: the default). A wider uncertainty is computed by the planar method only
        (ValueError for another).

    Returns
    -------
    list of WrenchSet
        One per mode, in order (:func:`robust_cone`); with ``errors="return"`` an invalid
        mode's exception in its place.

    Raises
    ------
    ModeError
        The first mode the contact state does not allow (``errors="raise"``);
        :class:`RobustWildcardError` for a wildcard mode under a nonzero width.
    ValueError
        For a bad quantifier, frame or ``errors``, ``exact`` with a non-friction
        uncertainty, or a method other than planar under an uncertainty of nonzero width.
    TypeError
        ``uncertainty`` is not an Uncertainty.
    """
    if errors not in ("raise", "return"):
        raise ValueError(f"errors must be 'raise' or 'return', got {errors!r}")
    if quantifier not in QUANTIFIERS:
        raise ValueError(f"quantifier must be one of {QUANTIFIERS}, got {quantifier!r}")
    if frame not in FRAMES:
        raise ValueError(f"frame must be one of {FRAMES}, got {frame!r}")
    if not isinstance(uncertainty, Uncertainty):
        raise TypeError(f"uncertainty must be an Uncertainty, got {type(uncertainty).__name__}")
    modes = list(modes)
    if uncertainty is NOMINAL:  # the nominal fast path (docstring)
        return _nominal_sets(scene, modes, quantifier, exact, engine, frame, nominal, errors,
                             method)
    eng = get_engine(engine)
    intervals = uncertainty.friction_intervals(scene)
    nonlinear = uncertainty.nonlinear(scene)
    if not nonlinear and at_scene_friction(scene, intervals):  # is_nominal, from the
        # intervals at hand: another zero-width uncertainty
        return _nominal_sets(scene, modes, quantifier, exact, eng, frame, nominal, errors,
                             method)
    if method not in (None, "planar"):
        raise ValueError(f"method {method!r}: the robust sets of an uncertainty of nonzero "
                         "width are computed by the planar method only (method planar, "
                         "or no method)")
    if errors == "raise":
        for m in modes:
            _check_mode(scene, m)
        return _model_sets(scene, modes, uncertainty, intervals, nonlinear, quantifier,
                           exact, eng, frame)
    refused: dict[int, ModeError] = {}
    for k, m in enumerate(modes):
        try:
            _check_mode(scene, m)
        except ModeError as exc:
            refused[k] = exc
    valid = [m for k, m in enumerate(modes) if k not in refused]
    got = iter(_model_sets(scene, valid, uncertainty, intervals, nonlinear, quantifier,
                           exact, eng, frame) if valid else [])
    return [refused[k] if k in refused else next(got) for k in range(len(modes))]


def _model_sets(scene: Scene, modes: list[str], uncertainty: Uncertainty,
                intervals: list[tuple], nonlinear: bool, quantifier: str, exact: bool,
                eng: Engine, frame: str) -> list[WrenchSet]:
    """The robust sets of valid concrete ``modes`` under an uncertainty of nonzero width
    (module docstring: friction exactly, other parameters by sampled models);
    ``intervals`` and ``nonlinear``: the uncertainty's, for ``scene``."""
    models, guarantee = _models(scene, uncertainty, exact, nonlinear)
    L = float(scene.length_scale)
    contact = scene.in_contact
    cones: dict[str, list] = {m: [] for m in modes}
    for model in models:
        check_time_budget()  # a caller's time limit (the node's max_request_time)
        data = model_rows(scene, model)
        base = scene if model is None else None
        T = _shift(data.offset, L) if frame == "nominal" else None
        fast_any = (eng.any_cones(data.A, data.kappa, L, modes, contact, intervals)
                    if quantifier == "any" and not exact else [None] * len(modes))
        for m, got in zip(modes, fast_any):
            if quantifier == "all":
                mus = _vertex_mus(m, intervals)
                fast = (None if exact or len(mus) == 1
                        else eng.vertex_intersection(data.A, data.kappa, L, m, contact, mus))
                if fast is None:  # one model's vertices intersected at once (memory:
                    # one cone per model and mode)
                    blocks = _all_blocks(data.A, m, contact, intervals)
                    fast = intersection(block_cones(blocks, data.kappa, L, m, exact, eng,
                                                    base), m, L, exact, engine=eng)
                # moved to the nominal frame with the other models' cones below:
                # {g : T g in every vertex cone} = {g : T g in their intersection}
                cones[m].append((fast, T))
            else:
                if got is None:
                    block = _any_block(data.A, m, contact, intervals)
                    got = block_cones([block], data.kappa, L, m, exact, eng, base)[0]
                cones[m].append((got, T))
    out = []
    for m in modes:
        if quantifier == "all":
            cone = intersection([c for c, _ in cones[m]], m, L, exact,
                                [T for _, T in cones[m]], eng)
            pieces: tuple = (cone,)
        else:
            got = [_to_nominal(c, T, m, L) for c, T in cones[m]]
            feasible = [c for c in got if c.feasible]
            pieces = tuple(feasible) if guarantee.kind == "scenario" else (got[0],)
        out.append(WrenchSet(m, pieces, guarantee, quantifier=quantifier, frame=frame))
    return out


def robust_cone(scene: Scene, mode: str, uncertainty: Uncertainty, quantifier: str = "all",
                *, exact: bool = False, engine: str | Engine | None = None,
                frame: str = "nominal", method: str | None = None) -> WrenchSet:
    """The wrenches consistent with ``mode`` for every model of ``uncertainty``
    (``quantifier="all"``) or for some model (``"any"``); module docstring.

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    mode : str
        A concrete mode (wildcards only for the zero-width uncertainty).
    uncertainty : Uncertainty
        The model set; :data:`.uncertainty.NOMINAL` (zero width) gives the nominal cone.
    quantifier : str
        "all" (every model: the intersection of the models' cones) or "any" (some model:
        their union; friction intervals exactly, eq. "any" of the module docstring).
    exact : bool
        Rational arithmetic (friction intervals only).
    engine : str, Engine or None
        The float engine (:func:`.engines.get_engine`).
    frame : str
        Wrenches about the nominal com ("nominal") or about each model's own com ("com").
    method : str or None
        The cone method for the zero-width uncertainty (:func:`robust_cones`).

    Returns
    -------
    WrenchSet
        Its ``cone`` the convex cone (one piece, except "any" under the scenario
        approach); ``guarantee`` exact for friction intervals, else scenario(eps, beta, N).

    Raises
    ------
    ModeError
        For a mode the contact state does not allow; :class:`RobustWildcardError` for a
        wildcard mode under an uncertainty of nonzero width.
    ValueError
        For a bad quantifier, frame or method, or ``exact`` with a non-friction
        uncertainty.
    TypeError
        When ``uncertainty`` is not an Uncertainty.
    """
    return robust_cones(scene, [mode], uncertainty, quantifier, exact=exact, engine=engine,
                        frame=frame, method=method)[0]


def as_float_robust(rc: WrenchSet) -> WrenchSet:
    """An exact robust cone's floats.

    Parameters
    ----------
    rc : WrenchSet
        A set computed in exact arithmetic.

    Returns
    -------
    WrenchSet
        Its pieces as floats (:func:`.cones.as_float`).
    """
    return replace(rc, pieces=tuple(as_float(c) for c in rc.pieces))


__all__ = ["QUANTIFIERS", "FRAMES", "RobustWildcardError", "robust_cone", "robust_cones",
           "model_rows", "block_cones", "intersection", "as_float_robust"]
