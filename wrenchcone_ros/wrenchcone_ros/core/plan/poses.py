# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Poses near contact: simulated poses put back onto their contacts, and near-seated poses.

One Gauss-Newton solve (:func:`solve_pose`) serves both: minimum-norm steps in
(x, y, L theta) on the gaps of chosen fixels (the gap of fixel i changes by n_i . dq at
its closest point q, :attr:`~.scene.Scene.contact_arrays`) until every gap is within
GAP_CONVERGENCE of the scene's contact tolerance of its goal. Pure geometry: no engine.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ..geometry import SceneError
from ..scene import Scene
from ..tolerances import SIM_SLOP

#: Dimensionless (a fraction of the scene's contact tolerance): how close to its goal
#: every gap must come when a pose is solved onto contacts (:func:`solve_pose`).
GAP_CONVERGENCE: float = 1e-3

#: Dimensionless (times L): the overlap an iterate of :func:`project_pose` may have with
#: a fixel. The engine's poses overlap by up to its collision slop (SIM_SLOP L) at rest,
#: and by up to one step's travel at an impact (a disc rolled onto a pin at speed:
#: about 0.5 mm for L = 40 mm): 100 times the slop.
PROJECTION_SLACK: float = 100.0 * SIM_SLOP


def solve_pose(scene: Scene, pose, fixels: Sequence[int], goals: Sequence[float],
               slack: float, iterations: int = 30) -> tuple[float, float, float] | None:
    """The pose nearest ``pose`` at which fixel ``fixels[k]`` (0-based) has gap
    ``goals[k]`` (m), by Gauss-Newton (module docstring); None when it does not converge
    within ``iterations`` or an iterate overlaps a fixel by more than ``slack`` (m).

    Parameters
    ----------
    scene : Scene
        The scene.
    pose : tuple of 3 float
        The start (x m, y m, theta rad).
    fixels : sequence of int
        The fixels whose gaps are set (0-based).
    goals : sequence of float
        Their gaps (m).
    slack : float
        The largest overlap of an iterate with a fixel (m).
    iterations : int, optional
        The most Gauss-Newton steps.

    Returns
    -------
    tuple of 3 float or None
        The pose, or None.
    """
    L = scene.length_scale
    tol = GAP_CONVERGENCE * scene.effective_contact_tolerance
    try:
        loose = replace(scene, contact_tolerance=max(scene.contact_tolerance, slack))
    except SceneError:  # a tolerance that large puts a point fixel on a vertex
        return None
    goal = np.asarray(goals, dtype=float)
    x, y, th = (float(v) for v in pose)
    if not fixels:
        return (x, y, th)
    for _ in range(iterations):
        try:
            ca = loose.with_pose(x, y, th).contact_arrays
        except SceneError:
            return None
        res = np.array([ca.gap[i] for i in fixels]) - goal
        if np.max(np.abs(res)) <= tol:
            return (x, y, th)
        rows = [[ca.n[i][0], ca.n[i][1],
                 ((ca.p[i][0] - x) * ca.n[i][1] - (ca.p[i][1] - y) * ca.n[i][0]) / L]
                for i in fixels]
        d = np.linalg.lstsq(np.array(rows), -res, rcond=None)[0]
        x, y, th = x + float(d[0]), y + float(d[1]), th + float(d[2]) / L
    return None


def project_pose(scene: Scene, pose, fixels: Sequence[int]
                 ) -> tuple[float, float, float] | None:
    """The pose nearest ``pose`` (a simulated one) at which every fixel in ``fixels``
    (0-based) touches the workpiece exactly (:func:`solve_pose`, goals 0).

    Parameters
    ----------
    scene : Scene
        The scene.
    pose : tuple of 3 float
        A simulated pose (x m, y m, theta rad).
    fixels : sequence of int
        The fixels in contact (0-based).

    Returns
    -------
    tuple of 3 float or None
        The pose, or None when the solve does not converge.
    """
    return solve_pose(scene, pose, fixels, [0.0] * len(fixels),
                      PROJECTION_SLACK * scene.length_scale)


def lifted_scene(scene: Scene, missing: int, keep: Sequence[int], lift: float
                 ) -> Scene | None:
    """The scene with the part lifted by ``lift`` (m) off fixel ``missing`` while every
    fixel in ``keep`` still touches it (all 0-based), or None when no such pose exists
    nearby (the kept contacts leave no motion that lifts it, or a fixel penetrates):
    :func:`solve_pose` from the scene's pose, the iterates allowed to overlap by up to
    four times the lift.

    Parameters
    ----------
    scene : Scene
        The seated scene.
    missing : int
        The fixel lifted off (0-based).
    keep : sequence of int
        The fixels that keep touching (0-based).
    lift : float
        The gap at ``missing`` (m).

    Returns
    -------
    Scene or None
        The lifted scene, or None.
    """
    pose = solve_pose(scene, scene.pose, [*keep, missing], [0.0] * len(keep) + [float(lift)],
                      4.0 * lift)
    if pose is None:
        return None
    try:
        out = scene.with_pose(*pose)
    except SceneError:
        return None
    if not all(out.in_contact[i] for i in keep) or out.in_contact[missing]:
        return None
    return out


def start_scene(scene: Scene, offset) -> Scene | None:
    """The scene with the part at its pose plus ``offset`` (dx m, dy m, dtheta rad), or
    None when a fixel overlaps the part there (not a start).

    Parameters
    ----------
    scene : Scene
        The scene at its nominal start pose.
    offset : sequence of 3 float
        The offset.

    Returns
    -------
    Scene or None
    """
    x, y, th = scene.pose
    try:
        return scene.with_pose(x + offset[0], y + offset[1], th + offset[2])
    except SceneError:
        return None
