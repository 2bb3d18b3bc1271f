# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The cones of modes: :func:`wrench_cone` (one mode), :func:`wrench_cones` (all requested
modes of one pose in one pass) and :func:`mode_union`.

A pose (a new :class:`~.scene.Scene`) changes the contact frames, hence J_hat; the
mode's constraints (Table 2 as index lists, :func:`.constraints.plan_for`) depend only
on the mode strings and the contact state. So:

* per pose, once: J_hat^T (contact frames, Jacobian rows; friction edges are J_hat
  columns combined with mu), M_hat, mu (:func:`.dynamics.nondimensional`, cached on the
  scene);
* per (modes, contact state), once per process: the validated plans of every requested
  mode (wildcards expanded, :func:`.engines.batch_plan`), reused by every later pose with
  that contact state;
* per call: one engine call (:meth:`.engines.Engine.cones`) computing every mode's cone.

Methods. :data:`METHODS` names the cone algorithms: ``"planar"``
(:func:`.planar.planar_cone`, the default: the fastest that passes the cross-checks) and
``"paper"`` (:func:`.paper.paper_cone`, the reference implementation of the paper's
algorithm). The float planar method is computed by an engine (:mod:`.engines`: the
compiled kernel or the numpy reference, ``engine=``); ``exact=True`` and
``method="paper"`` always use the per-mode reference code.

Errors per mode. ``errors="raise"`` (default) raises the first failing mode's exception,
in the order of ``modes``: :class:`~.modes.ModeSyntaxError` (not a string, unknown
letter, wrong length), :class:`~.modes.ModeError` (a letter the contact state does not
allow, or a "c" at a free fixel) -- exactly what :func:`wrench_cone` raises for that
mode. ``errors="return"`` puts the exception object in that mode's place instead, so one
bad mode does not sink the batch. An unknown ``method`` or ``engine`` is a ValueError for
the whole call either way.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

from .budget import check_time_budget
from .cones import Cone
from .dynamics import Problem, problem
from .engines import Engine, KernelEngine, batch_plan, default_engine, get_engine
from .modes import ModeError, expand_mode, is_wildcard, parse_mode
from .paper import paper_cone
from .planar import planar_cone
from .scene import Scene
from .scene_yaml import default_scene
from .wrenchset import WrenchSet, union_of, union_over

#: Methods by name. "planar" is the default (fastest that passes the cross-checks);
#: "paper" is the reference implementation of the paper's algorithm.
METHODS: dict[str, Callable[[Problem], Cone]] = {"planar": planar_cone, "paper": paper_cone}
DEFAULT_METHOD = "planar"


def method_name(method: str | None) -> str:
    """The method a call uses (DEFAULT_METHOD for None).

    Parameters
    ----------
    method : str or None
        A name in :data:`METHODS`, or None.

    Returns
    -------
    str
        The method's name.

    Raises
    ------
    ValueError
        For a name not in :data:`METHODS`.
    """
    name = DEFAULT_METHOD if method is None else method
    if name not in METHODS:
        raise ValueError(f"unknown method {name!r}; choose one of {sorted(METHODS)}")
    return name


def reference_cone(scene: Scene, mode: str, exact: bool = False,
                   method: str | None = None) -> Cone | WrenchSet:
    """The cone of ``mode`` by the named method, mode by mode (no engine batch).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        A mode, wildcards allowed.
    exact : bool, optional
        Exact rational arithmetic.
    method : str or None, optional
        A name in :data:`METHODS` (default :data:`DEFAULT_METHOD`).

    Returns
    -------
    Cone or WrenchSet
        A WrenchSet (union of the concrete modes' cones) for a mode with wildcards.

    Raises
    ------
    ModeError, ModeSyntaxError
        For an invalid mode.
    ValueError
        For an unknown method.
    """
    make = METHODS[method_name(method)]
    if is_wildcard(mode):
        return union_over(scene, mode, lambda m: make(problem(scene, m, exact)))
    return make(problem(scene, mode, exact))


def warm_up() -> float:
    """Load (or compile, the first time on a machine) the default engine; returns the
    seconds taken. The node calls this at start so that the first pose is not the one
    that pays. It runs the engine on the paper's disc, so that exactly the compiled
    signatures real calls use are loaded.

    Returns
    -------
    float
        The seconds taken (wall clock).
    """
    t0 = time.perf_counter()
    eng = default_engine()
    cones = eng.cones(default_scene(), ["na", "la", "ss"])
    make = getattr(eng, "cone_checks", None)  # the direction searches' compiled checks
    checks = make(cones) if make is not None else None
    if checks is not None:
        checks.check(np.array([[1.0, 0.0, 0.0]]))
    return time.perf_counter() - t0


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


def _engine_cones(eng: Engine, scene: Scene, plan) -> list[Cone]:
    """The cones of plan.concrete by the engine (the kernel reuses the packed plan)."""
    if isinstance(eng, KernelEngine):
        return eng.planned_cones(scene, plan.concrete, plan.arrays)
    return eng.cones(scene, plan.concrete)


