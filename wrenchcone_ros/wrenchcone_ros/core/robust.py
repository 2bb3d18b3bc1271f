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
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from .batch import plan_code, pose_arrays
from .budget import check_time_budget
from .engines import kernel_module, resolve_engine
from .cones import (
    Cone,
    as_float,
    assembled_cone,
    cone_from_hrep,
    infeasible_cone,
    infeasible_float_cone,
)
from .dynamics import Problem, float_rows, problem
from .modes import WILDCARDS, ModeError, expand_mode, parse_mode
from .planar import planar_cone
from .scene import Fixel, Scene
from .tolerances import CONE3_FACET_TOLERANCE, CONE_TOLERANCE
from .uncertainty import Model, Uncertainty

QUANTIFIERS = ("all", "any")
FRAMES = ("nominal", "com")
SLIDING = "lr"


@dataclass(frozen=True)
class Guarantee:
    """What a robust answer is guaranteed to mean: ``kind`` "exact" (over the whole set)
    or "scenario" (``models`` sampled models, violation probability ``epsilon`` with
    confidence 1 - ``beta``, module docstring)."""

    kind: str
    epsilon: float | None = None
    beta: float | None = None
    models: int | None = None

    def __str__(self) -> str:
        if self.kind == "exact":
            return "exact"
        return f"scenario(eps={self.epsilon:g}, beta={self.beta:g}, N={self.models})"

    def to_dict(self) -> dict:
        return {"kind": self.kind, "epsilon": self.epsilon, "beta": self.beta,
                "models": self.models, "text": str(self)}


EXACT_GUARANTEE = Guarantee("exact")


