# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The engines that compute float planar cones, registered in one place.

An engine (:class:`Engine`) computes, for the float planar method (:mod:`.planar`):

* the contact geometry of a scene (:meth:`Engine.contact_arrays`);
* the cones of a batch of valid concrete modes of one pose (:meth:`Engine.cones`);
* the relaxed cones of the mode search (:meth:`Engine.relaxed_rows`);
* the robust batches of :mod:`.robust`: the cones at the vertices of a friction box
  (:meth:`Engine.vertex_cones`), their intersection in one call
  (:meth:`Engine.vertex_intersection`), the "any" cones of many modes
  (:meth:`Engine.any_cones`), and a cone from many inequality rows
  (:meth:`Engine.hrep_cone`).

Two engines are registered in :data:`ENGINES`: ``"kernel"``, the planar method compiled
with numba (:mod:`.kernel`; the default when numba can be imported), and ``"numpy"``, the
reference (:func:`.planar.planar_cone` mode by mode). A mode the kernel declines (nearly
parallel acceleration rows, a failed cone3d self-check) is computed by the reference, so
both engines give the same cones (test/core/test_kernel.py).

Choosing the engine. Every function that computes cones takes ``engine=`` (a name, an
:class:`Engine`, or None for the default). The default is set in one place,
:func:`default_engine`: the name given to :func:`configure_engine`, else the environment
variable ``WRENCHCONE_ENGINE`` (``kernel`` or ``numpy``, read once per process), else
``"kernel"``; ``"kernel"`` becomes ``"numpy"`` when numba cannot be loaded (one
RuntimeWarning says why). Nothing else in the core reads the environment. A scene's
contact geometry is computed by the default engine (a scene is built before any call
names an engine).

This module is the only one that sees the kernel's input layout (the op-code of a mode's
plan, :func:`plan_code`) and that imports :mod:`.kernel`. Its caches live in
:mod:`.stats` (:func:`.stats.reset` clears them).
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from . import stats
from .budget import check_time_budget
from .cones import Cone, assembled_cone, cone_from_hrep, infeasible_float_cone
from .constraints import plan_for
from .dynamics import float_rows, problem
from .modes import MODE_TABLE, ModeError, expand_mode, is_wildcard, parse_mode
from .planar import PLANAR_FALLBACKS, planar_cone
from .geometry import ContactArrays, Disc, use_contact_geometry
from .scene import Scene

#: Environment variable naming the default engine: "kernel" or "numpy".
ENGINE_ENV = "WRENCHCONE_ENGINE"
#: Engine names, in order of preference.
ENGINE_NAMES = ("kernel", "numpy")

#: One line on stderr before numba compiles the kernel (a cold cache: the first use after
#: an install, or after kernel.py changed), so that the wait is not a silent one.
COMPILE_MESSAGE = ("wrenchcone: compiling the batch kernel once (about a minute; cached "
                   "afterwards)")

#: Sliding letters: their friction edge moves with mu (the "all" box's vertices).
SLIDING = "lr"

#: How many cones the kernel made, and how many modes it declined (then the reference
#: computed them). The counter lives in :mod:`.stats`.
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
                   for f in (kernel.planar_batch, kernel.contact_geometry))
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
            from . import kernel  # lazy: numba is optional, and slow to import
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


# --- the kernel's input layout: a mode's plan as op-codes -------------------------------
def plan_code(mode: str, in_contact: tuple[bool, ...], inters: tuple | None = None
              ) -> np.ndarray | None:
    """:func:`.constraints.plan_for` as the kernel's int64 op-code (cached, any pose).

    Layout: [ki, ke, kf, ineq rows (ki), signs (2 ki), strict flags (ki), eq rows (ke),
    loaded fixels (kf), edge signs (kf)]; row k < n is fixel k's normal acceleration,
    n + k its tangential one.

    Parameters
    ----------
    mode : str
        A concrete mode, or a relaxation with '?' letters (given by ``inters``).
    in_contact : tuple of bool
        The contact state.
    inters : tuple or None
        The mode's parsed intersections (:func:`.modes.parse_mode`); None: return the
        cached code only.

    Returns
    -------
    ndarray of int64 or None
        The code, or None when it is not cached and ``inters`` is None.
    """
    key = (mode, in_contact)
    code = stats.PLAN_CODES.get(key)
    if code is None and inters is not None:
        ineq, direction, strict, eq, f_idx, f_sgn = plan_for(mode, in_contact, inters)
        code = np.array([len(ineq), len(eq), len(f_idx), *ineq,
                         *np.asarray(direction).reshape(-1).tolist(),
                         *np.asarray(strict, dtype=int).tolist(), *eq, *f_idx,
                         *np.asarray(f_sgn, dtype=int).tolist()], dtype=np.int64)
        stats.remember(stats.PLAN_CODES, key, code)
    return code


