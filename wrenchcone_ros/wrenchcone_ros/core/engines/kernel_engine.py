# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The compiled engine, ``"kernel"``: the planar method compiled with numba
(:mod:`wrenchcone_ros.core.kernel`, loaded once, at first use), a batch of modes in one
call; a mode the kernel declines goes to the reference (:class:`.numpy_engine.NumpyEngine`).

The only module that imports the kernel.
"""

from __future__ import annotations

import math
import sys
import warnings
from collections.abc import Sequence

import numpy as np

from .. import stats
from ..budget import check_time_budget
from ..cones import Cone, assembled_cone, infeasible_float_cone
from ..dynamics import problem
from ..geometry import ContactArrays, Disc
from ..planar import PLANAR_FALLBACKS, planar_cone
from ..scene import Scene
from ..tolerances import CONE_TOLERANCE
from .numpy_engine import NumpyEngine
from .packing import (
    _any_code,
    _code,
    _vertex_codes,
    keep_pose_rows,
    pack,
    plan_code,
    pose_arrays,
)
from .protocol import Engine, RelaxedRows

#: One line on stderr before numba compiles the kernel (a cold cache: the first use after
#: an install, or after kernel.py changed), so that the wait is not a silent one.
COMPILE_MESSAGE = ("wrenchcone: compiling the batch kernel once (about a minute; cached "
                   "afterwards)")

#: Sliding letters: their friction edge moves with mu (the "all" box's vertices).
SLIDING = "lr"

#: How many cones the kernel made, and how many modes it declined (then the reference
#: computed them). The counter lives in :mod:`..stats`.
KERNEL_STATS = stats.KERNEL_STATS


# --- the compiled kernel, loaded once -----------------------------------------------------
_kernel_module = None
_kernel_error: str | None = None


def _cache_is_cold(kernel) -> bool:
    """Whether numba's on-disk cache lacks a usable compiled copy of the kernel's entry
    points (then the first call compiles them, about a minute). Reads numba's cache
    index, a numba internal; on any surprise it answers False (say nothing)."""
    try:
        return any(not f._cache._cache_file._load_index()
                   for f in (kernel.planar_batch, kernel.contact_geometry,
                             kernel.cone_checks))
    except Exception:  # another numba version: no message rather than a wrong one
        return False


def kernel_module():
    """The compiled kernel module, or None when it cannot be loaded.

    Returns
    -------
    module or None
        :mod:`.kernel`; None when numba is missing or has no writable cache directory
        (then one RuntimeWarning, and :func:`kernel_unavailable` says why).
    """
    global _kernel_module, _kernel_error
    if _kernel_module is None and _kernel_error is None:
        try:
            from .. import kernel  # lazy: numba is optional, and slow to import
        except Exception as exc:  # numba missing or broken, or no writable cache
            # location (numba's RuntimeError "no locator available"): the numpy engine
            _kernel_error = f"{type(exc).__name__}: {exc}"
            warnings.warn(f"wrenchcone_ros: compiled kernel unavailable ({_kernel_error}); "
                          "using the numpy reference engine (the same cones, slower; for "
                          "the kernel: pip install 'numba>=0.61')", RuntimeWarning,
                          stacklevel=3)
        else:
            if _cache_is_cold(kernel):
                print(COMPILE_MESSAGE, file=sys.stderr, flush=True)
            _kernel_module = kernel
    return _kernel_module


def kernel_unavailable() -> str | None:
    """Why the kernel could not be loaded (None if it loaded or was not tried yet).

    Returns
    -------
    str or None
        The loading error, as ``ExceptionType: message``.
    """
    return _kernel_error


def _sorted(rows: np.ndarray) -> np.ndarray:
    """Rows in the order of cones.from_cone3 (descending lexicographic on 12 decimals)."""
    if rows.shape[0] < 2:
        return rows
    keys = -np.round(rows, 12)
    return rows[np.lexsort(keys.T[::-1])]


def _kernel_cone(r: np.ndarray, counts: np.ndarray, feasible: bool, mode: str, L: float,
                 copy: bool = False) -> Cone:
    """One cone of a kernel.planar_batch output (its rows and counts); ``copy``: copied
    out (a view would keep the whole batch's rows alive). (:meth:`KernelEngine.
    planned_cones` builds its cones inline, with their SI rows.)"""
    nf, ne, nr, nl = counts.tolist()
    parts = (r[0, :nf], r[1, :ne], r[2, :nr], r[3, :nl])
    if copy:
        parts = tuple(p.copy() for p in parts)
    cone = assembled_cone(mode, True, *parts, L, "planar")
    return cone if feasible else infeasible_float_cone(cone)


def _si_rows(rows: np.ndarray, L: float) -> tuple[np.ndarray, np.ndarray]:
    """The SI inequality rows of every mode of a batch in one product, read-only, and
    the scale row [1, 1, 1/L] they were multiplied by (:attr:`.Cone.F`)."""
    s = np.array([1.0, 1.0, 1.0 / L])
    F = rows[:, 0] * s
    s.setflags(write=False)
    F.setflags(write=False)
    return F, s


class KernelEngine(NumpyEngine):
    """The compiled engine (:mod:`.kernel`): a batch of modes in one call; a mode the
    kernel declines goes to the reference.

    Parameters
    ----------
    kernel : module
        The compiled kernel (:func:`kernel_module`).
    """

    name = "kernel"
    batched = True

    def __init__(self, kernel) -> None:
        self.kernel = kernel

    def contact_arrays(self, scene: Scene) -> ContactArrays | None:
        """:func:`.kernel.contact_geometry` (the reference's operations in the same
        order: the same doubles), or None where the kernel refuses a fixel.

        Parameters
        ----------
        scene : Scene
            The scene.

        Returns
        -------
        ContactArrays or None
            The contact geometry.
        """
        x, y, th = scene.pose
        shape = scene.workpiece.shape
        fpos, frad, verts = scene.fixel_arrays
        status, _i, *arrays, rows = self.kernel.contact_geometry(
            x, y, math.cos(th), math.sin(th), *scene.workpiece.com,
            shape.radius if isinstance(shape, Disc) else 0.0, verts, fpos, frad,
            scene.effective_contact_tolerance, scene.length_scale)
        if status != 0:
            return None
        out = ContactArrays(*arrays)
        out.freeze()
        keep_pose_rows(scene, rows)  # J_hat^T, for pose_arrays: computed with the frames
        return out

    def run(self, scene: Scene, arrays: tuple):
        """kernel.planar_batch on the scene's pose arrays and packed op-codes: (status,
        feasible, counts, rows) per mode.

        Parameters
        ----------
        scene : Scene
            The scene.
        arrays : tuple
            (ptr, code) of :func:`pack`.

        Returns
        -------
        tuple of numpy.ndarray
            (status, feasible, counts, rows), as :class:`RelaxedRows`.
        """
        A, kappa, mu = pose_arrays(scene)
        return self.kernel.planar_batch(A, kappa, mu, *arrays)

    def planned_cones(self, scene: Scene, modes: Sequence[str], arrays: tuple) -> list[Cone]:
        """The cones of valid concrete ``modes`` whose packed op-codes are ``arrays``
        (one kernel call; the reference for declined modes).

        Parameters
        ----------
        scene : Scene
            The scene.
        modes : sequence of str
            Valid concrete modes.
        arrays : tuple
            Their packed op-codes (:func:`pack`).

        Returns
        -------
        list of Cone
            One per mode.
        """
        if not len(modes):
            return []
        check_time_budget()
        status, feas, counts, rows = self.run(scene, arrays)
        L = float(scene.length_scale)
        F, s = _si_rows(rows, L)
        out: list[Cone] = []
        n_ok = 0
        # _kernel_cone inlined, each cone given its SI rows F (the same doubles as
        # F_hat * s) and, infeasible, its empty F: the per-mode Python work is most of a
        # batch's time (docs/performance.md)
        for k, (mode, st, fe, (nf, ne, nr, nl)) in enumerate(zip(
                modes, status.tolist(), feas.tolist(), counts.tolist())):
            if st:
                KERNEL_STATS["declined"] += 1
                check_time_budget()  # the reference cone of a declined mode can be slow
                out.append(planar_cone(problem(scene, mode)))
                continue
            n_ok += 1
            r = rows[k]
            cone = assembled_cone(mode, True, r[0, :nf], r[1, :ne], r[2, :nr], r[3, :nl], L,
                                  "planar", F=F[k, :nf], s=s)
            out.append(cone if fe else infeasible_float_cone(cone, s))
        KERNEL_STATS["kernel_cones"] += n_ok
        PLANAR_FALLBACKS["float_cones"] += n_ok
        return out

    def cones(self, scene: Scene, modes: Sequence[str]) -> list[Cone]:
        contact = scene.in_contact
        return self.planned_cones(scene, modes, pack([_code(m, contact) for m in modes]))

    def relaxed_rows(self, scene, keys, inters) -> RelaxedRows:
        contact = scene.in_contact
        codes = []
        for k in keys:
            code = plan_code(k, contact)
            codes.append(code if code is not None else plan_code(k, contact, inters(k)))
        return RelaxedRows(*self.run(scene, pack(codes)))

    def vertex_cones(self, A, kappa, L, mode, in_contact, mus, reference) -> list[Cone]:
        k = len(mode)
        count = len(mus)
        ptr, code = _vertex_codes(mode, in_contact, count)
        rows = np.concatenate([np.tile(A[:k], (count, 1)), np.tile(A[k:], (count, 1))])
        mu = np.array([m for vertex in mus for m in vertex], dtype=float)
        status, feas, counts, out = self.kernel.planar_batch(rows, float(kappa), mu, ptr, code)
        return [reference(j) if status[j]
                else _kernel_cone(out[j], counts[j], bool(feas[j]), mode, L, copy=True)
                for j in range(count)]

    def vertex_intersection(self, A, kappa, L, mode, in_contact, mus) -> Cone | None:
        status, feasible, F, E, R, Lk = self.kernel.planar_all(
            A, float(kappa), np.array(mus, dtype=float), _code(mode, in_contact))
        if status:
            return None
        cone = assembled_cone(mode, True, F, E, R, Lk, L, "planar")
        # an impossible mode (for every mu: X does not depend on it): the intersection
        # of the vertices' closures is the closure
        return cone if feasible else infeasible_float_cone(cone)

    def any_cones(self, A, kappa, L, modes, in_contact, intervals) -> list[Cone | None]:
        n = len(in_contact)
        A2 = np.concatenate([A[:n], A[:n], A[n:], A[n:]])
        mu = np.array([hi for _, hi in intervals] + [lo for lo, _ in intervals], dtype=float)
        codes = [_any_code(m, in_contact, tuple(ch in SLIDING and lo < hi
                                                 for ch, (lo, hi) in zip(m, intervals)))
                 for m in modes]
        status, feas, counts, rows = self.kernel.planar_batch(A2, float(kappa), mu,
                                                              *pack(codes))
        return [None if status[j]
                else _kernel_cone(rows[j], counts[j], bool(feas[j]), m, L, copy=True)
                for j, m in enumerate(modes)]

    def cone_checks(self, cones: Sequence[Cone]) -> PackedCones:
        """:class:`PackedCones` of ``cones`` (the compiled :func:`.kernel.cone_checks`).

        Parameters
        ----------
        cones : sequence of Cone
            The cones, float.

        Returns
        -------
        PackedCones
            Their checks in one call.
        """
        return PackedCones(self.kernel, cones)

    def hrep_cone(self, F, E, mode, L) -> Cone:
        try:
            Fk, Ek, R, Lk = self.kernel.from_inequalities(-np.ascontiguousarray(F),
                                                          np.ascontiguousarray(E))
            return assembled_cone(mode, True, _sorted(Fk + 0.0), Ek + 0.0, _sorted(R + 0.0),
                                  Lk + 0.0, float(L), "planar")
        except Exception:  # the kernel's failed self-check: cone3d, then exact cddlib
            return super().hrep_cone(F, E, mode, L)


class PackedCones:
    """K cones packed for :func:`.kernel.cone_checks` (rows concatenated, with offsets):
    ``check(G)`` is each cone's ``check_many(G)``, the same doubles, in one compiled call
    (the direction searches ask it for every direction they try).

    Parameters
    ----------
    kernel : module
        The compiled kernel.
    cones : sequence of Cone
        The cones, float.
    """

    def __init__(self, kernel, cones: Sequence[Cone]) -> None:
        self.kernel = kernel
        self.cones = list(cones)
        queries = [c.prepared for c in self.cones]
        self.feasible = np.array([q.feasible for q in queries], dtype=np.bool_)
        self.inv_l = np.array([q.inv_l for q in queries], dtype=float)
        parts = [q.arrays() for q in queries]
        self.packed = []
        for i, width in enumerate((3, 3, 3, 3, 9)):
            blocks = [p[i] for p in parts]
            off = np.zeros(len(blocks) + 1, dtype=np.int64)
            off[1:] = np.cumsum([len(b) for b in blocks])
            rows = (np.ascontiguousarray(np.concatenate(blocks)) if blocks
                    else np.zeros((0, width)))
            self.packed += [rows, off]

    def check(self, G: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """contains (N, K) and margins (N, K) at the (N, 3) wrenches G (SI).

        Parameters
        ----------
        G : numpy.ndarray
            (N, 3) wrenches.

        Returns
        -------
        tuple of numpy.ndarray
            (contains, margins).

        Raises
        ------
        ValueError
            A wrench is not finite (the reference's error, from ``Cone.check_many``).
        """
        G = np.ascontiguousarray(G, dtype=float).reshape(-1, 3)
        N, K = G.shape[0], len(self.cones)
        contains = np.empty((N, K), dtype=np.bool_)
        margins = np.empty((N, K))
        if K and N:
            status = self.kernel.cone_checks(self.feasible, self.inv_l, *self.packed, G,
                                             CONE_TOLERANCE, contains, margins)
            if status != self.kernel.CHECKS_OK:
                for c in self.cones:  # raises the reference's ValueError
                    c.check_many(G)
                raise ValueError(f"wrench must be finite, got {G.tolist()}")
        return contains, margins


def make_kernel_engine() -> Engine | None:
    """The kernel engine, or None when the kernel cannot be loaded (:func:`kernel_module`).

    Returns
    -------
    KernelEngine or None
        The engine.
    """
    km = kernel_module()
    return KernelEngine(km) if km is not None else None


__all__ = ["COMPILE_MESSAGE", "KERNEL_STATS", "KernelEngine", "PackedCones", "SLIDING", "kernel_module",
           "kernel_unavailable", "make_kernel_engine"]