@dataclass(frozen=True)
class RobustCone:
    """The "all" or "any" set of a mode: ``pieces`` (one convex cone, except "any" under
    the scenario approach: the union of the sampled models' cones). Membership and
    margins as :class:`~.classify.ConeUnion` (a single piece: exactly its Cone's)."""

    mode: str
    quantifier: str
    pieces: tuple[Cone, ...]
    guarantee: Guarantee
    frame: str = "nominal"

    @property
    def feasible(self) -> bool:
        return any(c.feasible for c in self.pieces)

    @property
    def cone(self) -> Cone:
        """The single convex cone (friction only, or any "all" set)."""
        if len(self.pieces) != 1:
            raise ValueError(f"the {self.quantifier!r} set of {self.mode!r} is a union of "
                             f"{len(self.pieces)} cones (scenario approach); use .pieces")
        return self.pieces[0]

    def contains(self, g: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        return any(c.contains(g, tol) for c in self.pieces)

    def margin(self, g: Sequence[float]) -> float:
        return max((c.margin(g) for c in self.pieces), default=-1.0)

    def check(self, g: Sequence[float]) -> tuple[bool, float]:
        return self.contains(g), self.margin(g)

    def contains_many(self, G) -> np.ndarray:
        G = np.asarray(G, dtype=float).reshape(-1, 3)
        out = np.zeros(G.shape[0], dtype=bool)
        for c in self.pieces:
            out |= c.contains_many(G)
        return out

    def margin_many(self, G) -> np.ndarray:
        G = np.asarray(G, dtype=float).reshape(-1, 3)
        out = np.full(G.shape[0], -1.0)
        for c in self.pieces:
            out = np.maximum(out, c.margin_many(G))
        return out

    def to_dict(self) -> dict:
        d = {"mode": self.mode, "quantifier": self.quantifier, "frame": self.frame,
             "guarantee": self.guarantee.to_dict(), "feasible": self.feasible}
        if len(self.pieces) == 1:
            d["cone"] = self.pieces[0].to_dict()
        else:
            d["pieces"] = [c.to_dict() for c in self.pieces]
        return d


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
    tangent with it (both rows mixed by the rotation); kappa = I / (m L^2)."""
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
    nominal geometry (``base``) goes through its own scene, as :func:`.api.wrench_cone`
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


def _code(b: _Block) -> np.ndarray:
    code = plan_code(b.mode, b.in_contact)
    if code is None:
        code = plan_code(b.mode, b.in_contact, parse_mode(b.mode, b.in_contact))
    return code


_VERTEX_CODES: dict[tuple, tuple] = {}


def _vertex_stack(A: np.ndarray, mode: str, in_contact: tuple, count: int):
    """Rows, plan pointers and codes of ``count`` copies of one block stacked into one
    problem for kernel.planar_batch (the same rows and mode, friction
    differing): the copies' codes are the block's shifted by offsets (cached per mode,
    contact state and count)."""
    k = len(mode)
    key = (mode, in_contact, count)
    got = _VERTEX_CODES.get(key)
    if got is None:
        code = _code(_Block(A, (), mode, in_contact, ()))
        total = k * count
        ki, ke, kf = int(code[0]), int(code[1]), int(code[2])
        slot = np.zeros(code.shape[0], dtype=np.int64)  # 1: a row index, 2: a fixel index
        slot[3:3 + ki] = 1
        slot[3 + 3 * ki:3 + 3 * ki + ke] = 1
        slot[3 + 3 * ki + ke:3 + 3 * ki + ke + kf] = 2
        tangential = (slot == 1) & (code >= k)
        offs = np.arange(count, dtype=np.int64)[:, None] * k
        codes = (code[None, :] + offs * (slot > 0) + (total - k) * tangential).reshape(-1)
        got = (np.arange(count + 1, dtype=np.int64) * code.shape[0], codes)
        if len(_VERTEX_CODES) > 4096:
            _VERTEX_CODES.clear()
        _VERTEX_CODES[key] = got
    rows = np.concatenate([np.tile(A[:k], (count, 1)), np.tile(A[k:], (count, 1))])
    return rows, got[0], got[1]


def _vertex_rows(A: np.ndarray, mus: list[tuple], kappa, L: float, mode: str,
                 in_contact: tuple, engine: str | None) -> Cone | None:
    """The intersection of the cones at the friction vertices ``mus``, in one compiled
    call (:func:`.kernel.planar_all`: the acceleration cone once, every vertex's facets,
    one conversion of their stack); None (then :func:`block_cones` and
    :func:`intersection`) without the kernel, or when it declined the mode."""
    if resolve_engine(engine) != "kernel":
        return None
    code = _code(_Block(A, (), mode, in_contact, ()))
    status, feasible, F, E, R, Lk = kernel_module().planar_all(
        A, float(kappa), np.array(mus, dtype=float), code)
    if status:
        return None
    cone = assembled_cone(mode, True, F, E, R, Lk, L, "planar")
    # an impossible mode (for every mu: X does not depend on it): the intersection of
    # the vertices' closures is the closure, as in :func:`intersection`
    return cone if feasible else infeasible_float_cone(cone)


def block_cones(blocks: Sequence[_Block], kappa, L: float, mode: str, exact: bool = False,
                engine: str | None = None, base: Scene | None = None) -> list[Cone]:
    """The cone of every block: blocks of one geometry and mode, differing in friction
    (the vertices of a friction box, or one "any" block). Float with the kernel engine:
    the blocks' rows stacked into one problem and one kernel call (a block the kernel
    declines is computed by the reference); else the reference, block by block."""
    first = blocks[0]
    if not all(b.A is first.A and b.mode == first.mode for b in blocks):
        raise ValueError("block_cones takes blocks of one geometry and mode")
    if exact or resolve_engine(engine) != "kernel":
        return [_reference(b, kappa, L, exact, mode, base) for b in blocks]
    mu = np.array([m for b in blocks for m in b.mu], dtype=float)
    A, ptr, code = _vertex_stack(first.A, first.mode, first.in_contact, len(blocks))
    status, feas, counts, rows = kernel_module().planar_batch(A, float(kappa), mu, ptr, code)
    return [_reference(b, kappa, L, False, mode, base) if status[j]
            else _kernel_cone(rows[j], counts[j], bool(feas[j]), mode, L)
            for j, b in enumerate(blocks)]


def _kernel_cone(r: np.ndarray, counts: np.ndarray, feasible: bool, mode: str,
                 L: float) -> Cone:
    """One cone of a kernel.planar_batch output (its rows and counts), copied out (a view
    would keep the whole batch's rows alive)."""
    nf, ne, nr, nl = counts.tolist()
    cone = assembled_cone(mode, True, r[0, :nf].copy(), r[1, :ne].copy(), r[2, :nr].copy(),
                          r[3, :nl].copy(), L, "planar")
    return cone if feasible else infeasible_float_cone(cone)


_ANY_CODES: dict[tuple, np.ndarray] = {}


def _any_code(mode: str, in_contact: tuple, dup: tuple[bool, ...]) -> np.ndarray:
    """A mode's plan code moved to the "any" layout of 2n fixels (fixel n + i is a copy
    of fixel i, at mu_lo): rows of fixel i stay its rows (normal i, tangential 2n + i),
    and each uncertain sliding fixel (``dup``) gains a loaded copy with its edge sign (the
    copy's acceleration rows are the original's, so they add no constraint;
    :func:`_any_block` writes them out)."""
    key = (mode, in_contact, dup)
    got = _ANY_CODES.get(key)
    if got is not None:
        return got
    n = len(mode)
    code = _code(_Block(None, (), mode, in_contact, ()))
    ki, ke, kf = int(code[0]), int(code[1]), int(code[2])
    a = 3 + 3 * ki + ke
    head = code[3:a].copy()
    for lo, hi in ((0, ki), (3 * ki, 3 * ki + ke)):
        r = head[lo:hi]
        head[lo:hi] = np.where(r < n, r, n + r)  # tangential n + i -> 2n + i
    f_idx, f_sgn = code[a:a + kf], code[a + kf:a + 2 * kf]
    copy = [dup[i] for i in f_idx]
    got = np.concatenate([[ki, ke, kf + sum(copy)], head, f_idx, n + f_idx[copy], f_sgn,
                          f_sgn[copy]]).astype(np.int64)
    if len(_ANY_CODES) > 4096:
        _ANY_CODES.clear()
    _ANY_CODES[key] = got
    return got


def _any_cones(A: np.ndarray, kappa, L: float, modes: Sequence[str], in_contact: tuple,
               intervals) -> list[Cone | None]:
    """The "any" cones of many modes of one model in one kernel call (the layout of
    :func:`_any_code`: every fixel at mu_hi, its copy at mu_lo); None for a mode the
    kernel declines (then :func:`_any_block`)."""
    n = len(in_contact)
    A2 = np.concatenate([A[:n], A[:n], A[n:], A[n:]])
    mu = np.array([hi for _, hi in intervals] + [lo for lo, _ in intervals], dtype=float)
    codes = [_any_code(m, in_contact, tuple(ch in SLIDING and lo < hi
                                             for ch, (lo, hi) in zip(m, intervals)))
             for m in modes]
    ptr = np.zeros(len(codes) + 1, dtype=np.int64)
    np.cumsum([c.shape[0] for c in codes], out=ptr[1:])
    status, feas, counts, rows = kernel_module().planar_batch(A2, float(kappa), mu, ptr,
                                                              np.concatenate(codes))
    return [None if status[j] else _kernel_cone(rows[j], counts[j], bool(feas[j]), m, L)
            for j, m in enumerate(modes)]


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
                 transforms: Sequence[np.ndarray | None] | None = None) -> Cone:
    """The intersection of cones given by their facets and equalities (rows stacked, one
    conversion), each first moved to the nominal frame by its transform. Infeasible
    when any cone is (the closure is then the intersection of the closures)."""
    transforms = transforms or [None] * len(cones)
    if not all(c.feasible for c in cones):
        closures = [c if c.feasible else c.closure for c in cones]
        return infeasible_cone(intersection(closures, mode, L, exact, transforms))
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
    return intersect_rows(np.vstack(Fs), np.vstack(Es), mode, L)


