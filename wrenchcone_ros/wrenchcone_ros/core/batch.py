# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""All requested modes of one pose in one pass: :func:`wrench_cones`.

A pose (a new :class:`~.scene.Scene`) changes the contact frames, hence J_hat; the
mode's constraints (Table 2 as index lists, :func:`.constraints.plan_for`) depend only
on the mode strings and the contact state. So:

* per pose, once: J_hat^T (contact frames, Jacobian rows; friction edges are J_hat
  columns combined with mu), M_hat, mu (:func:`.dynamics.nondimensional`, cached on the
  scene);
* per (modes, contact state), once per process: the validated, packed plans of every
  requested mode (wildcards expanded), reused by every later pose with that contact
  state;
* per call: one compiled kernel call (:mod:`.kernel`) computing every mode's cone, then
  one :class:`~.cones.Cone` per mode.

Engines. ``"kernel"`` (default when numba can be imported) is the planar float method
compiled; ``"numpy"`` is the reference: :func:`.planar.planar_cone` per mode. Choose with
the ``engine`` argument or the ``WRENCHCONE_ENGINE`` environment variable (``numpy`` or
``kernel``). A mode the kernel declines (nearly parallel acceleration rows, a failed
cone3d self-check) is computed by the reference, which then uses exact arithmetic as
documented in docs/numerics.md. ``exact=True`` and ``method="paper"`` always use the
per-mode reference code.

Errors per mode. ``errors="raise"`` (default) raises the first failing mode's exception,
in the order of ``modes``: :class:`~.modes.ModeSyntaxError` (not a string, unknown
letter, wrong length), :class:`~.modes.ModeError` (a letter the contact state does not
allow, or a "c" at a free fixel) -- exactly what :func:`~.api.wrench_cone` raises for
that mode. ``errors="return"`` puts the exception object in that mode's place instead,
so one bad mode does not sink the batch. An unknown ``method`` or ``engine`` is a
ValueError for the whole call either way.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from . import stats
from .budget import check_time_budget
from .cones import Cone, assembled_cone, infeasible_float_cone
from .constraints import plan_for
from .dynamics import float_rows, problem
from .engines import ENGINE_ENV, ENGINES, kernel_module, kernel_unavailable, resolve_engine
from .methods import method_name, reference_cone
from .modes import ModeError, expand_mode, is_wildcard, parse_mode
from .planar import PLANAR_FALLBACKS, planar_cone
from .scene import Scene, default_scene
from .unions import union_of

#: How many cones each engine produced (kernel), and how many the kernel declined (then
#: the reference computed them: counted in planar.PLANAR_FALLBACKS as usual). The
#: counter lives in :mod:`.stats`.
KERNEL_STATS = stats.KERNEL_STATS


def warm_up() -> float:
    """Load (or compile, the first time on a machine) the kernel; returns seconds taken.
    The node calls this at start so that the first pose is not the one that pays. It
    runs the real engine on the paper's disc, so that exactly the compiled signatures
    real calls use are loaded."""
    t0 = time.perf_counter()
    if resolve_engine() == "kernel":
        kernel_cones(default_scene(), ["na", "la", "ss"])
    return time.perf_counter() - t0


# --- plans -----------------------------------------------------------------------------
@dataclass(frozen=True)
class _BatchPlan:
    """Packed Table 2 plans of a list of modes for one contact state."""

    concrete: tuple[str, ...]  # the kernel's modes, in kernel order
    entries: tuple  # per requested mode: ("cone", k) | ("union", mode, ks) | ("error",)
    arrays: tuple  # the packed arrays of kernel.planar_batch


_BATCH_PLANS = stats.BATCH_PLANS  # the caches live in .stats (reset there)
_PLAN_CODES = stats.PLAN_CODES


def plan_code(mode: str, in_contact: tuple[bool, ...], inters: tuple | None = None
              ) -> np.ndarray | None:
    """:func:`.constraints.plan_for` as the kernel's int64 code (cached, any pose):
    [ki, ke, kf, ineq rows, signs, strict flags, eq rows, loaded fixels, edge signs].
    ``mode`` may contain '?' (a relaxation of .classify, given by ``inters``). With
    ``inters=None`` returns the cached code or None."""
    key = (mode, in_contact)
    code = _PLAN_CODES.get(key)
    if code is None and inters is not None:
        ineq, direction, strict, eq, f_idx, f_sgn = plan_for(mode, in_contact, inters)
        code = np.array([len(ineq), len(eq), len(f_idx), *ineq,
                         *np.asarray(direction).reshape(-1).tolist(),
                         *np.asarray(strict, dtype=int).tolist(), *eq, *f_idx,
                         *np.asarray(f_sgn, dtype=int).tolist()], dtype=np.int64)
        stats.remember(_PLAN_CODES, key, code)
    return code


