# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Which modes is a wrench consistent with? Wildcard unions and "only this mode".

One wrench is often consistent with several augmented modes (frictional indeterminacy,
the companion paper). This module answers, for a scene:

* :func:`consistent_modes` -- every valid concrete mode g is consistent with, with margins
  (:class:`ModeMatch`), for the nominal model or under an uncertainty (then against every
  mode's robust "all" and "any" sets, :func:`robust_classification_cones` and
  :func:`robust_mode_matches`: the one robust classification);
* :func:`mode_union` -- the wrenches of a wildcard mode ("c": l, r or n; "*": anything
  valid), a union of convex cones (:class:`~.wrenchset.WrenchSet`, made by :mod:`.batch`);
* :func:`only_mode` -- is g consistent with the desired mode and with no other;
* :func:`exclusive_region` -- the wrenches consistent with a mode and no other, as a list
  of convex pieces.

Pruning. The modes are searched depth first, one fixel at a time, fixels in contact
first. At a node, the fixels not yet decided are replaced by the convex relaxation of
all their letters (:func:`~wrenchcone_ros.core.modes.relaxation`), whose wrench set
contains the union of every completion's. If g is not in the relaxed set (closure, a
non-negative least-squares test on 3-D generators), or the decided fixels' strict
conditions are already impossible, the whole subtree is skipped. Free fixels carry no
force, so they never decide *whether* a contact mode is consistent, only its labels a/s;
they come last and are only reached under consistent contact modes. Cones of complete
modes are cached per classifier.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .batch import mode_union, wrench_cone
from .budget import check_time_budget
from .cones import Cone, cone_from_hrep
from .constraints import force_generators, open_mode_feasible
from .dynamics import problem_from
from .engines import get_engine
from .modes import (
    MODE_TABLE,
    ModeError,
    allowed_letters,
    expand_mode,
    is_wildcard,
    parse_mode,
    relaxation,
)
from .planar import acceleration_cone
from .robust import robust_cones
from .scene import Scene
from .tolerances import CONE_TOLERANCE, PRUNE_TOLERANCE
from .uncertainty import Uncertainty, as_uncertainty
from .wrenchset import EXACT_GUARANTEE, Guarantee, WrenchSet


# --- the classification result and the robust matching -----------------------------------
@dataclass(frozen=True)
class ModeMatch:
    """A mode a wrench is consistent with, and how surely.

    Parameters
    ----------
    mode : str
        The concrete mode.
    margin : float
        The wrench's margin in the mode's "any" set (consistent for some model); for the
        nominal model, its margin in the mode's cone (:meth:`.cones.Cone.margin`).
    certain : bool
        Whether the wrench is consistent with the mode for every model (in the "all"
        set); always True for the nominal model.
    margin_all : float or None
        Its margin in the "all" set (the worst case over the models); None: ``margin``
        (the nominal model, where the two sets are one cone).
    guarantee : Guarantee
        What the answer is guaranteed to mean (:class:`~.wrenchset.Guarantee`).
    """

    mode: str
    margin: float
    certain: bool = True
    margin_all: float | None = None
    guarantee: Guarantee = EXACT_GUARANTEE

    def __post_init__(self) -> None:
        if self.margin_all is None:
            object.__setattr__(self, "margin_all", self.margin)

    @property
    def possible(self) -> bool:
        """Consistent for some model: always True for a match."""
        return True

    @property
    def margin_any(self) -> float:
        """The margin in the "any" set (:attr:`margin`)."""
        return self.margin

    def to_dict(self) -> dict:
        """JSON-able form: mode, certain, possible, margins and guarantee.

        Returns
        -------
        dict
            ``mode``, ``certain``, ``possible``, ``margin``, ``margin_all``, ``margin_any``,
            ``guarantee`` (its text).
        """
        return {"mode": self.mode, "certain": self.certain, "possible": True,
                "margin": self.margin, "margin_all": self.margin_all,
                "margin_any": self.margin, "guarantee": str(self.guarantee)}