def _code(mode: str, in_contact: tuple[bool, ...]) -> np.ndarray:
    """The op-code of a valid concrete mode (the caller validated it)."""
    code = plan_code(mode, in_contact)
    if code is None:
        code = plan_code(mode, in_contact, tuple(MODE_TABLE[ch] for ch in mode))
    return code


def pack(codes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(ptr, code): several :func:`plan_code` packed (CSR) for kernel.planar_batch.

    Parameters
    ----------
    codes : list of numpy.ndarray
        Op-codes of :func:`plan_code`.

    Returns
    -------
    ptr : numpy.ndarray
        int64, (len(codes) + 1,): where each code starts.
    code : numpy.ndarray
        int64: the codes, concatenated.
    """
    ptr = np.zeros(len(codes) + 1, dtype=np.int64)
    if not codes:
        return ptr, np.zeros(0, dtype=np.int64)
    np.cumsum([c.shape[0] for c in codes], out=ptr[1:])
    return ptr, np.concatenate(codes)


@dataclass(frozen=True)
class BatchPlan:
    """The validated plans of a list of requested modes for one contact state.

    Parameters
    ----------
    concrete : tuple of str
        The distinct concrete modes to compute, in order.
    entries : tuple
        Per requested mode ("cone", k) | ("union", mode, ks) | ("error",) (an invalid
        mode), k indexing ``concrete``.
    arrays : tuple
        The packed op-codes (ptr, code) (kernel engine only).
    """

    concrete: tuple[str, ...]
    entries: tuple
    arrays: tuple


def batch_plan(modes: tuple, in_contact: tuple[bool, ...]) -> BatchPlan:
    """The packed plans of ``modes`` (cached per modes and contact state, any pose).

    Parameters
    ----------
    modes : tuple of str
        The requested modes, wildcards allowed.
    in_contact : tuple of bool
        The contact state.

    Returns
    -------
    BatchPlan
        The plan; an invalid mode's entry is ("error",).

    Raises
    ------
    TypeError
        For an unhashable mode (the per-mode path words the error).
    """
    key = (modes, in_contact)
    plan = stats.BATCH_PLANS.get(key)
    if plan is not None:
        return plan
    concrete: list[str] = []
    index: dict[str, int] = {}
    plans: list[np.ndarray] = []
    entries = []

    def add(m: str) -> int:
        if m not in index:
            check_time_budget()  # a wildcard may expand to many thousand plans
            code = plan_code(m, in_contact, parse_mode(m, in_contact))  # may raise
            index[m] = len(concrete)
            concrete.append(m)
            plans.append(code)
        return index[m]

    for mode in modes:
        try:
            if is_wildcard(mode):
                ks = tuple(add(m) for m in expand_mode(mode, in_contact))
                entries.append(("union", mode, ks))
            else:
                entries.append(("cone", add(mode)))
        except ModeError:
            entries.append(("error",))
    plan = BatchPlan(tuple(concrete), tuple(entries), pack(plans))
    if any(e[0] == "error" for e in entries):
        # not kept: a refused mode is cheap to refuse again, and a client sending many
        # distinct malformed modes (each up to max_mode_length letters) must not fill
        # the cache with them
        return plan
    return stats.remember(stats.BATCH_PLANS, key, plan, stats.BATCH_PLAN_CACHE_LIMIT)


def _vertex_codes(mode: str, in_contact: tuple, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(ptr, codes) of ``count`` copies of one mode stacked into one problem (fixel
    j k + i is copy j of fixel i): the copies' codes are the mode's shifted by offsets
    (cached per mode, contact state and count in :data:`.stats.VERTEX_CODES`)."""
    key = (mode, in_contact, count)
    got = stats.VERTEX_CODES.get(key)
    if got is None:
        k = len(mode)
        code = _code(mode, in_contact)
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
        stats.remember(stats.VERTEX_CODES, key, got, stats.BATCH_PLAN_CACHE_LIMIT)
    return got


def _any_code(mode: str, in_contact: tuple, dup: tuple[bool, ...]) -> np.ndarray:
    """A mode's op-code moved to the "any" layout of 2n fixels (fixel n + i is a copy of
    fixel i, at mu_lo): rows of fixel i stay its rows (normal i, tangential 2n + i), and
    each uncertain sliding fixel (``dup``) gains a loaded copy with its edge sign (the
    copy's acceleration rows are the original's, so they add no constraint). Cached in
    :data:`.stats.ANY_CODES`."""
    key = (mode, in_contact, dup)
    got = stats.ANY_CODES.get(key)
    if got is not None:
        return got
    n = len(mode)
    code = _code(mode, in_contact)
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
    return stats.remember(stats.ANY_CODES, key, got, stats.BATCH_PLAN_CACHE_LIMIT)


def _sorted(rows: np.ndarray) -> np.ndarray:
    """Rows in the order of cones.from_cone3 (descending lexicographic on 12 decimals)."""
    if rows.shape[0] < 2:
        return rows
    keys = -np.round(rows, 12)
    return rows[np.lexsort(keys.T[::-1])]


def _kernel_cone(r: np.ndarray, counts: np.ndarray, feasible: bool, mode: str, L: float,
                 copy: bool = False) -> Cone:
    """One cone of a kernel.planar_batch output (its rows and counts); ``copy``: copied
    out (a view would keep the whole batch's rows alive)."""
    nf, ne, nr, nl = counts.tolist()
    parts = (r[0, :nf], r[1, :ne], r[2, :nr], r[3, :nl])
    if copy:
        parts = tuple(p.copy() for p in parts)
    cone = assembled_cone(mode, True, *parts, L, "planar")
    return cone if feasible else infeasible_float_cone(cone)


def pose_arrays(scene: Scene) -> tuple[np.ndarray, float, np.ndarray]:
    """J_hat^T (2n x 3, contiguous), kappa and mu of a scene: computed once per scene.

    Parameters
    ----------
    scene : Scene
        The scene.

    Returns
    -------
    A : numpy.ndarray
        J_hat^T, 2n x 3.
    kappa : float
        I / (m L^2).
    mu : numpy.ndarray
        The friction coefficient of each fixel, (n,).
    """
    cache = scene.__dict__.get("_pose_arrays")
    if cache is None:
        cache = scene.__dict__["_pose_arrays"] = float_rows(scene)
    return cache


# --- the interface --------------------------------------------------------------------------
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

    #: The engine's name in :data:`ENGINES`.
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

    def hrep_cone(self, F, E, mode, L) -> Cone:
        return cone_from_hrep(F, E, mode=mode, length_scale=L, method="planar", exact=False)


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
        status, _i, *arrays = self.kernel.contact_geometry(
            x, y, math.cos(th), math.sin(th), *scene.workpiece.com,
            shape.radius if isinstance(shape, Disc) else 0.0, verts, fpos, frad,
            scene.effective_contact_tolerance)
        if status != 0:
            return None
        out = ContactArrays(*arrays)
        out.freeze()
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
        out: list[Cone] = []
        n_ok = 0
        for k, (mode, st, fe) in enumerate(zip(modes, status.tolist(), feas.tolist())):
            if st:
                KERNEL_STATS["declined"] += 1
                check_time_budget()  # the reference cone of a declined mode can be slow
                out.append(planar_cone(problem(scene, mode)))
                continue
            n_ok += 1
            out.append(_kernel_cone(rows[k], counts[k], fe, mode, L))
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

    def hrep_cone(self, F, E, mode, L) -> Cone:
        try:
            Fk, Ek, R, Lk = self.kernel.from_inequalities(-np.ascontiguousarray(F),
                                                          np.ascontiguousarray(E))
            return assembled_cone(mode, True, _sorted(Fk + 0.0), Ek + 0.0, _sorted(R + 0.0),
                                  Lk + 0.0, float(L), "planar")
        except Exception:  # the kernel's failed self-check: cone3d, then exact cddlib
            return super().hrep_cone(F, E, mode, L)


# --- the registry and the one configuration point ------------------------------------------
_NUMPY = NumpyEngine()
_engines: dict[str, Engine] = {"numpy": _NUMPY}
_configured: str | None = None
_environment: str | None = None
_environment_read = False


def _by_name(name: str) -> Engine:
    """The registered engine ``name`` ("kernel" falls back to "numpy" without numba)."""
    if name not in ENGINE_NAMES:
        raise ValueError(f"unknown engine {name!r}; choose one of {list(ENGINE_NAMES)} "
                         f"(argument engine=, configure_engine() or ${ENGINE_ENV})")
    got = _engines.get(name)
    if got is None:  # "kernel", first use: load (or compile) it
        km = kernel_module()
        got = _engines["kernel"] = KernelEngine(km) if km is not None else _NUMPY
    return got


def configure_engine(name: str | None) -> None:
    """Set the process's default engine (the one configuration point).

    Parameters
    ----------
    name : str or None
        "kernel" or "numpy"; None: back to ``$WRENCHCONE_ENGINE``, else "kernel".

    Raises
    ------
    ValueError
        For an unknown name.
    """
    global _configured
    if name is not None and name not in ENGINE_NAMES:
        _by_name(name)  # raises the worded ValueError
    _configured = name


@contextmanager
def using_engine(name: str | None) -> Iterator[None]:
    """:func:`configure_engine` ``name`` for the duration of a ``with`` block (then restored):
    how a one-shot command (the CLI) chooses the engine of everything it calls.

    Parameters
    ----------
    name : str or None
        "kernel", "numpy", or None (back to the environment's or the default).

    Yields
    ------
    None
        Inside the block, the engine is ``name``.

    Raises
    ------
    ValueError
        For an unknown name.
    """
    global _configured
    saved = _configured
    configure_engine(name)
    try:
        yield
    finally:
        _configured = saved


def engine_from_environment() -> str | None:
    """The engine ``$WRENCHCONE_ENGINE`` names, read once per process (the only read of
    the environment in the core).

    Returns
    -------
    str or None
        The variable's value; None when it is unset or empty.
    """
    global _environment, _environment_read
    if not _environment_read:
        _environment = os.environ.get(ENGINE_ENV) or None
        _environment_read = True
    return _environment


def default_engine() -> Engine:
    """The engine a call without ``engine=`` uses: the name given to :func:`configure_engine`,
    else ``$WRENCHCONE_ENGINE`` (read once), else "kernel".

    Returns
    -------
    Engine
        "kernel" becomes the numpy engine when numba cannot be loaded.

    Raises
    ------
    ValueError
        For an unknown name in the configuration or the environment.
    """
    return _by_name(_configured or engine_from_environment() or "kernel")


def get_engine(engine: str | Engine | None = None) -> Engine:
    """The engine a call uses.

    Parameters
    ----------
    engine : str, Engine or None
        A name in :data:`ENGINE_NAMES`, an engine object, or None for
        :func:`default_engine`.

    Returns
    -------
    Engine

    Raises
    ------
    ValueError
        For an unknown name.
    """
    if engine is None:
        return default_engine()
    if isinstance(engine, str):
        return _by_name(engine)
    return engine


def resolve_engine(engine: str | Engine | None = None) -> str:
    """The name of the engine a call uses.

    Parameters
    ----------
    engine : str, Engine or None, optional
        An engine, its name, or None (the default engine).

    Returns
    -------
    str
        ``get_engine(engine).name``: "kernel" or "numpy".

    Raises
    ------
    ValueError
        For an unknown name.
    """
    return get_engine(engine).name


def _default_contact_arrays(scene: Scene) -> ContactArrays | None:
    return default_engine().contact_arrays(scene)


use_contact_geometry(_default_contact_arrays)  # asked for by Scene.contact_arrays


__all__ = ["ENGINE_ENV", "ENGINE_NAMES", "Engine", "NumpyEngine", "KernelEngine",
           "RelaxedRows", "BatchPlan", "KERNEL_STATS", "configure_engine", "using_engine",
           "default_engine", "engine_from_environment", "get_engine", "resolve_engine", "kernel_module",
           "kernel_unavailable", "plan_code", "pack", "batch_plan", "pose_arrays"]
