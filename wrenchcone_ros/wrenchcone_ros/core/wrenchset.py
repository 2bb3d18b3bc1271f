# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A set of wrenches: :class:`WrenchSet`, a finite union of convex cones, and the
:class:`Guarantee` that says what its membership means.

Every answer of the core that is a set of wrenches is one type:

* a concrete mode's cone (:func:`.batch.wrench_cone`): ``WrenchSet.of(cone)``, one piece;
* a mode with wildcards ("c": l, r or n; "*": any valid letter, :data:`.modes.WILDCARDS`):
  the union of its concrete modes' cones (:func:`union_over`), the infeasible ones
  listed in ``impossible``;
* a robust "all" / "any" set (:func:`.robust.robust_cone`): one convex cone, or under the
  scenario approach the union of the sampled models' "any" cones, with its guarantee.

Membership and margin of a union U = C_1 u ... u C_k (unit nondimensional direction u of
g, :meth:`.cones.Cone.margin`): g in U iff g in some C_i; margin(g) = max_i margin_i(g).
Outside every piece this is exactly minus the distance of u to U; inside, a lower bound on
the distance to U's boundary (pieces may touch, and U need not be convex). No piece:
nothing is contained, margin -1.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .budget import check_time_budget
from .cones import Cone, margins_at
from .modes import expand_mode
from .scene import Scene
from .tolerances import CONE_TOLERANCE

#: The guarantee kinds: "exact" (the set is the true set, up to the float tolerances of
#: docs/numerics.md) and "scenario" (sampled models, :class:`Guarantee`).
GUARANTEE_KINDS = ("exact", "scenario")


@dataclass(frozen=True)
class Guarantee:
    """What membership in a set of wrenches is guaranteed to mean.

    Parameters
    ----------
    kind : str
        ``"exact"``: the set is exact over the whole model set (the nominal model, or
        friction intervals). ``"scenario"``: it was computed from ``models`` independently
        sampled models; a wrench chosen independently of the draw that lies in an "all"
        set fails, with confidence 1 - ``beta``, for at most a fraction ``epsilon`` of the
        models (one outside an "any" set is consistent, with the same confidence, for at
        most a fraction ``epsilon``).
    epsilon, beta : float or None
        Violation probability and confidence parameter of the scenario approach.
    models : int or None
        Number of sampled models N.

    Raises
    ------
    ValueError
        For a kind not in :data:`GUARANTEE_KINDS`.
    """

    kind: str
    epsilon: float | None = None
    beta: float | None = None
    models: int | None = None

    def __post_init__(self) -> None:
        if self.kind not in GUARANTEE_KINDS:
            raise ValueError(f"guarantee kind must be one of {GUARANTEE_KINDS}, "
                             f"got {self.kind!r}")

    @property
    def exact(self) -> bool:
        """Whether the guarantee is exact (not a scenario bound)."""
        return self.kind == "exact"

    def __str__(self) -> str:
        if self.kind == "exact":
            return "exact"
        return f"scenario(eps={self.epsilon:g}, beta={self.beta:g}, N={self.models})"

    def to_dict(self) -> dict:
        """JSON-able form: kind, epsilon, beta, models and the one-line text.

        Returns
        -------
        dict
            ``kind``, ``epsilon``, ``beta``, ``models``, ``text``.
        """
        return {"kind": self.kind, "epsilon": self.epsilon, "beta": self.beta,
                "models": self.models, "text": str(self)}


#: The guarantee of a nominal or friction-interval answer.
EXACT_GUARANTEE = Guarantee("exact")


def _rows(G) -> np.ndarray:
    G = np.asarray(G, dtype=float)
    return G.reshape(-1, 3) if G.size else G.reshape(0, 3)


