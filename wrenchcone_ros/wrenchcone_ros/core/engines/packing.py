# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The kernel's input layout: a mode's plan (:func:`.constraints.plan_for`) as int64
op-codes (:func:`plan_code`), several packed into one array (:func:`pack`), the plans of
a list of modes (:func:`batch_plan`), and a scene's pose arrays (:func:`pose_arrays`).

The only module that sees the op-codes' layout. Its caches live in :mod:`..stats`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import stats
from ..budget import check_time_budget
from ..constraints import plan_for
from ..dynamics import float_rows
from ..modes import MODE_TABLE, ModeError, expand_mode, is_wildcard, parse_mode
from ..scene import Scene


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
    d = scene.__dict__
    cache = d.get(_POSE_ARRAYS)
    if cache is None:
        cache = d[_POSE_ARRAYS] = float_rows(scene, d.get(_POSE_ROWS))
    return cache


def keep_pose_rows(scene: Scene, rows: np.ndarray) -> None:
    """Keep J_hat^T (2n x 3) of the scene's pose, computed with its contact geometry (the
    doubles :func:`.dynamics.float_rows` computes), for :func:`pose_arrays`.

    Parameters
    ----------
    scene : Scene
        The scene whose contact geometry is being computed.
    rows : numpy.ndarray
        Its J_hat^T.
    """
    scene.__dict__[_POSE_ROWS] = rows


#: Where a scene keeps its pose arrays and its J_hat^T rows (Scene.with_pose carries
#: neither: both depend on the pose).
_POSE_ARRAYS, _POSE_ROWS = "_pose_arrays", "_pose_rows"


__all__ = ["BatchPlan", "batch_plan", "keep_pose_rows", "pack", "plan_code", "pose_arrays"]
