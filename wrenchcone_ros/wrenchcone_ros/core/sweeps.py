# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Sweeps: the force directions that give a contact mode at every pose of a path, their
intersection, and the first pose where the mode stops (:func:`sweep`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from .classify import ModeMatch, consistent_modes
from .directions import (
    DirectionInterval,
    _angle,
    _arcs,
    _arcs_to_angles,
    _intervals,
    _request,
    force_basis,
)
from .modes import ModeError
from .geometry import SceneError
from .scene import Scene
from .uncertainty import Uncertainty, as_uncertainty
from .wrenchset import Guarantee


# --- sweeps along a path ----------------------------------------------------------------
@dataclass(frozen=True)
class SweepResult:
    """:func:`.directions.force_directions` along a path of poses.

    ``intervals[k]``: the intervals at pose k, None from ``stop`` on. ``stop``: the first
    pose where the mode is not valid any more (its letters do not fit the contact state,
    ``stop_reason`` says why) or has no direction; None when it holds along the whole
    path. ``common``: the directions valid at every pose before ``stop`` (their
    intersection; ``best`` maximises the smallest margin over those poses).
    ``after``: when ``stop`` is a pose with a valid scene and ``common`` is not empty, the
    modes the force along ``common[0].best`` is consistent with at that pose.

    Parameters
    ----------
    mode : str
        The mode swept.
    poses : tuple of tuple of 3 float
        The path (x m, y m, theta rad).
    intervals : tuple
        Per pose, its intervals, or None from ``stop`` on.
    common : tuple of DirectionInterval
        The directions valid at every pose before ``stop``.
    stop : int or None
        The first pose where the mode stops being valid or has no direction.
    stop_reason : str
        Why (empty when ``stop`` is None).
    after : tuple of ModeMatch, optional
        The modes at ``stop`` of the force along ``common[0].best``.
    """

    mode: str
    poses: tuple[tuple[float, float, float], ...]
    intervals: tuple[tuple[DirectionInterval, ...] | None, ...]
    common: tuple[DirectionInterval, ...]
    stop: int | None
    stop_reason: str
    after: tuple[ModeMatch, ...] = ()


def _pose(p, k: int) -> tuple[float, float, float]:
    if isinstance(p, (str, bytes)) or not isinstance(p, Sequence) or len(p) != 3:
        raise ValueError(f"pose {k} must be [x m, y m, theta rad], got {p!r}")
    out = tuple(float(v) for v in p)
    if not all(math.isfinite(v) for v in out):
        raise ValueError(f"pose {k} must be finite, got {list(p)}")
    return out


def _in_intervals(phi: float, ivs: Sequence[DirectionInterval]) -> bool:
    return any(iv.contains(phi) for iv in ivs)


def common_directions(per: Sequence[Sequence[DirectionInterval]],
                      margin: Callable[[float], float], guarantee: Guarantee | None = None
                      ) -> list[DirectionInterval]:
    """The directions that lie in an interval of every list of ``per`` (the intersection
    of their unions), as intervals whose ``best`` and ``margin`` maximise ``margin``.

    Parameters
    ----------
    per : sequence of sequence of DirectionInterval
        The intervals at each pose.
    margin : callable
        The margin of a direction (rad -> dimensionless).
    guarantee : Guarantee or None, optional
        The guarantee the intervals carry.

    Returns
    -------
    list of DirectionInterval
        The intersection.
    """
    dirs = [(math.cos(a), math.sin(a)) for ivs in per for iv in ivs for a in (iv.lo, iv.hi)]

    def member(d) -> bool:
        phi = _angle(d)
        return all(_in_intervals(phi, ivs) for ivs in per)

    return _intervals(_arcs_to_angles(_arcs(dirs, member, False)), margin, guarantee)


def sweep(scene: Scene, poses: Sequence[Sequence[float]], mode: str,
          point: Sequence[float] | None = None, exclusive: bool = False,
          uncertainty: Uncertainty | None = None) -> SweepResult:
    """:func:`.directions.force_directions` at every pose (x m, y m, theta rad) of a path, their
    intersection, and the first pose where ``mode`` stops being valid (:class:`SweepResult`).

    A pose where a fixel penetrates the workpiece is an input error (SceneError naming
    the pose). ``uncertainty``: robust directions at every pose (:func:`.directions.force_directions`);
    ``after`` then lists the robust matches (certain / possible) at the stop.

    Parameters
    ----------
    scene : Scene
        The scene (its pose is replaced by each of ``poses``).
    poses : sequence of sequence of 3 float
        The path.
    mode : str
        The mode, wildcards allowed.
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    exclusive : bool, optional
        Only directions consistent with no other mode.
    uncertainty : Uncertainty or None, optional
        The model set (None: the nominal model).

    Returns
    -------
    SweepResult
        The sweep.

    Raises
    ------
    SceneError
        A fixel penetrates the workpiece at a pose.
    ValueError
        No pose, or a pose that is not three finite numbers.
    """
    poses = tuple(_pose(p, k) for k, p in enumerate(poses))
    if not poses:
        raise ValueError("poses must be a non-empty list of [x, y, theta]")
    uncertainty = as_uncertainty(uncertainty)
    scenes, reqs, per = [], [], []
    stop, reason = None, ""
    for k, pose in enumerate(poses):
        try:
            sc = scene.with_pose(*pose)
        except SceneError as exc:
            raise SceneError(f"pose {k} {list(pose)}: {exc}") from None
        scenes.append(sc)
        try:
            req = _request(sc, mode, point, exclusive, False, None, uncertainty)
        except ModeError as exc:
            stop, reason = k, str(exc)
            break
        arcs = _arcs(req.breakpoints(), req.member, False, req.members)
        ivs = _intervals(_arcs_to_angles(arcs), req.margin, req.guarantee, req.margins)
        if not ivs:
            stop, reason = k, f"no force direction at pose {k} is consistent with {mode!r}"
            break
        reqs.append(req)
        per.append(tuple(ivs))
    common: list[DirectionInterval] = []
    if per:
        def margin(phi: float) -> float:
            return min(r.margin(phi) for r in reqs)

        common = common_directions(per, margin, reqs[0].guarantee)
    after: tuple[ModeMatch, ...] = ()
    if stop is not None and common:
        g = force_basis(scenes[stop], point) @ np.array(
            [math.cos(common[0].best), math.sin(common[0].best)])
        after = tuple(consistent_modes(scenes[stop], g, uncertainty=uncertainty,
                                       frame="com" if point is None else "nominal"))
    intervals = tuple(per) + (None,) * (len(poses) - len(per))
    return SweepResult(mode, poses, intervals, tuple(common), stop, reason, after)


__all__ = ["SweepResult", "common_directions", "sweep"]
