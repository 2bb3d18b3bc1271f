# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The cone algorithms by name (:data:`METHODS`) and the reference path through them.

``"planar"`` (:func:`.planar.planar_cone`) is the default: the fastest that passes the
cross-checks; ``"paper"`` (:func:`.paper.paper_cone`) is the reference implementation of
the paper's algorithm. Both take a :class:`~.dynamics.Problem` (one concrete mode of one
scene, float or exact). The compiled engine (:mod:`.batch`) computes the float planar
method; everything else goes through :func:`reference_cone`.
"""

from __future__ import annotations

from collections.abc import Callable

from .cones import Cone
from .dynamics import Problem, problem
from .modes import is_wildcard
from .paper import paper_cone
from .planar import planar_cone
from .scene import Scene
from .unions import ConeUnion, union_over

#: Methods by name. "planar" is the default (fastest that passes the cross-checks);
#: "paper" is the reference implementation of the paper's algorithm.
METHODS: dict[str, Callable[[Problem], Cone]] = {"planar": planar_cone, "paper": paper_cone}
DEFAULT_METHOD = "planar"


def method_name(method: str | None) -> str:
    """The method a call uses (DEFAULT_METHOD for None); ValueError for an unknown one."""
    name = DEFAULT_METHOD if method is None else method
    if name not in METHODS:
        raise ValueError(f"unknown method {name!r}; choose one of {sorted(METHODS)}")
    return name


def reference_cone(scene: Scene, mode: str, exact: bool = False,
                   method: str | None = None) -> Cone | ConeUnion:
    """The cone of ``mode`` by the named method, mode by mode (no compiled engine): a
    :class:`~.unions.ConeUnion` for a mode with wildcards. Raises ModeError /
    ModeSyntaxError for an invalid mode, ValueError for an unknown method."""
    make = METHODS[method_name(method)]
    if is_wildcard(mode):
        return union_over(scene, mode, lambda m: make(problem(scene, m, exact)))
    return make(problem(scene, mode, exact))
