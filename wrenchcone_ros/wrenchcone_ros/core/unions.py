# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The wrenches of a wildcard mode: :class:`ConeUnion`, a union of convex cones.

A mode with wildcards ("c": l, r or n; "*": any valid letter, :data:`.modes.WILDCARDS`)
stands for every concrete mode it expands to (:func:`.modes.expand_mode`); its wrenches
are the union of their cones. This module holds the type and how a union is assembled
from a function that makes one concrete mode's cone; which function (the compiled
engine or a reference method) is the caller's choice (:mod:`.api`, :mod:`.batch`,
:mod:`.methods`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .budget import check_time_budget
from .cones import Cone
from .modes import expand_mode
from .scene import Scene
from .tolerances import CONE_TOLERANCE


@dataclass(frozen=True)
class ConeUnion:
    """The wrenches of a wildcard mode: the union of its concrete modes' cones.

    ``contains(g)``: g is in some piece. ``margin(g)``: the largest of the pieces'
    margins. Outside every piece this is exactly minus the distance of g's unit direction
    to the union; inside, it is a lower bound on the distance to the union's boundary
    (pieces may touch, and the union need not be convex). Infeasible concrete modes are
    left out (``impossible``).
    """

    mode: str
    pieces: tuple[Cone, ...]
    impossible: tuple[str, ...] = field(default=())

    @property
    def feasible(self) -> bool:
        return bool(self.pieces)

    @property
    def modes(self) -> tuple[str, ...]:
        return tuple(c.mode for c in self.pieces)

    def contains(self, g: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        return any(c.contains(g, tol) for c in self.pieces)

    def margin(self, g: Sequence[float]) -> float:
        return max((c.margin(g) for c in self.pieces), default=-1.0)

    def contains_many(self, G, tol: float = CONE_TOLERANCE) -> np.ndarray:
        """:meth:`contains` of every row of an (N, 3) array (elementwise identical)."""
        G = np.asarray(G, dtype=float)
        out = np.zeros(G.reshape(-1, 3).shape[0] if G.size else 0, dtype=bool)
        for c in self.pieces:
            out |= c.contains_many(G, tol)
        return out

    def margin_many(self, G) -> np.ndarray:
        """:meth:`margin` of every row of an (N, 3) array (elementwise identical)."""
        G = np.asarray(G, dtype=float)
        out = np.full(G.reshape(-1, 3).shape[0] if G.size else 0, -1.0)
        for k, c in enumerate(self.pieces):
            m = c.margin_many(G)
            out = m if k == 0 else np.maximum(out, m)
        return out


def union_of(mode: str, cones: Iterable[Cone]) -> ConeUnion:
    """The union named ``mode`` of its concrete modes' ``cones``: the feasible ones are
    its pieces, the infeasible ones are listed as impossible."""
    cones = tuple(cones)
    return ConeUnion(mode, tuple(c for c in cones if c.feasible),
                     tuple(c.mode for c in cones if not c.feasible))


def union_over(scene: Scene, mode: str, cone_of: Callable[[str], Cone]) -> ConeUnion:
    """The union of ``cone_of(m)`` over every concrete mode m of ``mode`` in ``scene``
    (ModeError, with the fixels' gaps in the message, for a mode the contact state does
    not allow). Checks the request's time budget before each cone."""
    concrete = expand_mode(mode, scene.in_contact, scene.gaps,
                           scene.effective_contact_tolerance)
    cones = []
    for m in concrete:
        check_time_budget()
        cones.append(cone_of(m))
    return union_of(mode, cones)