def robust_classification_cones(scene: Scene, uncertainty: Uncertainty, *,
                                engine: str | None = None, frame: str = "nominal"
                                ) -> tuple[list[WrenchSet], list[WrenchSet]]:
    """The "all" and "any" sets of every valid concrete mode of ``scene`` (the same
    order): what :func:`robust_mode_matches` classifies a wrench with. Computing them is
    the whole cost of a robust classification; keep them to classify many wrenches.

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    uncertainty : Uncertainty
        The model set.
    engine : str or None, optional
        The engine (:func:`.engines.get_engine`).
    frame : str, optional
        Torques about the nominal centre of mass (``"nominal"``) or each model's own
        (``"com"``).

    Returns
    -------
    alls : list of WrenchSet
        The "all" set of every valid concrete mode.
    anys : list of WrenchSet
        The "any" set of every valid concrete mode, in the same order.
    """
    modes = expand_mode("*" * scene.n_fixels, scene.in_contact)
    alls = robust_cones(scene, modes, uncertainty, "all", engine=engine, frame=frame)
    anys = robust_cones(scene, modes, uncertainty, "any", engine=engine, frame=frame)
    return alls, anys


def robust_mode_matches(g: Sequence[float], alls: Sequence[WrenchSet],
                        anys: Sequence[WrenchSet]) -> list[ModeMatch]:
    """Every mode whose "any" set holds ``g`` (possible), flagged ``certain`` when its
    "all" cone holds it too; certain modes first, then by margin in the "any" set.
    ``alls`` and ``anys``: :func:`robust_classification_cones`.

    Parameters
    ----------
    g : sequence of 3 float
        Wrench (f_x N, f_y N, tau N m), fixture frame.
    alls : sequence of WrenchSet
        The "all" sets.
    anys : sequence of WrenchSet
        The "any" sets, in the same order.

    Returns
    -------
    list of ModeMatch
        The matches.

    Raises
    ------
    ValueError
        A wrench that is not finite.
    """
    g = np.asarray(g, dtype=float).reshape(3)
    if not np.all(np.isfinite(g)):
        raise ValueError(f"wrench must be finite, got {g.tolist()}")
    out = []
    for a, y in zip(alls, anys):
        if not y.contains(g):
            continue
        out.append(ModeMatch(a.mode, y.margin(g), a.contains(g), a.margin(g), a.guarantee))
    return sorted(out, key=lambda m: (not m.certain, -m.margin_any, m.mode))


class SearchBudgetError(ValueError):
    """The mode search would visit more nodes than the caller allowed."""


#: Not a tolerance: the batched search skips Cone.check for a complete mode whose facet
#: residual on the unit wrench exceeds CONE_TOLERANCE by more than this (rounding of the
#: two ways of computing the residual differs by ~1e-16; the decision is Cone.check's).
_SCREEN = 1e-12


@lru_cache(maxsize=None)
def _relaxed(in_contact: bool):
    """The relaxation of every letter allowed in this contact state (two possible)."""
    return relaxation(allowed_letters(in_contact), in_contact, "*")