def intersect_rows(F: np.ndarray, E: np.ndarray, mode: str, L: float) -> Cone:
    """The float cone {F g <= 0, E g = 0} of many (possibly repeated or redundant) rows."""
    F, E = _unique_rows(F), _unique_rows(E)
    if F.shape[0] + E.shape[0] > _CUT:
        cone = _cutting_rows(F, E, mode, L)
        if cone is not None:
            return cone
    while F.shape[0] > _CHUNK:  # drop redundant rows chunk by chunk (the work grows
        # faster than linearly with the rows of one conversion)
        parts = [_hrep_cone(F[k:k + _CHUNK], E, mode, L) for k in range(0, F.shape[0], _CHUNK)]
        if any(not p.feasible or p.E_hat.shape[0] for p in parts):
            break  # an empty interior: one conversion of everything decides it
        F = _unique_rows(np.vstack([p.F_hat for p in parts]))
        if len(parts) == 1:
            return parts[0]
    return _hrep_cone(F, E, mode, L)


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


def _cutting_rows(F: np.ndarray, E: np.ndarray, mode: str, L: float) -> Cone | None:
    """{F g <= 0, E g = 0} for many rows, adding only the rows that cut the current
    cone: start from the first :data:`_CUT` rows of each; a row that holds, within
    CONE3_FACET_TOLERANCE, at every unit generator of the current cone (:func:`_depth`)
    holds on all of it, and so on the final cone, which lies inside; the deepest cuts
    are added first, up to :data:`_CUT` rows per conversion (a conversion's work grows
    with the cube of its rows). None (then the chunked path) if a conversion fails to
    give a cone."""
    F, E = _unit(F), _unit(E)
    cone = _hrep_cone(F[:_CUT], E[:_CUT], mode, L)
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
        cone = _hrep_cone(np.vstack([cone.F_hat, take_f]), np.vstack([cone.E_hat, take_e]),
                          mode, L)