@dataclass(frozen=True)
class WrenchSet:
    """A set of wrenches: the union of convex cones (``pieces``) with its guarantee.

    Parameters
    ----------
    mode : str
        The mode the set belongs to (with wildcards for a union of modes).
    pieces : tuple of Cone
        The convex cones whose union is the set (one for a convex set).
    guarantee : Guarantee
        What membership means (:data:`EXACT_GUARANTEE` unless sampled models made it).
    impossible : tuple of str
        Concrete modes of a wildcard mode whose cone is empty (infeasible): not pieces.
    quantifier : str or None
        ``"all"`` (consistent for every model) or ``"any"`` (for some model) for a robust
        set; None for the nominal model's set.
    frame : str
        ``"nominal"``: torques about the nominal centre of mass; ``"com"``: about each
        model's own centre of mass (:mod:`.robust`).

    Notes
    -----
    ``contains(g)``: g lies in some piece. ``margin(g)``: the largest of the pieces'
    margins (module docstring); -1 with no piece.
    """

    mode: str
    pieces: tuple[Cone, ...]
    guarantee: Guarantee = EXACT_GUARANTEE
    impossible: tuple[str, ...] = field(default=())
    quantifier: str | None = None
    frame: str = "nominal"

    @staticmethod
    def of(cone: Cone, guarantee: Guarantee = EXACT_GUARANTEE) -> WrenchSet:
        """The set of one convex cone (feasible or not).

        Parameters
        ----------
        cone : Cone
            The cone.
        guarantee : Guarantee
            Its guarantee (exact by default).

        Returns
        -------
        WrenchSet
            One piece: membership and margins are exactly the cone's.
        """
        return WrenchSet(cone.mode, (cone,), guarantee)

    @property
    def feasible(self) -> bool:
        """Whether some piece is a feasible cone (some wrench realises the mode)."""
        return any(c.feasible for c in self.pieces)

    @property
    def modes(self) -> tuple[str, ...]:
        """The concrete modes of the pieces, in order."""
        return tuple(c.mode for c in self.pieces)

    @property
    def cone(self) -> Cone:
        """The single convex cone of a one-piece set.

        Raises
        ------
        ValueError
            For a union of several cones (use :attr:`pieces`).
        """
        if len(self.pieces) != 1:
            what = (f"the {self.quantifier!r} set" if self.quantifier else "the set")
            raise ValueError(f"{what} of {self.mode!r} is a union of {len(self.pieces)} "
                             "cones; use .pieces")
        return self.pieces[0]

    def check(self, g: Sequence[float]) -> tuple[bool, float]:
        """``(contains(g), margin(g))`` in one pass.

        Parameters
        ----------
        g : sequence of 3 float
            Wrench (f_x, f_y, tau) in N, N, N m.

        Returns
        -------
        tuple of (bool, float)
            Whether g lies in the set, and its margin (module docstring).

        Raises
        ------
        ValueError
            If g is not finite.
        """
        if len(self.pieces) == 1:
            return self.pieces[0].check(g)
        inside, margin = False, -1.0
        for c in self.pieces:
            ok, m = c.check(g)
            inside, margin = inside or ok, max(margin, m)
        return inside, margin

    def contains(self, g: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        """Whether g lies in some piece (tolerance ``tol`` on the unit direction).

        Parameters
        ----------
        g : sequence of 3 float
            Wrench (f_x, f_y, tau) in N, N, N m.
        tol : float, optional
            Dimensionless tolerance on the unit nondimensional direction
            (:meth:`Cone.contains <wrenchcone_ros.core.cones.Cone.contains>`).

        Returns
        -------
        bool
            Membership of the union of the pieces; False with no piece.

        Raises
        ------
        ValueError
            If g is not finite.
        """
        if tol == CONE_TOLERANCE:
            return self.check(g)[0]
        return any(c.contains(g, tol) for c in self.pieces)

    def margin(self, g: Sequence[float]) -> float:
        """The largest of the pieces' margins of g (-1 with no piece).

        Parameters
        ----------
        g : sequence of 3 float
            Wrench (f_x, f_y, tau) in N, N, N m.

        Returns
        -------
        float
            Dimensionless, in [-1, 1], positive inside.

        Raises
        ------
        ValueError
            If g is not finite.
        """
        return self.check(g)[1]

    def check_many(self, G) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`check` of every row of an (N, 3) array, elementwise identical.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3), SI units.

        Returns
        -------
        tuple of (ndarray of bool, ndarray of float)
            Membership and margin of each row.

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        G = _rows(G)
        inside = np.zeros(G.shape[0], dtype=bool)
        margin = np.full(G.shape[0], -1.0)
        for k, c in enumerate(self.pieces):
            ok, m = c.check_many(G)
            inside |= ok
            margin = m if k == 0 else np.maximum(margin, m)
        return inside, margin

    def contains_many(self, G, tol: float = CONE_TOLERANCE) -> np.ndarray:
        """:meth:`contains` of every row of an (N, 3) array, elementwise identical.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3), SI units.
        tol : float, optional
            As in :meth:`contains`.

        Returns
        -------
        numpy.ndarray
            bool, shape (N,).

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        G = _rows(G)
        out = np.zeros(G.shape[0], dtype=bool)
        for c in self.pieces:
            out |= c.contains_many(G, tol)
        return out

    def margin_many(self, G) -> np.ndarray:
        """:meth:`margin` of every row of an (N, 3) array, elementwise identical.

        Parameters
        ----------
        G : array_like
            Wrenches, shape (N, 3), SI units.

        Returns
        -------
        numpy.ndarray
            float, shape (N,).

        Raises
        ------
        ValueError
            G is not of shape (N, 3), or a row is not finite.
        """
        return self.check_many(G)[1]

    def to_dict(self) -> dict:
        """JSON-able form: mode, feasibility, guarantee, pieces (SI units; ``cone`` too
        for a one-piece set), impossible modes, and the quantifier and frame of a robust
        set.

        Returns
        -------
        dict
            ``mode``, ``feasible``, ``guarantee``, ``pieces``, ``impossible`` (and ``cone``,
            ``quantifier``, ``frame`` where they apply).
        """
        d = {"mode": self.mode, "feasible": self.feasible,
             "guarantee": self.guarantee.to_dict(),
             "pieces": [c.to_dict() for c in self.pieces],
             "impossible": list(self.impossible)}
        if len(self.pieces) == 1:
            d["cone"] = d["pieces"][0]
        if self.quantifier is not None:
            d["quantifier"] = self.quantifier
            d["frame"] = self.frame
        return d


def union_of(mode: str, cones: Iterable[Cone]) -> WrenchSet:
    """The union named ``mode`` of its concrete modes' ``cones``.

    Parameters
    ----------
    mode : str
        The wildcard mode.
    cones : iterable of Cone
        The cone of each concrete mode it expands to.

    Returns
    -------
    WrenchSet
        The feasible cones as pieces, the infeasible ones' modes as ``impossible``.
    """
    cones = tuple(cones)
    return WrenchSet(mode, tuple(c for c in cones if c.feasible),
                     impossible=tuple(c.mode for c in cones if not c.feasible))


def union_over(scene: Scene, mode: str, cone_of: Callable[[str], Cone]) -> WrenchSet:
    """The union of ``cone_of(m)`` over every concrete mode m of ``mode`` in ``scene``.

    Checks the request's time budget (:func:`.budget.check_time_budget`) before each cone.

    Parameters
    ----------
    scene : Scene
        The scene (its contact state).
    mode : str
        A mode, wildcards allowed.
    cone_of : callable
        The cone of one concrete mode.

    Returns
    -------
    WrenchSet
        The union (:func:`union_of`).

    Raises
    ------
    ModeError
        For a mode the contact state does not allow (the fixels' gaps in the message).
    """
    concrete = expand_mode(mode, scene.in_contact, scene.gaps,
                           scene.effective_contact_tolerance)
    cones = []
    for m in concrete:
        check_time_budget()
        cones.append(cone_of(m))
    return union_of(mode, cones)


def margins_of(sets: Sequence[WrenchSet | Cone], g: Sequence[float]) -> list[float]:
    """``[s.margin(g) for s in sets]``, the same doubles, at a fraction of the cost.

    Every piece's margin comes from one :func:`.cones.margins_at` pass (the scalar
    margin's operations written out), folded per set as :meth:`WrenchSet.check` folds
    them (one piece: its margin; several: the running ``max`` from -1). The planner's
    margin functions call it for every direction they try.

    Parameters
    ----------
    sets : sequence of WrenchSet or Cone
        The sets (a Cone counts as a set of one piece).
    g : sequence of 3 float
        Wrench (f_x, f_y, tau) in N, N, N m.

    Returns
    -------
    list of float
        One margin per set, in order.

    Raises
    ------
    ValueError
        If g is not finite.
    """
    groups = [(s,) if isinstance(s, Cone) else s.pieces for s in sets]
    values = margins_at([c for pieces in groups for c in pieces], g)
    out, k = [], 0
    for pieces in groups:
        n = len(pieces)
        if n == 1:
            out.append(values[k])
        else:
            margin = -1.0
            for m in values[k:k + n]:
                margin = max(margin, m)
            out.append(margin)
        k += n
    return out


__all__ = ["GUARANTEE_KINDS", "Guarantee", "EXACT_GUARANTEE", "WrenchSet", "margins_of",
           "union_of", "union_over"]