class ModeClassifier:
    """Classifies wrenches over the modes of one scene under one uncertainty; caches
    cones and relaxations.

    Parameters
    ----------
    scene : Scene
        The scene.
    method : str or None, optional
        The cone method (:func:`.batch.wrench_cone`).
    engine : str or None, optional
        The engine (:func:`.engines.get_engine`).
    uncertainty : Uncertainty or None, optional
        The model set (None: :data:`.uncertainty.NOMINAL`, the zero-width uncertainty).
    frame : str, optional
        Torques about the nominal centre of mass or each model's own
        (:func:`.robust.robust_cones`).

    Notes
    -----
    The one place where a classification takes the nominal fast path: for the
    zero-width uncertainty (:meth:`.uncertainty.Uncertainty.is_nominal`) ``pruned`` is
    True and :meth:`consistent_modes` is the pruned search of the module docstring
    (every match certain, bounded by ``max_nodes`` as it goes); otherwise it classifies
    against the "all" and "any" sets of every mode
    (:func:`robust_classification_cones`, computed once per classifier).
    """

    def __init__(self, scene: Scene, method: str | None = None, engine: str | None = None,
                 *, uncertainty: Uncertainty | None = None, frame: str = "nominal") -> None:
        self.scene = scene
        self.method = method
        self.engine = engine
        self.uncertainty = as_uncertainty(uncertainty)
        self.frame = frame
        #: Whether :meth:`consistent_modes` is the pruned search (the zero-width
        #: uncertainty), else the classification against every mode's robust sets.
        self.pruned = self.uncertainty.is_nominal(scene)
        self._robust_sets: tuple[list[WrenchSet], list[WrenchSet]] | None = None
        self._cones: dict[str, Cone] = {}
        self._nodes: dict[str, tuple] = {}
        self._residuals: dict[str, tuple] = {}
        contact = scene.in_contact
        # fixels in contact first (they prune), free fixels last (labels only)
        self.order = sorted(range(scene.n_fixels), key=lambda i: (not contact[i], i))
        self._relaxed = [_relaxed(c) for c in contact]
        self.nodes_visited = 0

    # --- cones of complete modes ------------------------------------------------------
    def cone(self, mode: str) -> Cone:
        """The (cached) cone of one concrete mode.

        Parameters
        ----------
        mode : str
            A concrete mode.

        Returns
        -------
        Cone
            Its cone.

        Raises
        ------
        ModeError
            The mode is not valid for the scene's contacts.
        """
        if mode not in self._cones:
            self._cones[mode] = wrench_cone(self.scene, mode, method=self.method,
                                            engine=self.engine)
        return self._cones[mode]

    def _batched(self) -> bool:
        return self.method in (None, "planar") and get_engine(self.engine).batched

    # --- the batched search (kernel engine): one kernel call per depth ----------------
    def _may_contain_many(self, keys: list[str], u: np.ndarray) -> list[bool]:
        """Whether u may lie in each relaxed node's cone: False only when the node is an
        impossible open mode or u is farther than PRUNE_TOLERANCE from it (some unit
        facet row f has f . u > PRUNE_TOLERANCE, or an equality |e . u| does: the
        distance to the cone is at least that). A node the kernel declined (a degenerate
        relaxation, e.g. every contact normal through one point) is pruned by the
        reference test :meth:`_may_contain`, as the depth-first search does; keeping it
        unpruned made such scenes explode (8 fixels on a disc's rim: the budget of
        20,000 nodes used up where the reference search visits a few dozen).
        Nodes not seen before by this classifier: one kernel call, residuals vectorised."""
        out = dict.fromkeys(keys, True)
        new = [k for k in keys if k not in self._residuals]
        if new:
            got = get_engine(self.engine).relaxed_rows(self.scene, new, self._inters)
            status, feas, counts, rows = got.status, got.feasible, got.counts, got.rows
            width = np.arange(rows.shape[2])
            fu = np.where(width < counts[:, :1], rows[:, 0] @ u, -1.0).max(axis=1)
            eu = np.where(width < counts[:, 1:2], np.abs(rows[:, 1] @ u), -1.0).max(axis=1)
            keep = feas & (np.maximum(fu, eu) <= PRUNE_TOLERANCE)
            for j in np.flatnonzero(status != 0):
                keep[j] = self._may_contain(new[j], u)
            out.update(zip(new, keep.tolist()))
            self._residuals.update((k, (status, feas, counts, rows, j))
                                   for j, k in enumerate(new))
            if len(new) == len(keys):
                return keep.tolist()
        fresh = set(new)
        for k in keys:
            if k in fresh:
                continue
            status, feas, counts, rows, j = self._residuals[k]
            if status[j]:
                out[k] = self._may_contain(k, u)
            elif not feas[j]:
                out[k] = False
            else:
                F, E = rows[j, 0, :counts[j, 0]], rows[j, 1, :counts[j, 1]]
                r = max(float((F @ u).max()) if F.shape[0] else -1.0,
                        float(np.abs(E @ u).max()) if E.shape[0] else -1.0)
                out[k] = r <= PRUNE_TOLERANCE
        return [out[k] for k in keys]

    def _consistent_batched(self, g: np.ndarray, u: np.ndarray,
                            max_nodes: int | None = None) -> list[ModeMatch]:
        """Breadth first: each depth's relaxed nodes in one kernel call, then the
        complete modes' cones in one call (:meth:`.engines.Engine.cones`). ``max_nodes``
        is checked before each depth is computed (:meth:`consistent_modes`)."""
        contact = self.scene.in_contact
        frontier = ["?" * self.scene.n_fixels]
        visited = 0

        def visit(k: int) -> None:
            nonlocal visited
            visited += k
            self.nodes_visited += k
            check_time_budget()
            if max_nodes is not None and visited > max_nodes:
                raise SearchBudgetError(
                    f"the mode search needs more than {max_nodes} node(s) for this scene "
                    f"({self.scene.n_fixels} fixel(s), {sum(contact)} in contact)")

        for i in self.order:
            visit(len(frontier))
            alive = [k for k, ok in zip(frontier, self._may_contain_many(frontier, u)) if ok]
            letters = allowed_letters(contact[i])
            frontier = [k[:i] + ch + k[i + 1:] for k in alive for ch in letters]
            if not frontier:
                return []
        visit(len(frontier))
        todo = [m for m in frontier if m not in self._cones]
        if todo:  # valid by construction
            self._cones.update(zip(todo, get_engine(self.engine).cones(self.scene, todo)))
        found = []
        bound = CONE_TOLERANCE + _SCREEN
        for m in frontier:
            cone = self._cones[m]
            if not cone.feasible:
                continue
            # screen: clearly outside (by far more than rounding) needs no exact check
            F, E = cone.F_hat, cone.E_hat
            if (F.shape[0] and float((F @ u).max()) > bound) or (
                    E.shape[0] and float(np.abs(E @ u).max()) > bound):
                continue
            ok, margin = cone.check(g)
            if ok:
                found.append(ModeMatch(m, margin))
        return found

    # --- the relaxed search -----------------------------------------------------------
    def _inters(self, partial: str) -> tuple:
        """The intersections of a relaxed mode: '?' the relaxation of every letter."""
        return tuple(self._relaxed[i] if ch == "?" else MODE_TABLE[ch]
                     for i, ch in enumerate(partial))

    def _node(self, partial: str):
        """Generators and feasibility of the relaxation where partial has '?' undecided."""
        if partial in self._nodes:
            return self._nodes[partial]
        prob = problem_from(self.scene, partial, self._inters(partial))
        acc, rays, lines = acceleration_cone(prob)
        feasible = open_mode_feasible(acc, rays, lines, False)
        M = prob.M
        lin = np.reshape(lines, (-1, 3)) @ M.T
        A = np.vstack([np.reshape(rays, (-1, 3)) @ M.T, force_generators(prob), lin, -lin]).T
        if A.shape[1]:
            A = A / np.linalg.norm(A, axis=0)
        self._nodes[partial] = out = (feasible, A)
        return out

    def _may_contain(self, partial: str, u: np.ndarray) -> bool:
        feasible, A = self._node(partial)
        if not feasible:
            return False
        if A.shape[1] == 0:
            return float(np.linalg.norm(u)) <= PRUNE_TOLERANCE
        from scipy.optimize import nnls  # lazy: scipy.optimize takes 0.6 s to import

        return nnls(A, u)[1] <= PRUNE_TOLERANCE

    def robust_sets(self) -> tuple[list[WrenchSet], list[WrenchSet]]:
        """The "all" and "any" sets of every valid concrete mode under the classifier's
        uncertainty (:func:`robust_classification_cones`), computed once.

        Returns
        -------
        alls, anys : list of WrenchSet
            The "all" and the "any" set of every mode, in the same order.
        """
        if self._robust_sets is None:
            self._robust_sets = robust_classification_cones(
                self.scene, self.uncertainty, engine=self.engine, frame=self.frame)
        return self._robust_sets

    @property
    def guarantee(self) -> Guarantee:
        """What the matches are guaranteed to mean: exact for the pruned search, else the
        guarantee of the robust sets (computed if they are not yet).

        Returns
        -------
        Guarantee
        """
        if self.pruned:
            return EXACT_GUARANTEE
        alls = self.robust_sets()[0]
        return alls[0].guarantee if alls else EXACT_GUARANTEE

    def consistent_modes(self, g: Sequence[float], max_nodes: int | None = None
                         ) -> list[ModeMatch]:
        """Every valid concrete mode g is consistent with for some model (``margin`` in its
        "any" set), ``certain`` when for every model; certain first, then by margin, best
        first (for the zero-width uncertainty every match is certain).

        ``max_nodes`` bounds the work of the pruned search: it raises
        :class:`SearchBudgetError` after visiting that many nodes of the mode tree (None:
        no bound; the search is iterative, no recursion limit on the number of fixels).
        The robust classification computes every mode's sets (check its size first).

        Parameters
        ----------
        g : sequence of 3 float
            Wrench (f_x N, f_y N, tau N m about the centre of mass, fixture frame).
        max_nodes : int or None, optional
            The most nodes of the mode tree to visit.

        Returns
        -------
        list of ModeMatch
            The matches, certain ones first, then best margin first.

        Raises
        ------
        SearchBudgetError
            The search needs more than ``max_nodes`` nodes.
        ValueError
            A wrench that is not finite.
        """
        if not self.pruned:
            return robust_mode_matches(g, *self.robust_sets())
        g = np.asarray(g, dtype=float).reshape(3)
        if not np.all(np.isfinite(g)):
            raise ValueError(f"wrench must be finite, got {list(g)}")
        L = self.scene.length_scale
        gh = g * np.array([1.0, 1.0, 1.0 / L])
        norm = float(np.linalg.norm(gh))
        u = gh / norm if norm > 0 else gh
        if self._batched():
            return sorted(self._consistent_batched(g, u, max_nodes), key=lambda m: (-m.margin, m.mode))
        contact = self.scene.in_contact
        found: list[ModeMatch] = []
        visited = 0
        stack = [(0, "?" * self.scene.n_fixels)]  # (depth, partial mode), depth first
        while stack:
            depth, key = stack.pop()
            visited += 1
            self.nodes_visited += 1
            check_time_budget()
            if max_nodes is not None and visited > max_nodes:
                raise SearchBudgetError(
                    f"the mode search needs more than {max_nodes} node(s) for this scene "
                    f"({self.scene.n_fixels} fixel(s), {sum(contact)} in contact)")
            if not self._may_contain(key, u):
                continue
            if depth == len(self.order):
                cone = self.cone(key)
                if cone.contains(g):
                    found.append(ModeMatch(key, cone.margin(g)))
                continue
            i = self.order[depth]
            for ch in reversed(allowed_letters(contact[i])):
                stack.append((depth + 1, key[:i] + ch + key[i + 1:]))
        return sorted(found, key=lambda m: (-m.margin, m.mode))


