# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What an engine computes (:class:`Engine`), and the rows of a batch of relaxed modes
(:class:`RelaxedRows`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from ..cones import Cone
from ..geometry import ContactArrays
from ..scene import Scene


@dataclass(frozen=True)
class RelaxedRows:
    """The facet and equality rows of a batch of (relaxed) modes' cones.

    Parameters
    ----------
    status : numpy.ndarray
        (m,): nonzero where the engine declined the mode (the caller decides it by the
        reference).
    feasible : numpy.ndarray
        (m,): whether each mode's open mode is possible.
    counts : numpy.ndarray
        (m, 4): the numbers of facet, equality, ray and line rows.
    rows : numpy.ndarray
        (m, 4, w, 3): those rows, unit, nondimensional.
    """

    status: np.ndarray
    feasible: np.ndarray
    counts: np.ndarray
    rows: np.ndarray


@runtime_checkable
class Engine(Protocol):
    """What an engine computes (module docstring). Every cone is in the scene's
    nondimensional metric, g_hat = (f_x, f_y, tau / L)."""

    #: The engine's name in the registry (:mod:`.registry`).
    name: str
    #: Whether :meth:`relaxed_rows` computes (else the mode search uses its reference).
    batched: bool

    def contact_arrays(self, scene: Scene) -> ContactArrays | None:
        """The float contact geometry of ``scene``, or None to leave it to the reference
        :meth:`.scene.Scene.contact_frames` (which words a refused fixel's SceneError).

        Parameters
        ----------
        scene : Scene
            The scene.

        Returns
        -------
        ContactArrays or None
            The contact geometry.
        """

    def cones(self, scene: Scene, modes: Sequence[str]) -> list[Cone]:
        """The cones of valid concrete ``modes`` of ``scene``, in order (eq. (7)-(9) of
        the paper by the planar method; a declined mode by the reference).

        Parameters
        ----------
        scene : Scene
            The scene.
        modes : sequence of str
            Valid concrete modes.

        Returns
        -------
        list of Cone
            One per mode.
        """

    def relaxed_rows(self, scene: Scene, keys: Sequence[str],
                     inters: Callable[[str], tuple]) -> RelaxedRows | None:
        """The rows of the cones of relaxed modes ``keys`` ('?' letters, whose
        intersections ``inters(key)`` gives), or None when the engine has no batch.

        Parameters
        ----------
        scene : Scene
            The scene.
        keys : sequence of str
            Relaxed modes.
        inters : callable
            The interactions of a key.

        Returns
        -------
        RelaxedRows or None
            The rows.
        """

    def vertex_cones(self, A: np.ndarray, kappa: float, L: float, mode: str,
                     in_contact: tuple[bool, ...], mus: Sequence[tuple],
                     reference: Callable[[int], Cone]) -> list[Cone]:
        """The cone of ``mode`` with rows ``A`` at each friction vector ``mus[j]``
        (a vertex of a friction box); ``reference(j)`` computes one the engine does not.

        Parameters
        ----------
        A : numpy.ndarray
            J_hat^T, 2n x 3.
        kappa : float
            I / (m L^2).
        L : float
            The length scale (m).
        mode : str
            A valid concrete mode.
        in_contact : tuple of bool
            The contact state.
        mus : sequence of tuple
            The friction vectors, one mu per fixel each.
        reference : callable
            The reference cone of vertex j.

        Returns
        -------
        list of Cone
            One per friction vector.
        """

    def vertex_intersection(self, A: np.ndarray, kappa: float, L: float, mode: str,
                            in_contact: tuple[bool, ...], mus: Sequence[tuple]
                            ) -> Cone | None:
        """The intersection of the cones at the friction vectors ``mus`` in one call, or
        None (then the caller intersects :meth:`vertex_cones`).

        Parameters
        ----------
        A : numpy.ndarray
            J_hat^T, 2n x 3.
        kappa : float
            I / (m L^2).
        L : float
            The length scale (m).
        mode : str
            A valid concrete mode.
        in_contact : tuple of bool
            The contact state.
        mus : sequence of tuple
            The friction vectors, one mu per fixel each.

        Returns
        -------
        Cone or None
            The intersection.
        """

    def any_cones(self, A: np.ndarray, kappa: float, L: float, modes: Sequence[str],
                  in_contact: tuple[bool, ...], intervals: Sequence[tuple]
                  ) -> list[Cone | None]:
        """The "any" cones of ``modes`` for friction ``intervals`` (every fixel at mu_hi
        plus a copy of each uncertain sliding fixel at mu_lo); None for a mode the engine
        does not compute.

        Parameters
        ----------
        A : numpy.ndarray
            J_hat^T, 2n x 3.
        kappa : float
            I / (m L^2).
        L : float
            The length scale (m).
        modes : sequence of str
            Valid concrete modes.
        in_contact : tuple of bool
            The contact state.
        intervals : sequence of tuple
            (mu_lo, mu_hi) of each fixel.

        Returns
        -------
        list of Cone or None
            One per mode.
        """

    def hrep_cone(self, F: np.ndarray, E: np.ndarray, mode: str, L: float) -> Cone:
        """The float cone {F g <= 0, E g = 0} (nondimensional rows).

        Parameters
        ----------
        F : numpy.ndarray
            Inequality rows, (k, 3).
        E : numpy.ndarray
            Equality rows, (e, 3).
        mode : str
            The mode of the result.
        L : float
            The length scale (m).

        Returns
        -------
        Cone
            The canonical cone.
        """

    def cone_checks(self, cones: Sequence[Cone]) -> ConeChecks | None:
        """The checks of many cones at many wrenches in one call, or None: then the
        caller uses each cone's :meth:`.cones.Cone.check_many` (the reference).

        Parameters
        ----------
        cones : sequence of Cone
            The cones, float.

        Returns
        -------
        ConeChecks or None
            ``check(G)`` gives, for the (N, 3) wrenches G, contains (N, K) and
            margins (N, K): ``cones[k].check_many(G)``, the same doubles.
        """


class ConeChecks(Protocol):
    """``Cone.check_many`` of K cones at once (:meth:`Engine.cone_checks`)."""

    def check(self, G: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """contains (N, K) and margins (N, K) of the cones at the (N, 3) wrenches G (SI).

        Parameters
        ----------
        G : numpy.ndarray
            (N, 3) wrenches (fx N, fy N, tz N m).

        Returns
        -------
        tuple of numpy.ndarray
            (contains, margins), column k that of ``cones[k].check_many(G)``.

        Raises
        ------
        ValueError
            A wrench is not finite (as ``Cone.check_many`` raises it).
        """


__all__ = ["ConeChecks", "Engine", "RelaxedRows"]