def _sorted(rows: np.ndarray) -> np.ndarray:
    """Rows in the order of cones.from_cone3 (descending lexicographic on 12 decimals),
    vectorised."""
    if rows.shape[0] < 2:
        return rows
    keys = -np.round(rows, 12)
    return rows[np.lexsort(keys.T[::-1])]


#: Rows per conversion when many cones are intersected (:func:`intersection`).
_CHUNK = 48
#: Rows per conversion when the rows are added as cuts (:func:`_cutting_rows`).
_CUT = 16


def _hrep_cone(F: np.ndarray, E: np.ndarray, mode: str, L: float) -> Cone:
    """The float cone {F g <= 0, E g = 0}: the compiled conversion when available, else
    cone3d (each with its exact fallback)."""
    km = kernel_module() if resolve_engine() == "kernel" else None
    if km is not None:
        try:
            Fk, Ek, R, Lk = km.from_inequalities(-np.ascontiguousarray(F),
                                                 np.ascontiguousarray(E))
            return assembled_cone(mode, True, _sorted(Fk + 0.0), Ek + 0.0, _sorted(R + 0.0),
                                  Lk + 0.0, float(L), "planar")
        except Exception:  # the kernel's failed self-check: cone3d, then exact cddlib
            pass
    return cone_from_hrep(F, E, mode=mode, length_scale=L, method="planar", exact=False)


# --- the public entry points --------------------------------------------------------------
def _check_mode(scene: Scene, mode: str) -> None:
    if isinstance(mode, str) and any(ch in WILDCARDS for ch in mode):
        raise ModeError(f"mode {mode!r}: robust cones take concrete modes (no wildcards "
                        "c, *): 'for every model' of a union is not the union of the "
                        "modes' robust cones")
    parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)


