# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The reference engine, ``"numpy"``: :func:`..planar.planar_cone` mode by mode."""

from __future__ import annotations

from collections.abc import Sequence

from ..budget import check_time_budget
from ..cones import Cone, cone_from_hrep
from ..dynamics import problem
from ..geometry import ContactArrays
from ..planar import planar_cone
from ..scene import Scene
from .protocol import Engine, RelaxedRows


class NumpyEngine:
    """The reference engine: :func:`.planar.planar_cone` mode by mode, cone3d conversions
    (each with its exact fallback, docs/numerics.md)."""

    name = "numpy"
    batched = False

    def contact_arrays(self, scene: Scene) -> ContactArrays | None:
        return None

    def cones(self, scene: Scene, modes: Sequence[str]) -> list[Cone]:
        out = []
        for m in modes:
            check_time_budget()
            out.append(planar_cone(problem(scene, m)))
        return out

    def relaxed_rows(self, scene, keys, inters) -> RelaxedRows | None:
        return None

    def vertex_cones(self, A, kappa, L, mode, in_contact, mus, reference) -> list[Cone]:
        return [reference(j) for j in range(len(mus))]

    def vertex_intersection(self, A, kappa, L, mode, in_contact, mus) -> Cone | None:
        return None

    def any_cones(self, A, kappa, L, modes, in_contact, intervals) -> list[Cone | None]:
        return [None] * len(modes)

    def cone_checks(self, cones: Sequence[Cone]) -> None:
        return None  # the reference: each cone's check_many

    def hrep_cone(self, F, E, mode, L) -> Cone:
        return cone_from_hrep(F, E, mode=mode, length_scale=L, method="planar", exact=False)


#: The reference engine of the process (it keeps no state).
_NUMPY = NumpyEngine()


def make_numpy_engine() -> Engine:
    """The reference engine (one per process).

    Returns
    -------
    NumpyEngine
        The engine.
    """
    return _NUMPY


__all__ = ["NumpyEngine", "make_numpy_engine"]