def consistent_modes(scene: Scene, g: Sequence[float], method: str | None = None,
                     engine: str | None = None, *, uncertainty: Uncertainty | None = None,
                     frame: str = "nominal") -> list[ModeMatch]:
    """Every valid augmented mode of ``scene`` that wrench ``g`` may produce.

    A fixel in contact may be s, l, r or n; a free fixel a or s. Impossible modes never
    match.

    Parameters
    ----------
    scene : Scene
        The workpiece, fixels, friction and pose.
    g : sequence of 3 float
        Wrench (f_x N, f_y N, tau N m about the centre of mass, fixture frame).
    method, engine
        The cone method and engine (:func:`.batch.wrench_cone`).
    uncertainty : Uncertainty or None
        The model set; None: the nominal model (the zero-width uncertainty).
    frame : str
        Torques about the nominal centre of mass or each model's own
        (:func:`.robust.robust_cones`).

    Returns
    -------
    list of ModeMatch
        Every mode g is consistent with for some model (``margin``: in its "any" set),
        ``certain`` when it is for every model (``margin_all``: in its "all" set);
        certain modes first, then by margin, best first. For the zero-width uncertainty
        every match is certain with one margin, found by the pruned search (module
        docstring; with the kernel engine breadth first, one batched call per depth,
        ``engine="numpy"`` the reference depth-first search).

    Raises
    ------
    ValueError
        For a wrench that is not finite.
    """
    return ModeClassifier(scene, method, engine, uncertainty=uncertainty,
                          frame=frame).consistent_modes(g)