def _models(scene: Scene, uncertainty: Uncertainty, exact: bool):
    """The models to compute (None: the nominal geometry, friction exact) and the
    guarantee they carry."""
    if not uncertainty.nonlinear(scene):
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
                 engine: str | None = None, frame: str = "nominal") -> list[RobustCone]:
    """:func:`robust_cone` of every mode in ``modes`` (one pass over the models)."""
    if quantifier not in QUANTIFIERS:
        raise ValueError(f"quantifier must be one of {QUANTIFIERS}, got {quantifier!r}")
    if frame not in FRAMES:
        raise ValueError(f"frame must be one of {FRAMES}, got {frame!r}")
    if not isinstance(uncertainty, Uncertainty):
        raise TypeError(f"uncertainty must be an Uncertainty, got {type(uncertainty).__name__}")
    modes = list(modes)
    for m in modes:
        _check_mode(scene, m)
    intervals = uncertainty.friction_intervals(scene)
    models, guarantee = _models(scene, uncertainty, exact)
    L = float(scene.length_scale)
    contact = scene.in_contact
    cones: dict[str, list] = {m: [] for m in modes}
    for model in models:
        check_time_budget()  # a caller's time limit (the node's max_request_time)
        data = model_rows(scene, model)
        base = scene if model is None else None
        T = _shift(data.offset, L) if frame == "nominal" else None
        fast_any = (_any_cones(data.A, data.kappa, L, modes, contact, intervals)
                    if quantifier == "any" and not exact and resolve_engine(engine) == "kernel"
                    else [None] * len(modes))
        for m, got in zip(modes, fast_any):
            if quantifier == "all":
                mus = _vertex_mus(m, intervals)
                fast = (None if exact or len(mus) == 1
                        else _vertex_rows(data.A, mus, data.kappa, L, m, contact, engine))
                if fast is None:  # one model's vertices intersected at once (memory:
                    # one cone per model and mode)
                    blocks = _all_blocks(data.A, m, contact, intervals)
                    fast = intersection(block_cones(blocks, data.kappa, L, m, exact, engine,
                                                    base), m, L, exact)
                # moved to the nominal frame with the other models' cones below:
                # {g : T g in every vertex cone} = {g : T g in their intersection}
                cones[m].append((fast, T))
            else:
                if got is None:
                    block = _any_block(data.A, m, contact, intervals)
                    got = block_cones([block], data.kappa, L, m, exact, engine, base)[0]
                cones[m].append((got, T))
    out = []
    for m in modes:
        if quantifier == "all":
            cone = intersection([c for c, _ in cones[m]], m, L, exact, [T for _, T in cones[m]])
            pieces: tuple = (cone,)
        else:
            got = [_to_nominal(c, T, m, L) for c, T in cones[m]]
            feasible = [c for c in got if c.feasible]
            pieces = tuple(feasible) if guarantee.kind == "scenario" else (got[0],)
        out.append(RobustCone(m, quantifier, pieces, guarantee, frame))
    return out


def robust_cone(scene: Scene, mode: str, uncertainty: Uncertainty, quantifier: str = "all",
                *, exact: bool = False, engine: str | None = None,
                frame: str = "nominal") -> RobustCone:
    """The wrenches consistent with ``mode`` for every model of ``uncertainty``
    (``quantifier="all"``) or for some model (``"any"``); module docstring.

    Returns a :class:`RobustCone` (its ``cone`` the convex cone, ``guarantee`` "exact" for
    friction intervals, else scenario(eps, beta, N)). ``exact=True``: rational arithmetic
    (friction intervals only). ``frame``: wrenches about the nominal com ("nominal") or
    about each model's own com ("com"). Raises ModeError for a wildcard mode or one the
    contact state does not allow, ValueError for a bad quantifier or frame.
    """
    return robust_cones(scene, [mode], uncertainty, quantifier, exact=exact, engine=engine,
                        frame=frame)[0]


# --- robust classification ------------------------------------------------------------------
@dataclass(frozen=True)
class RobustModeMatch:
    """A mode a wrench may produce: ``certain`` (consistent for every model: in the
    "all" cone) or only ``possible`` (for some model: in the "any" set), with the
    wrench's margins in both and the guarantee of the answer."""

    mode: str
    certain: bool
    possible: bool
    margin_all: float
    margin_any: float
    guarantee: Guarantee

    def to_dict(self) -> dict:
        return {"mode": self.mode, "certain": self.certain, "possible": self.possible,
                "margin_all": self.margin_all, "margin_any": self.margin_any,
                "guarantee": str(self.guarantee)}


