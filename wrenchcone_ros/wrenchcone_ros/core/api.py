# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Public entry points of the core: :func:`wrench_cone` (one mode) and :func:`mode_union`.

The batched entry point for many modes of one pose is :func:`.batch.wrench_cones`.
"""

from __future__ import annotations

from .batch import kernel_cone
from .cones import Cone
from .engines import resolve_engine
from .methods import DEFAULT_METHOD, METHODS, method_name, reference_cone
from .scene import Scene
from .unions import ConeUnion, union_over

__all__ = ["DEFAULT_METHOD", "METHODS", "wrench_cone", "mode_union"]


def wrench_cone(scene: Scene, mode: str, exact: bool = False, method: str | None = None,
                engine: str | None = None) -> Cone | ConeUnion:
    """The cone of wrenches consistent with ``mode`` in ``scene``.

    A mode with wildcards ("c": l, r or n; "*": any valid letter) gives a
    :class:`~wrenchcone_ros.core.unions.ConeUnion` of the concrete modes' cones.

    ``exact=True`` runs the whole computation in rational arithmetic (cddlib GMP) from
    the scene's numbers as written. Raises ModeError for a mode the contact state does
    not allow, ValueError for an unknown method.

    ``engine`` (float planar method only): "kernel", the compiled batch engine, or
    "numpy", the reference (:mod:`.engines`; default: $WRENCHCONE_ENGINE, else "kernel"
    when numba is importable). Many modes of one pose: :func:`.batch.wrench_cones`.
    """
    name = method_name(method)
    if not exact and name == "planar" and isinstance(mode, str) \
            and resolve_engine(engine) == "kernel":
        return kernel_cone(scene, mode)
    return reference_cone(scene, mode, exact=exact, method=name)


def mode_union(scene: Scene, mode: str, exact: bool = False, method: str | None = None,
               engine: str | None = None) -> ConeUnion:
    """The union of cones of a mode with wildcards ("c", "*"), each concrete mode's cone
    by :func:`wrench_cone`; see :class:`~.unions.ConeUnion`. A concrete mode gives a
    union of one cone."""
    return union_over(scene, mode, lambda m: wrench_cone(scene, m, exact=exact,
                                                         method=method, engine=engine))