# --- only this mode -------------------------------------------------------------------
@dataclass(frozen=True)
class OnlyModeAnswer:
    """The answer of :func:`only_mode`.

    Parameters
    ----------
    mode : str
        The desired mode.
    consistent : bool
        Whether g is consistent with it.
    only : bool
        Whether g is consistent with it and with no other mode.
    others : tuple of ModeMatch
        The other modes g is consistent with.
    """

    mode: str
    consistent: bool  # with the desired mode
    only: bool  # consistent with it and with no other mode
    others: tuple[ModeMatch, ...]  # the other modes g is consistent with


def only_mode(scene: Scene, mode: str, g: Sequence[float], method: str | None = None,
              classifier: ModeClassifier | None = None) -> OnlyModeAnswer:
    """Whether g is consistent with ``mode`` and with no other valid mode of the scene.

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The desired concrete mode.
    g : sequence of 3 float
        Wrench (f_x N, f_y N, tau N m about the centre of mass, fixture frame).
    method : str or None, optional
        The cone method (:func:`.batch.wrench_cone`).
    classifier : ModeClassifier or None, optional
        A classifier of the scene whose cached cones are reused.

    Returns
    -------
    OnlyModeAnswer
        The answer.

    Raises
    ------
    ModeError
        The mode is not valid for the scene's contacts.
    ValueError
        A wrench that is not finite.
    """
    parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)
    clf = classifier or ModeClassifier(scene, method)
    matches = clf.consistent_modes(g)
    mine = any(m.mode == mode for m in matches)
    others = tuple(m for m in matches if m.mode != mode)
    return OnlyModeAnswer(mode, mine, mine and not others, others)


