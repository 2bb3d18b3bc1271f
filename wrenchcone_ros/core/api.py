"""Public entry points of the core: :func:`wrench_cone`."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .cones import Cone
from .dynamics import problem
from .paper import paper_cone
from .planar import planar_cone
from .modes import WILDCARDS
from .batch import kernel_cone, resolve_engine
from .scene import Scene

if TYPE_CHECKING:
    from .classify import ConeUnion

#: Methods by name. "planar" is the default (fastest that passes the cross-checks);
#: "paper" is the reference implementation of the paper's algorithm.
METHODS = {"planar": planar_cone, "paper": paper_cone}
DEFAULT_METHOD = "planar"  # batch.wrench_cones assumes it for method=None


def wrench_cone(scene: Scene, mode: str, exact: bool = False, method: str | None = None,
                engine: str | None = None) -> Cone | ConeUnion:
    """The cone of wrenches consistent with ``mode`` in ``scene``.

    A mode with wildcards ("c": l, r or n; "*": any valid letter) gives a
    :class:`~wrenchcone_ros.core.classify.ConeUnion` of the concrete modes' cones.

    ``exact=True`` runs the whole computation in rational arithmetic (cddlib GMP) from
    the scene's numbers as written. Raises ModeError for a mode the contact state does
    not allow, ValueError for an unknown method.

    ``engine`` (float planar method only): "kernel", the compiled batch engine, or
    "numpy", the reference (:mod:`.batch`; default: $WRENCHCONE_ENGINE, else "kernel"
    when numba is importable). Many modes of one pose: :func:`.batch.wrench_cones`.
    """
    name = DEFAULT_METHOD if method is None else method
    if name not in METHODS:
        raise ValueError(f"unknown method {name!r}; choose one of {sorted(METHODS)}")
    if not exact and name == "planar" and isinstance(mode, str) \
            and resolve_engine(engine) == "kernel":
        return kernel_cone(scene, mode)
    if isinstance(mode, str) and any(ch in WILDCARDS for ch in mode):
        from .classify import mode_union

        return mode_union(scene, mode, exact=exact, method=method, engine=engine)
    return METHODS[name](problem(scene, mode, exact))