def pack(codes: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(ptr, code): several :func:`plan_code` packed for kernel.planar_batch."""
    ptr = np.zeros(len(codes) + 1, dtype=np.int64)
    if not codes:
        return ptr, np.zeros(0, dtype=np.int64)
    np.cumsum([c.shape[0] for c in codes], out=ptr[1:])
    return ptr, np.concatenate(codes)


def batch_plan(modes: tuple, in_contact: tuple[bool, ...]) -> _BatchPlan:
    """The packed plans of ``modes`` (cached per modes and contact state, any pose)."""
    key = (modes, in_contact)
    plan = _BATCH_PLANS.get(key)
    if plan is not None:
        return plan
    concrete: list[str] = []
    index: dict[str, int] = {}
    plans: list[tuple] = []
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
    plan = _BatchPlan(tuple(concrete), tuple(entries), pack(plans))
    if any(e[0] == "error" for e in entries):
        # not kept: a refused mode is cheap to refuse again, and a client sending many
        # distinct malformed modes (each up to max_mode_length letters) must not fill
        # the cache with them
        return plan
    return stats.remember(_BATCH_PLANS, key, plan, stats.BATCH_PLAN_CACHE_LIMIT)


def pose_arrays(scene: Scene) -> tuple[np.ndarray, float, np.ndarray]:
    """J_hat^T (2n x 3, contiguous), kappa and mu of a scene: computed once per scene."""
    cache = scene.__dict__.get("_pose_arrays")
    if cache is None:
        cache = scene.__dict__["_pose_arrays"] = float_rows(scene)
    return cache


# --- the engine ---------------------------------------------------------------------------
def _mode_error(scene: Scene, mode) -> Exception:
    """The exception wrench_cone raises for an invalid mode (with gaps in the message)."""
    try:
        if is_wildcard(mode):
            expand_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)
        else:
            parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)
    except ModeError as exc:
        return exc
    raise AssertionError(f"mode {mode!r} was refused by the plan but parses")  # not reached


def kernel_cones(scene: Scene, modes: Sequence[str]) -> list[Cone]:
    """The cones of valid concrete ``modes`` (no wildcards) from one kernel call; modes
    the kernel declines are computed by the reference. Raises ModeError like
    :func:`wrench_cones`."""
    plan = batch_plan(tuple(modes), scene.in_contact)
    for entry, mode in zip(plan.entries, modes):
        if entry[0] != "cone":
            raise _mode_error(scene, mode) if entry[0] == "error" else ValueError(
                "kernel_cones takes concrete modes only")
    return _run(scene, plan)


def kernel_cone(scene: Scene, mode: str):
    """``wrench_cones(scene, [mode], engine="kernel")[0]`` without the list handling:
    the single-cone path of :func:`~.api.wrench_cone`."""
    plan = batch_plan((mode,), scene.in_contact)
    entry = plan.entries[0]
    if entry[0] == "error":
        raise _mode_error(scene, mode)
    cones = cones_from_codes(scene, plan.concrete, plan.arrays)
    return cones[0] if entry[0] == "cone" else union_of(mode, cones)


def run_kernel(scene: Scene, arrays: tuple):
    """kernel.planar_batch on the scene's pose arrays and packed plans: (status,
    feasible, counts, rows) per mode."""
    A, kappa, mu = pose_arrays(scene)
    return kernel_module().planar_batch(A, kappa, mu, *arrays)


def _run(scene: Scene, plan: _BatchPlan) -> list[Cone]:
    """One kernel call for plan.concrete; the reference for declined modes."""
    return cones_from_codes(scene, plan.concrete, plan.arrays)


def cones_from_codes(scene: Scene, modes: Sequence[str], arrays: tuple) -> list[Cone]:
    """The cones of valid concrete ``modes`` whose packed plans are ``arrays`` (one kernel
    call; the reference for declined modes)."""
    if not len(modes):
        return []
    check_time_budget()
    status, feas, counts, rows = run_kernel(scene, arrays)
    L = float(scene.length_scale)
    out: list[Cone] = []
    n_ok = 0
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
                              "planar")
        out.append(cone if fe else infeasible_float_cone(cone))
    KERNEL_STATS["kernel_cones"] += n_ok
    PLANAR_FALLBACKS["float_cones"] += n_ok
    return out


def wrench_cones(scene: Scene, modes: Sequence[str], *, exact: bool = False,
                 method: str | None = None, engine: str | None = None,
                 errors: str = "raise") -> list:
    """The cone of every mode in ``modes`` for one scene (pose), in the same order.

    Each entry is what ``wrench_cone(scene, mode, exact, method)`` returns: a
    :class:`~.cones.Cone`, or a :class:`~.unions.ConeUnion` for a mode with wildcards.
    ``errors``: "raise" (the first invalid mode's ModeError / ModeSyntaxError, in the
    order of ``modes``) or "return" (the exception object in that mode's place). See the
    module docstring for engines.
    """
    if errors not in ("raise", "return"):
        raise ValueError(f"errors must be 'raise' or 'return', got {errors!r}")
    name = method_name(method)
    modes = list(modes)
    plan = None
    if not exact and name == "planar" and resolve_engine(engine) == "kernel":
        try:
            plan = batch_plan(tuple(modes), scene.in_contact)
        except TypeError:  # an unhashable "mode": the per-mode path words the error
            plan = None
    if plan is None:  # the reference, mode by mode
        out = []
        for mode in modes:
            check_time_budget()
            try:
                out.append(reference_cone(scene, mode, exact=exact, method=name))
            except ModeError as exc:
                if errors == "raise":
                    raise
                out.append(exc)
        return out
    if errors == "raise":
        for mode, entry in zip(modes, plan.entries):
            if entry[0] == "error":
                raise _mode_error(scene, mode)
    cones = _run(scene, plan)
    out = []
    for mode, entry in zip(modes, plan.entries):
        if entry[0] == "cone":
            out.append(cones[entry[1]])
        elif entry[0] == "union":
            out.append(union_of(mode, [cones[k] for k in entry[2]]))
        else:
            out.append(_mode_error(scene, mode))
    return out


__all__ = ["wrench_cones", "kernel_cones", "kernel_cone", "resolve_engine", "warm_up", "KERNEL_STATS",
           "ENGINE_ENV", "ENGINES", "batch_plan", "pose_arrays", "kernel_module", "plan_code",
           "pack", "run_kernel", "cones_from_codes",
           "kernel_unavailable"]