def robust_classification_cones(scene: Scene, uncertainty: Uncertainty, *,
                                engine: str | None = None, frame: str = "nominal"
                                ) -> tuple[list[RobustCone], list[RobustCone]]:
    """The "all" and "any" sets of every valid concrete mode of ``scene`` (the same
    order): what :func:`robust_mode_matches` classifies a wrench with. Computing them is
    the whole cost of a robust classification; keep them to classify many wrenches."""
    modes = expand_mode("*" * scene.n_fixels, scene.in_contact)
    alls = robust_cones(scene, modes, uncertainty, "all", engine=engine, frame=frame)
    anys = robust_cones(scene, modes, uncertainty, "any", engine=engine, frame=frame)
    return alls, anys


def robust_mode_matches(g: Sequence[float], alls: Sequence[RobustCone],
                        anys: Sequence[RobustCone]) -> list[RobustModeMatch]:
    """Every mode whose "any" set holds ``g`` (possible), flagged ``certain`` when its
    "all" cone holds it too; certain modes first, then by margin in the "any" set.
    ``alls`` and ``anys``: :func:`robust_classification_cones`."""
    g = np.asarray(g, dtype=float).reshape(3)
    if not np.all(np.isfinite(g)):
        raise ValueError(f"wrench must be finite, got {g.tolist()}")
    out = []
    for a, y in zip(alls, anys):
        if not y.contains(g):
            continue
        out.append(RobustModeMatch(a.mode, a.contains(g), True, a.margin(g), y.margin(g),
                                   a.guarantee))
    return sorted(out, key=lambda m: (not m.certain, -m.margin_any, m.mode))


def robust_consistent_modes(scene: Scene, g: Sequence[float], uncertainty: Uncertainty,
                            *, engine: str | None = None, frame: str = "nominal"
                            ) -> list[RobustModeMatch]:
    """Every concrete mode ``g`` is consistent with for some model (possible), flagged
    ``certain`` when it is for every model; certain modes first, then by margin."""
    g = np.asarray(g, dtype=float).reshape(3)
    if not np.all(np.isfinite(g)):
        raise ValueError(f"wrench must be finite, got {g.tolist()}")
    alls, anys = robust_classification_cones(scene, uncertainty, engine=engine, frame=frame)
    return robust_mode_matches(g, alls, anys)


def as_float_robust(rc: RobustCone) -> RobustCone:
    """An exact robust cone's floats."""
    return replace(rc, pieces=tuple(as_float(c) for c in rc.pieces))


__all__ = ["QUANTIFIERS", "FRAMES", "Guarantee", "RobustCone", "RobustModeMatch",
           "robust_cone", "robust_cones", "robust_consistent_modes", "robust_classification_cones",
           "robust_mode_matches", "model_rows",
           "block_cones", "intersection", "as_float_robust", "robust_direction_cones"]


# --- what force directions need (called by directions.force_directions) -----------------
def robust_direction_cones(scene: Scene, mode: str, uncertainty: Uncertainty, point,
                           exclusive: bool, exact: bool) -> tuple[list[Cone], list[Cone],
                                                                  Guarantee]:
    """The cones a robust force-direction question is answered from: ``pieces`` = the
    mode's "all" cone (when feasible), ``others`` (``exclusive``) = the "any" pieces of
    every other valid mode, and the guarantee. A force at the com (``point`` None) acts
    at each model's own com (``frame="com"``), a force at a point of the workpiece is a
    wrench about the nominal com (``frame="nominal"``). Its margin in the "all" cone is
    the worst case over the models (docs/theory.md)."""
    frame = "com" if point is None else "nominal"
    mine = robust_cone(scene, mode, uncertainty, "all", exact=exact, frame=frame)
    pieces = [mine.cone] if mine.feasible else []
    others: list[Cone] = []
    if exclusive:
        rest = [m for m in expand_mode("*" * scene.n_fixels, scene.in_contact) if m != mode]
        for rc in robust_cones(scene, rest, uncertainty, "any", exact=exact, frame=frame):
            others += [c for c in rc.pieces if c.feasible]
    return pieces, others, mine.guarantee