def _subtract(piece: tuple[list, list], other: Cone) -> list[tuple[list, list]]:
    """Closures of the convex parts of piece minus a full-dimensional cone ``other``.

    piece \\ {F_o g <= 0} = union_j piece & {f_j g >= 0} & {f_i g <= 0, i < j}: disjoint
    up to boundaries (nondimensional rows).
    """
    F, E = piece
    out, earlier = [], []
    for f in other.F_hat.tolist():
        out.append((F + earlier + [[-x for x in f]], E))
        earlier.append(f)
    return out


def exclusive_region(scene: Scene, mode: str, method: str | None = None) -> list[Cone]:
    """The wrenches consistent with ``mode`` and with no other mode, as convex pieces.

    Each piece is the closure of a convex part of cone(mode) minus the union of every
    other feasible mode's cone (in the nondimensional metric). Limits: the pieces are
    closed, so their shared boundaries and the boundary with the other modes are
    included; other modes whose cones have an empty interior remove only a set of
    measure zero and are not subtracted; pieces with an empty interior are dropped.
    An empty list means no wrench is consistent only with ``mode`` (up to measure zero).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        A concrete mode.
    method : str or None, optional
        The cone method (:func:`.batch.wrench_cone`).

    Returns
    -------
    list of Cone
        The pieces (method ``exclusive``); empty when there is none.

    Raises
    ------
    ModeError
        The mode is not valid for the scene's contacts.
    """
    parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)
    clf = ModeClassifier(scene, method)
    base = clf.cone(mode)
    if not base.full_dimensional:
        return []
    pieces = [(base.F_hat.tolist(), [])]
    L = scene.length_scale
    kw = {"mode": mode, "length_scale": L, "method": "exclusive", "exact": False}
    for other in _all_modes(scene):
        if other == mode:
            continue
        oc = clf.cone(other)
        if not oc.full_dimensional:
            continue
        nxt = []
        for p in pieces:
            for q in _subtract(p, oc):
                c = cone_from_hrep(q[0], q[1], **kw)
                if c.full_dimensional:
                    nxt.append((c.F_hat.tolist(), []))
        pieces = nxt
        if not pieces:
            return []
    return [cone_from_hrep(F, E, **kw) for F, E in pieces]


def _all_modes(scene: Scene) -> list[str]:
    return expand_mode("*" * scene.n_fixels, scene.in_contact)


__all__ = ["ModeMatch", "ModeClassifier", "SearchBudgetError", "consistent_modes", "mode_union",
           "robust_classification_cones", "robust_mode_matches",
           "is_wildcard", "OnlyModeAnswer", "only_mode", "exclusive_region", "PRUNE_TOLERANCE",
           "ModeError"]
