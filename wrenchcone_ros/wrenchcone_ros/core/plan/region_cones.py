# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The cones' part of a region certificate: the poses of a box at which the part rests on
a segment's contacts, where the mode analysis decides what the force does
(:func:`check_region_cones`).

A start of the box lifted off its pins falls onto them, and a part arriving at a
segment's entry moves: that is dynamics, which the simulation decides
(:func:`~.region.certify_region`, :mod:`.segment_funnels`). A pose at which the part
rests on the contacts a segment begins with is different: there the paper's cones decide
which contact modes the segment's force is consistent with, for every model of the
uncertainty. Those poses, within a box, are a **slice** of it: a manifold of dimension
3 - rank(J), J the contacts' gap gradients in (x, y, L theta) (and the axes on which the
box has no width). The uniformly drawn
starts of the box almost never land on it (it has no volume); the cones cover it.

For segment k, with its box (segment 1: the start box around the scene's pose; k >= 2:
the pose bounds of its entry region, :attr:`~.results.SegmentFunnel.pose_bounds`, a box
holding every pose of the region) and its start contacts C (the fixels touching at the
segment's planned start pose):

* a moving segment: the slice of the box's poses at rest on exactly C. At each of its
  cover poses the segment's direction must give the segment's mode alone, for every
  model (:func:`~.segments.exclusive_margin` > 0, what the planner asks of a segment's
  start pose). A part at rest there moves in the planned mode, and keeps C as the mode
  says, along the slice: towards the planned start pose, whose path the planner swept,
  or from it.
* the hold segment (the part seated on C): for each target fixel m, the slice of the
  box's poses at rest on C without m, lifted off m: only modes approaching m may be
  consistent, for every model (the funnel condition of
  :func:`~.segments.funnel_checks`, there at FUNNEL_LIFTS, here at every cover pose of
  the box).

**The cover** of a slice (:func:`slice_cover`): the slice's tangent directions at its
reference pose (the segment's planned start pose, which lies on it); a scan over the
tangent coordinates of the box's corners finds where the slice lies in the box; then a
grid of SLICE_GRID values per tangent axis over that part, and on a curve its two ends,
each put onto the contacts (:func:`~.poses.solve_pose`) and kept when it lies in the box
with exactly the slice's contacts. The claim is exactly: the margin is positive at every
cover pose (for every model); between cover poses nothing is proved. The work is
bounded by counts: (SLICE_SCAN + 1) SLICE_GRID ** d poses per slice, d <= 2 (a slice
needs a contact), and 2 SLICE_END_STEPS more on a curve.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..geometry import SceneError
from ..scene import Scene
from .poses import PROJECTION_SLACK, solve_pose
from .results import ConeSlice, Plan, PlanError, RegionCertificate, Segment
from .segments import exclusive_margin

#: Cover values per tangent axis of a slice (an odd number puts one on the reference
#: pose): a curve's cover has at most this many poses, a surface's its square.
SLICE_GRID: int = 17

#: Scan values per cover value and tangent axis: the scan that finds where the slice
#: lies in its box before the cover is laid on it.
SLICE_SCAN: int = 4

#: Bisections that find each end of a curve slice in its box, between the scan's last
#: pose on it and its first one off it (the end found to 2 ** -SLICE_END_STEPS of a scan
#: step).
SLICE_END_STEPS: int = 12

#: Metres (radians on theta): how far outside its box a cover pose may lie and still count
#: as in it (the projection onto the contacts lands on the box's faces to rounding); a box
#: no wider on an axis holds that axis fixed.
SLICE_BOX_SLACK: float = 1e-9


def slice_tangents(scene: Scene, contacts: Sequence[int], fixed: Sequence[int] = ()
                   ) -> np.ndarray:
    """The tangent directions of the slice of poses at rest on ``contacts`` (0-based) at
    the scene's pose: an orthonormal basis (columns) of the null space of the contacts'
    gap gradients in (x, y, L theta), the rows of :func:`~.poses.solve_pose`, and of the
    pose axes in ``fixed`` (a box of half-width 0 on them).

    Parameters
    ----------
    scene : Scene
        The part at a pose on the slice.
    contacts : sequence of int
        The fixels touching (0-based).
    fixed : sequence of int, optional
        Pose axes held (0: x, 1: y, 2: theta).

    Returns
    -------
    numpy.ndarray
        3 x d, d = 3 - rank (0 columns: the contacts fix the pose).
    """
    ca = scene.contact_arrays
    x, y, _ = scene.pose
    L = scene.length_scale
    J = np.array([[ca.n[i][0], ca.n[i][1],
                   ((ca.p[i][0] - x) * ca.n[i][1] - (ca.p[i][1] - y) * ca.n[i][0]) / L]
                  for i in contacts] + [list(np.eye(3)[k]) for k in fixed])
    if not len(J):
        return np.eye(3)
    _, s, vt = np.linalg.svd(J)
    rank = int(np.sum(s > 1e-9 * max(1.0, float(s[0]))))
    return vt[rank:].T


def _on_slice(scene: Scene, guess, contacts: Sequence[int], lo, hi
              ) -> tuple[float, float, float] | None:
    """``guess`` put onto ``contacts`` (:func:`~.poses.solve_pose`), or None when that
    pose is not in the box [lo, hi], a fixel overlaps the part there, or other fixels
    touch than ``contacts``."""
    pose = solve_pose(scene, guess, list(contacts), [0.0] * len(contacts),
                      PROJECTION_SLACK * scene.length_scale)
    if pose is None or not all(a - SLICE_BOX_SLACK <= v <= b + SLICE_BOX_SLACK
                               for v, a, b in zip(pose, lo, hi)):
        return None
    try:
        at = scene.with_pose(*pose)
    except SceneError:  # a fixel overlaps the part: not a rest pose
        return None
    if {i for i, c in enumerate(at.in_contact) if c} != set(contacts):
        return None
    return tuple(float(v) for v in pose)


def slice_fixed(lo, hi) -> tuple[int, ...]:
    """The pose axes on which the box [``lo``, ``hi``] has no width (at most
    SLICE_BOX_SLACK): the slice keeps them."""
    return tuple(k for k in range(3) if hi[k] - lo[k] <= SLICE_BOX_SLACK)


def slice_cover(scene: Scene, reference, contacts: Sequence[int], lo, hi,
                grid: int = SLICE_GRID) -> tuple[list[tuple[float, float, float]], float]:
    """The cover poses of the slice of the box [``lo``, ``hi``] at rest on exactly
    ``contacts`` (0-based), and its grid step.

    The tangent coordinates (m, in (x, y, L theta)) of the box's corners about
    ``reference`` bound a first scan of SLICE_SCAN times ``grid`` values per tangent
    axis; the cover is the grid of ``grid`` values per axis between the smallest and
    the largest coordinates of the scan's poses on the slice, and, on a curve, its two
    ends found to SLICE_END_STEPS bisections between the scan's last pose on the slice
    and its first one off it. Each value is put onto the contacts and kept when it lies
    in the box with exactly ``contacts`` touching.

    Parameters
    ----------
    scene : Scene
        The scene (any pose).
    reference : sequence of 3 float
        A pose on the slice (x m, y m, theta rad): the grid's origin.
    contacts : sequence of int
        The fixels the part rests on (0-based; at least one).
    lo, hi : sequence of 3 float
        The box's corners (m, m, rad).
    grid : int
        Values per tangent axis (>= 1).

    Returns
    -------
    poses : list of tuple of 3 float
        The cover poses (none: no pose of the box rests on exactly ``contacts``).
    step : float
        The grid's step along the slice (m, in (x, y, L theta); 0 for a single value).
    """
    L = scene.length_scale
    ref = np.asarray(reference, dtype=float)
    T = slice_tangents(scene.with_pose(*ref), contacts, slice_fixed(lo, hi))
    d = T.shape[1]
    scale = np.array([1.0, 1.0, L])

    def at(values) -> tuple[float, float, float] | None:
        return _on_slice(scene, ref + (T @ np.asarray(values, dtype=float)) / scale,
                         contacts, lo, hi)

    def points(axes) -> np.ndarray:
        return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(axes))

    if d == 0:
        pose = at(np.zeros(0))
        return ([] if pose is None else [pose]), 0.0
    corners = np.array([[a if bit == 0 else b for bit, a, b in zip(bits, lo, hi)]
                        for bits in np.ndindex(2, 2, 2)])
    coords = ((corners - ref) * scale) @ T  # each corner's tangent coordinates
    scan_axes = [np.linspace(coords[:, k].min(), coords[:, k].max(),
                             max(SLICE_SCAN * grid, 2)) for k in range(d)]
    scan = points(scan_axes)
    valid = [at(v) is not None for v in scan]
    if not any(valid):
        return [], 0.0
    inside = scan[np.array(valid)]
    first, last = inside.min(axis=0), inside.max(axis=0)
    axes = [np.linspace(first[k], last[k], grid) if grid > 1 and last[k] > first[k]
            else np.array([first[k]]) for k in range(d)]
    step = max((float(a[1] - a[0]) for a in axes if len(a) > 1), default=0.0)
    chosen = [at(v) for v in points(axes)]
    if d == 1:  # a curve: its ends, between the scan's last pose on it and the next
        ax = scan_axes[0]
        on = np.array(valid)
        for edge, beyond in ((first[0], -1), (last[0], 1)):
            k = int(np.argmin(np.abs(ax - edge)))
            j = k + beyond
            if not 0 <= j < len(ax) or on[j]:
                continue
            a, b = float(ax[k]), float(ax[j])
            for _ in range(SLICE_END_STEPS):
                mid = 0.5 * (a + b)
                if at([mid]) is None:
                    b = mid
                else:
                    a = mid
            chosen.insert(0 if beyond < 0 else len(chosen), at([a]))
    out: list[tuple[float, float, float]] = []
    for pose in chosen:
        if pose is not None and not any(np.allclose(pose, q, rtol=0.0, atol=1e-12)
                                        for q in out):
            out.append(pose)
    return out, step


def check_slice(scene: Scene, poses: Sequence, margin_at: Callable[[Scene], float]
                ) -> tuple[float | None, tuple | None, int, tuple | None]:
    """The margin at every pose of a slice's cover.

    Parameters
    ----------
    scene : Scene
        The scene (any pose).
    poses : sequence of tuple of 3 float
        The cover poses.
    margin_at : callable
        Scene at a cover pose -> the margin there (dimensionless; > 0: as required).

    Returns
    -------
    worst : float or None
        The smallest margin (None without poses).
    worst_pose : tuple of 3 float or None
        Where.
    failed : int
        Cover poses whose margin is not positive.
    first_failure : tuple of 3 float or None
        The first of them, in the cover's order.
    """
    worst, worst_pose, failed, first = None, None, 0, None
    for pose in poses:
        m = float(margin_at(scene.with_pose(*pose)))
        if worst is None or m < worst:
            worst, worst_pose = m, tuple(pose)
        if not m > 0.0:
            failed += 1
            first = first or tuple(pose)
    return worst, worst_pose, failed, first


def _contacts(scene: Scene, pose) -> tuple[int, ...]:
    return tuple(i for i, c in enumerate(scene.with_pose(*pose).in_contact) if c)


def segment_slices(scene: Scene, plan: Plan, index: int, lo, hi, box: str,
                   grid: int = SLICE_GRID) -> list[ConeSlice]:
    """The cone slices of segment ``index`` (0-based) of ``plan`` in the box [``lo``,
    ``hi``] (module docstring): one for a moving segment, one per target fixel the part
    can be lifted off for the hold segment.

    Parameters
    ----------
    scene : Scene
        The scene (any pose).
    plan : Plan
        A feasible plan.
    index : int
        The segment (0-based).
    lo, hi : sequence of 3 float
        The box (m, m, rad).
    box : str
        The box in words ("the start box", ...).
    grid : int
        Cover values per tangent axis.

    Returns
    -------
    list of ConeSlice
        The slices (none when the segment starts without a contact: nothing rests).
    """
    seg: Segment = plan.segments[index]
    point = plan.actuator.directions_point
    unc = plan.uncertainty
    contacts = _contacts(scene, seg.start_pose)
    out: list[ConeSlice] = []

    def one(kept: tuple[int, ...], lifted: int, requirement: str,
            allowed: Callable[[str], bool]) -> ConeSlice:
        poses, step = slice_cover(scene, seg.start_pose, kept, lo, hi, grid)
        worst, where, failed, first = check_slice(
            scene, poses, lambda s: exclusive_margin(s, allowed, point, unc)[0](
                seg.direction))
        arr = np.array(poses) if poses else np.zeros((0, 3))
        return ConeSlice(
            index + 1, tuple(i + 1 for i in kept), lifted, requirement, box,
            int(slice_tangents(scene.with_pose(*seg.start_pose), kept,
                               slice_fixed(lo, hi)).shape[1]),
            len(poses), grid, step,
            tuple(float(v) for v in arr.min(axis=0)) if poses else (),
            tuple(float(v) for v in arr.max(axis=0)) if poses else (),
            worst, where, failed, first)

    if not contacts:
        return out
    if not seg.hold:
        mode = seg.mode
        out.append(one(contacts, 0, f"mode {mode} alone", lambda m: m == mode))
        return out
    for m in sorted(t - 1 for t in plan.target):
        kept = tuple(i for i in contacts if i != m)
        if m not in contacts or not kept:
            continue
        out.append(one(kept, m + 1, f"only modes approaching fixel {m + 1}",
                       lambda mode, m=m: mode[m] == "a"))
    return out


def check_region_cones(scene: Scene, plan: Plan, certificate: RegionCertificate, *,
                       grid: int = SLICE_GRID) -> RegionCertificate:
    """The certificate with its cone slices: segment 1's in the certified box, each
    later segment's in the pose bounds of its entry region (:mod:`.segment_funnels`;
    none without them).

    Parameters
    ----------
    scene : Scene
        The part at the box's centre pose.
    plan : Plan
        The plan the certificate is of.
    certificate : RegionCertificate
        A certificate with a certified box (unchanged without one).
    grid : int
        Cover values per tangent axis of a slice (>= 1; SLICE_GRID).

    Returns
    -------
    RegionCertificate
        ``certificate`` with its ``cone_slices``.

    Raises
    ------
    PlanError
        ``grid`` is not a whole number >= 1.
    """
    if isinstance(grid, bool) or not isinstance(grid, int) or grid < 1:
        raise PlanError(f"grid must be a whole number >= 1, got {grid!r}")
    box = certificate.certified
    if box is None or not plan.feasible:
        return certificate
    c = np.asarray(scene.pose, dtype=float)
    h = np.asarray(box.half_widths, dtype=float)
    slices = segment_slices(scene, plan, 0, c - h, c + h, "the start box", grid)
    for funnel in certificate.segment_funnels:
        lo, hi = funnel.pose_bounds
        slices += segment_slices(scene, plan, funnel.segment - 1, lo, hi,
                                 f"segment {funnel.segment}'s entry region", grid)
    return replace(certificate, cone_slices=tuple(slices))


__all__ = ["SLICE_GRID", "SLICE_BOX_SLACK", "SLICE_END_STEPS", "SLICE_SCAN", "check_region_cones", "check_slice",
           "segment_slices", "slice_cover", "slice_tangents"]