def wrench_cone(scene: Scene, mode: str, exact: bool = False, method: str | None = None,
                engine: str | Engine | None = None) -> Cone | WrenchSet:
    """The cone of wrenches consistent with ``mode`` in ``scene`` (eq. (9) of the paper).

    Parameters
    ----------
    scene : Scene
        The workpiece, fixels, friction and pose.
    mode : str
        One letter per fixel (:data:`.modes.MODE_TABLE`); "c" (l, r or n) and "*" (any
        valid letter) are wildcards.
    exact : bool
        Run the whole computation in rational arithmetic (cddlib GMP) from the scene's
        numbers as written.
    method : str or None
        A name in :data:`METHODS` (default :data:`DEFAULT_METHOD`).
    engine : str, Engine or None
        The engine of the float planar method (:func:`.engines.get_engine`).

    Returns
    -------
    Cone or WrenchSet
        The convex cone of a concrete mode; for a mode with wildcards, the
        :class:`~.wrenchset.WrenchSet` union of its concrete modes' cones.

    Raises
    ------
    ModeError, ModeSyntaxError
        For a mode the contact state does not allow, or a malformed one.
    ValueError
        For an unknown method or engine.
    """
    return wrench_cones(scene, [mode], exact=exact, method=method, engine=engine)[0]


def mode_union(scene: Scene, mode: str, exact: bool = False, method: str | None = None,
               engine: str | Engine | None = None) -> WrenchSet:
    """The union of cones of a mode with wildcards ("c", "*"), each concrete mode's cone
    by :func:`wrench_cone`; a concrete mode gives a union of one cone.

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        A mode, wildcards allowed.
    exact : bool, optional
        Exact rational arithmetic.
    method : str or None, optional
        A name in :data:`METHODS` (default :data:`DEFAULT_METHOD`).
    engine : str, Engine or None, optional
        The engine of the float planar method (:func:`.engines.get_engine`).

    Returns
    -------
    WrenchSet
        Feasible cones as pieces, infeasible modes in ``impossible``.

    Raises
    ------
    ModeError, ModeSyntaxError, ValueError
        As :func:`wrench_cone`.
    """
    return union_over(scene, mode, lambda m: wrench_cone(scene, m, exact=exact,
                                                         method=method, engine=engine))


def wrench_cones(scene: Scene, modes: Sequence[str], *, exact: bool = False,
                 method: str | None = None, engine: str | Engine | None = None,
                 errors: str = "raise") -> list:
    """The cone of every mode in ``modes`` for one scene (pose), in the same order.

    Parameters
    ----------
    scene : Scene
        The workpiece, fixels, friction and pose.
    modes : sequence of str
        The modes (wildcards allowed), in the order of the answers.
    exact, method, engine
        As :func:`wrench_cone`.
    errors : str
        "raise" (the first invalid mode's ModeError / ModeSyntaxError, in the order of
        ``modes``) or "return" (the exception object in that mode's place).

    Returns
    -------
    list
        What ``wrench_cone(scene, mode, exact, method)`` returns for each mode (or the
        exception object, ``errors="return"``).

    Raises
    ------
    ModeError, ModeSyntaxError
        With ``errors="raise"``, for the first invalid mode.
    ValueError
        For an unknown ``errors``, method or engine.
    """
    if errors not in ("raise", "return"):
        raise ValueError(f"errors must be 'raise' or 'return', got {errors!r}")
    name = method_name(method)
    eng = get_engine(engine)
    modes = list(modes)
    plan = None
    if not exact and name == "planar":
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
    cones = _engine_cones(eng, scene, plan)
    out = []
    for mode, entry in zip(modes, plan.entries):
        if entry[0] == "cone":
            out.append(cones[entry[1]])
        elif entry[0] == "union":
            out.append(union_of(mode, [cones[k] for k in entry[2]]))
        else:
            out.append(_mode_error(scene, mode))
    return out


def wrench_sets(scene: Scene, modes: Sequence[str], *, engine: str | Engine | None = None,
                errors: str = "raise") -> list:
    """:func:`wrench_cones` (float, planar method) with every answer a
    :class:`~.wrenchset.WrenchSet`: a concrete mode's cone as a set of one piece, a
    wildcard mode's union as it is.

    Parameters
    ----------
    scene, modes, engine, errors
        As :func:`wrench_cones`.

    Returns
    -------
    list
        A WrenchSet per mode (or, ``errors="return"``, the exception of an invalid one).

    Raises
    ------
    ModeError, ModeSyntaxError, ValueError
        As :func:`wrench_cones`.
    """
    return [WrenchSet.of(c) if isinstance(c, Cone) else c
            for c in wrench_cones(scene, modes, engine=engine, errors=errors)]


__all__ = ["DEFAULT_METHOD", "METHODS", "method_name", "reference_cone", "wrench_cone",
           "wrench_cones", "wrench_sets", "mode_union", "warm_up"]
