# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Animations of a simulated plan (matplotlib.animation; GIF through Pillow, MP4 through
ffmpeg when installed).

Each frame shows the fixture frame (metres): the workpiece's outline at the simulated
pose, the fixels (pins with their radius), the letter the simulation reads at each fixel
(Table 2, coloured as in every other picture of the package), the applied force as an
arrow at its point, and a title with the time, the segment, its planned mode and the
letters observed. matplotlib is imported inside the functions (object-oriented API, no
pyplot), as in :mod:`wrenchcone_ros.core.plot`.

    from wrenchcone_ros.core.animate import animate_plan
    animate_plan(scene, plan, "docs/figures/plan_pawl.gif")

A plan for a region of starts (``plan_seating(..., start_region=...)``) is drawn by
:func:`draw_region` (a PNG: the certified box as the part at its corner poses, each
segment's entry region as the poses at which runs from the box's cover and from sampled
starts enter it, the paths of the sampled starts' centres of mass and where they end)
and animated by :func:`animate_region` (the sampled starts seating together).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dataclasses import dataclass

from .drawing import LETTER_COLOURS, outline
from .plan import Plan, RunResult, TraceFrame, cover, sample_starts, start_scene, trace
from .scene import Scene

#: Frames per second of the animation, and the most frames it may have (the trace is
#: subsampled evenly beyond that, keeping every change of direction).
FPS: int = 15
MAX_FRAMES: int = 90

#: Starts drawn uniformly in the certified box (seeded) whose paths :func:`draw_region`
#: draws and :func:`animate_region` animates.
REGION_PICTURE_STARTS: int = 12

#: Cover points per axis of the certified box whose runs the pictures show (3: the
#: corners, the middles of the edges and faces, and the centre; a subset of the
#: certificate's cover of REGION_GRID = 5, whose values from -1 to 1 include -1, 0, 1).
REGION_PICTURE_GRID: int = 3

#: Colours of the segments' entry regions, in segment order (cycled).
SEGMENT_COLOURS: tuple[str, ...] = ("tab:orange", "tab:green", "tab:purple", "tab:brown",
                                    "tab:pink", "tab:olive")


def _animation_path(path: str | Path) -> Path:
    """``path`` as a Path; ValueError unless it ends in .gif or .mp4."""
    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise ValueError(f"animation file must end in .gif or .mp4, got {str(path)!r}")
    return path


def _save(anim, path: Path, dpi: int) -> Path:
    """Write ``anim`` to ``path`` (a GIF with Pillow, an MP4 with ffmpeg) at FPS."""
    from matplotlib.animation import FFMpegWriter, PillowWriter

    writer = PillowWriter(fps=FPS) if path.suffix.lower() == ".gif" else FFMpegWriter(fps=FPS)
    path.parent.mkdir(parents=True, exist_ok=True)
    anim.save(str(path), writer=writer, dpi=dpi)
    return path


def _frames(frames: list[TraceFrame], limit: int) -> list[TraceFrame]:
    if len(frames) <= limit:
        return frames
    keep = set(np.linspace(0, len(frames) - 1, limit).round().astype(int).tolist())
    keep |= {k for k in range(1, len(frames)) if frames[k].segment != frames[k - 1].segment}
    return [frames[k] for k in sorted(keep)]


def animate_plan(scene: Scene, plan: Plan, path: str | Path,
                 friction: list[float] | None = None, record_every: int = 5,
                 dpi: int = 60) -> Path:
    """Simulate ``plan`` from the scene's pose and write the animation.

    Parameters
    ----------
    scene : Scene
        The part at its start pose.
    plan : Plan
        A plan of ``plan_seating``.
    path : str or Path
        The file, ``.gif`` (Pillow) or ``.mp4`` (ffmpeg).
    friction : list of float, optional
        One mu per fixel (default: the scene's, the nominal model).
    record_every : int
        Simulation steps between recorded frames (at most MAX_FRAMES are kept, and every
        change of segment).
    dpi : int
        Dots per inch.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        A suffix other than .gif or .mp4, or a plan without segments.
    SimulationUnavailable
        pymunk is not installed.
    """
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, FancyArrow, Polygon

    path = _animation_path(path)
    if not plan.segments:
        raise ValueError("the plan has no segments to animate")
    result, frames = trace(scene, plan, friction, record_every=record_every)
    frames = _frames(frames, MAX_FRAMES)
    L = scene.length_scale
    local = _local_outline(scene)
    poses = np.array([f.readout.pose for f in frames])
    outlines = [_posed(local, p) for p in poses]
    pts = np.vstack(outlines + [np.array([f.position for f in scene.fixels])])
    lo, hi = pts.min(axis=0) - 0.35 * L, pts.max(axis=0) + 0.35 * L

    fig = Figure(figsize=(5.0, 4.0))
    ax = fig.add_subplot(1, 1, 1)
    ax.set_aspect("equal")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    body = Polygon(outlines[0][:-1], closed=True, fc=(0.85, 0.85, 0.9), ec="k", lw=1.0)
    ax.add_patch(body)
    labels = []
    for i, fx in enumerate(scene.fixels):
        ax.add_patch(Circle(fx.position, max(fx.radius, 0.03 * L), fc="0.3", ec="k"))
        labels.append(ax.text(fx.position[0], fx.position[1] - 0.12 * L, "", ha="center",
                              va="top", fontsize=11, fontweight="bold"))
        ax.text(fx.position[0] + 0.08 * L, fx.position[1] + 0.05 * L, str(i + 1),
                fontsize=7, color="0.3")
    arrow = [None]
    title = ax.set_title("", fontsize=9)
    point = plan.actuator.application_point(scene)

    def draw(k: int):
        fr = frames[k]
        pose = fr.readout.pose
        body.set_xy(outlines[k][:-1])
        for lab, ch in zip(labels, fr.readout.letters):
            lab.set_text(ch)
            lab.set_color(LETTER_COLOURS[ch])
        c, s = math.cos(pose[2]), math.sin(pose[2])
        px = pose[0] + c * point[0] - s * point[1]
        py = pose[1] + s * point[0] + c * point[1]
        if arrow[0] is not None:
            arrow[0].remove()
        d = 0.5 * L
        arrow[0] = FancyArrow(px, py, d * math.cos(fr.direction), d * math.sin(fr.direction),
                              width=0.02 * L, head_width=0.08 * L, head_length=0.1 * L,
                              color="crimson", length_includes_head=True)
        ax.add_patch(arrow[0])
        seg = plan.segments[min(fr.segment, len(plan.segments) - 1)]
        title.set_text(f"t = {fr.readout.t:.3f} s   segment {fr.segment + 1}: {seg.mode} "
                       f"at {math.degrees(fr.direction):.1f} deg\n"
                       f"observed {fr.readout.letters}"
                       + ("   (seated)" if seg.hold else ""))
        return [body, title, arrow[0], *labels]

    return _save(FuncAnimation(fig, draw, frames=len(frames), blit=False), path, dpi)


@dataclass(frozen=True)
class RegionRun:
    """One run of a region's picture: its start pose, the engine's result and the
    recorded frames.

    Parameters
    ----------
    start : tuple of 3 float
        The start pose (x m, y m, theta rad).
    result : RunResult
        The run (its ``final_pose`` where the engine left the part).
    frames : list of TraceFrame
        The recorded frames, the last one the final state.
    cover : bool
        True for a point of the certified box's cover, False for a drawn start.
    """

    start: tuple[float, float, float]
    result: RunResult
    frames: list
    cover: bool


@dataclass(frozen=True)
class RegionDrawing:
    """What :func:`draw_region` drew: the file, the runs, each drawn start's path of its
    centre of mass (world frame, m; the last point where the engine left it) and each
    segment's entry poses, and the figure.

    Parameters
    ----------
    path : Path
        The file written.
    runs : tuple of RegionRun
        The runs (cover points first, then the drawn starts).
    paths : tuple of numpy.ndarray
        One (k, 2) array per drawn start, m.
    entries : tuple of numpy.ndarray
        Per segment, the (n, 3) poses (x m, y m, theta rad) at which the runs entered it.
    figure : matplotlib.figure.Figure
        The figure (its axes hold the paths as lines with gid ``"path"``).
    """

    path: Path
    runs: tuple
    paths: tuple
    entries: tuple
    figure: object


def _com(scene: Scene, pose) -> tuple[float, float]:
    """The centre of mass (world frame, m) of the workpiece at ``pose``."""
    cx, cy = scene.workpiece.com
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return (pose[0] + c * cx - s * cy, pose[1] + s * cx + c * cy)


def region_runs(scene: Scene, plan: Plan, starts: int = REGION_PICTURE_STARTS,
                seed: int = 0, grid: int | None = REGION_PICTURE_GRID,
                record_every: int = 5) -> list[RegionRun]:
    """The runs a region's pictures show, in the nominal model: from every start of a
    cover of the plan's certified box (``grid`` points per axis) and from ``starts``
    starts drawn uniformly in it (seeded).

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose.
    plan : Plan
        A plan with a certified start region (``plan.start_region``).
    starts : int
        Starts drawn in the box.
    seed : int
        Their seed.
    grid : int, optional
        Cover points per axis (REGION_PICTURE_GRID; None: the certificate's).
    record_every : int
        Simulation steps between recorded frames.

    Returns
    -------
    list of RegionRun
        The cover's runs, then the drawn starts'.

    Raises
    ------
    ValueError
        A plan without a certified start region.
    SimulationUnavailable
        pymunk is not installed.
    """
    box = plan.start_region
    if box is None or not plan.segments:
        raise ValueError("the plan has no certified start region to draw (plan with "
                         "start_region=...; none holds when not even the scene's pose "
                         "seats the part)")
    n = plan.region.grid if grid is None else grid
    poses = [(tuple(s.pose), True) for s in (start_scene(scene, off) for off in
                                             cover(box, n)) if s is not None]
    poses += [(p, False) for p in sample_starts(scene, box, starts, seed)]
    out = []
    for pose, is_cover in poses:
        result, frames = trace(scene.with_pose(*pose), plan, None, record_every=record_every)
        out.append(RegionRun(tuple(pose), result, frames, is_cover))
    return out


def _entries(runs: list[RegionRun], segments: int) -> list[np.ndarray]:
    """Per segment, the poses at which the runs entered it (the first frame of it)."""
    out = []
    for k in range(segments):
        poses = []
        for r in runs:
            fr = next((f for f in r.frames if f.segment == k), None)
            if fr is not None:
                poses.append(fr.readout.pose)
        out.append(np.array(poses, dtype=float).reshape(-1, 3))
    return out


def draw_region(scene: Scene, plan: Plan, path: str | Path,
                starts: int = REGION_PICTURE_STARTS, seed: int = 0,
                runs: list[RegionRun] | None = None, dpi: int = 100) -> RegionDrawing:
    """A picture of a plan for a region of starts, two panels: the scene, and its
    centres of mass enlarged. The fixels; the part at the region's
    centre (filled) and at the corners of the certified box (grey outlines); for each
    segment, its entry region, the centres of mass at which the runs from the box's
    cover and from ``starts`` drawn starts entered it (dots, their convex hull shaded,
    the range of angles in the legend); the paths of the drawn starts' centres of mass
    (thin lines) and where the engine left them (crosses); the part where the nominal
    run from the centre ends (blue outline). Runs in the nominal model.

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose.
    plan : Plan
        A plan with a certified start region.
    path : str or Path
        The file (.png, .svg or .pdf).
    starts : int
        Starts drawn in the certified box whose paths are drawn.
    seed : int
        Their seed.
    runs : list of RegionRun, optional
        The runs (:func:`region_runs`), when made already.
    dpi : int
        Dots per inch.

    Returns
    -------
    RegionDrawing
        What was drawn.

    Raises
    ------
    ValueError
        A plan without a certified start region, or another file format.
    SimulationUnavailable
        pymunk is not installed.
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Polygon

    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise ValueError(f"picture file must end in .png, .svg or .pdf, got {str(path)!r}")
    if runs is None:
        runs = region_runs(scene, plan, starts, seed)
    box = plan.start_region
    L = scene.length_scale
    local = _local_outline(scene)
    fig = Figure(figsize=(11.0, 6.2))
    ax = fig.add_subplot(1, 2, 1)
    zoom = fig.add_subplot(1, 2, 2)
    for a in (ax, zoom):
        a.set_aspect("equal")
        a.set_xlabel("x (m)")
        a.set_ylabel("y (m)")
    pts = [np.array([f.position for f in scene.fixels])]
    ax.add_patch(Polygon(_posed(local, scene.pose)[:-1], closed=True, fc=(0.85, 0.85, 0.9),
                         ec="0.4", lw=0.8, label="the part at the region's centre"))
    x0, y0, t0 = scene.pose
    first = True
    for sx in (-1, 1):
        for sy in (-1, 1):
            for st in (-1, 1):
                pose = (x0 + sx * box.dx, y0 + sy * box.dy, t0 + st * box.dtheta)
                o = _posed(local, pose)
                pts.append(o)
                ax.plot(o[:, 0], o[:, 1], color="0.6", lw=0.5, ls="--",
                        label="corners of the certified box" if first else None)
                first = False
    entries = _entries(runs, len(plan.segments))
    drawn = [r for r in runs if not r.cover]
    paths = [np.array([_com(scene, f.readout.pose) for f in r.frames]
                      + [_com(scene, r.result.final_pose)]) for r in drawn]
    coms = []
    for a, labelled in ((ax, True), (zoom, False)):
        for k, (seg, poses) in enumerate(zip(plan.segments, entries)):
            if not len(poses):
                continue
            col = SEGMENT_COLOURS[k % len(SEGMENT_COLOURS)]
            c = np.array([_com(scene, p) for p in poses])
            lo, hi = np.degrees(poses[:, 2].min()), np.degrees(poses[:, 2].max())
            a.scatter(c[:, 0], c[:, 1], s=9, color=col, zorder=4, label=(
                f"segment {k + 1} ({seg.mode} at {math.degrees(seg.direction):.1f} deg): "
                f"its entry region, {len(poses)} poses, theta {lo:.1f}..{hi:.1f} deg"
                if labelled else None))
            hull = _hull(c)
            if len(hull) >= 3:
                a.add_patch(Polygon(hull, closed=True, fc=col, ec=col, alpha=0.2, zorder=3))
            coms.append(c)
        for j, (r, xy) in enumerate(zip(drawn, paths)):
            a.plot(xy[:, 0], xy[:, 1], color="tab:red" if r.result.success else "k", lw=0.7,
                   gid="path", label="paths of the drawn starts' centres of mass (red: "
                   "seated)" if j == 0 and labelled else None)
            a.plot(xy[-1, 0], xy[-1, 1], "x", color="tab:red", ms=5,
                   label="where the engine left them" if j == 0 and labelled else None)
    pts += paths + coms
    centre = next((r for r in runs if r.cover and r.start == tuple(scene.pose)), None)
    if centre is not None:
        o = _posed(local, centre.result.final_pose)
        ax.plot(o[:, 0], o[:, 1], color="tab:blue", lw=1.2,
                label="seated (the nominal run from the centre)")
    for i, fx in enumerate(scene.fixels):
        ax.add_patch(Circle(fx.position, max(fx.radius, 0.03 * L), fc="0.3", ec="k",
                            zorder=5))
        ax.text(fx.position[0] + 0.08 * L, fx.position[1] + 0.05 * L, str(i + 1),
                fontsize=7, color="0.3")
    allp = np.vstack(pts)
    lo, hi = allp.min(axis=0) - 0.2 * L, allp.max(axis=0) + 0.2 * L
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    near = np.vstack(paths + coms)
    mid, half = (near.max(axis=0) + near.min(axis=0)) / 2, (
        near.max(axis=0) - near.min(axis=0)).max() / 2 * 1.15 + 0.02 * L
    zoom.set_xlim(mid[0] - half, mid[0] + half)
    zoom.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_title("the scene", fontsize=9)
    zoom.set_title("the centres of mass, enlarged", fontsize=9)
    seated = sum(r.result.success for r in runs)
    fig.suptitle(f"start region {box.text()} certified\n{len(runs)} nominal runs "
                 f"({len(runs) - len(drawn)} from cover points, {len(drawn)} from drawn "
                 f"starts), {seated} seated", fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", fontsize=8, ncol=2,
               frameon=False)
    fig.subplots_adjust(bottom=0.24, top=0.86, wspace=0.3)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(str(path), dpi=dpi)
    return RegionDrawing(path, tuple(runs), tuple(paths), tuple(entries), fig)


def _hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2-D points (monotone chain), counter-clockwise."""
    pts = sorted(set(map(tuple, np.round(points, 12))))
    if len(pts) < 3:
        return np.array(pts)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


def animate_region(scene: Scene, plan: Plan, path: str | Path,
                   starts: int = REGION_PICTURE_STARTS, seed: int = 0,
                   runs: list[RegionRun] | None = None, dpi: int = 60,
                   frames: int = MAX_FRAMES) -> Path:
    """An animation of starts drawn in a plan's certified start region seating
    together (nominal model): each frame shows the part at every start's pose at that
    time (one colour per start), the fixels, and the time and the segments the runs are
    in; a run that has ended stays at its final pose.

    Parameters
    ----------
    scene : Scene
        The part at the region's centre pose.
    plan : Plan
        A plan with a certified start region.
    path : str or Path
        The file, ``.gif`` (Pillow) or ``.mp4`` (ffmpeg).
    starts : int
        Starts drawn in the certified box.
    seed : int
        Their seed.
    runs : list of RegionRun, optional
        The runs (:func:`region_runs`); only the drawn starts are animated.
    dpi : int
        Dots per inch.
    frames : int
        Frames, evenly spaced in time from 0 to the end of the longest run (>= 2).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        A suffix other than .gif or .mp4, or a plan without a certified start region.
    SimulationUnavailable
        pymunk is not installed.
    """
    from matplotlib import colormaps
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, Polygon

    path = _animation_path(path)
    if runs is None:
        runs = region_runs(scene, plan, starts, seed, grid=1)
    drawn = [r for r in runs if not r.cover] or list(runs)
    end = max(r.frames[-1].readout.t for r in drawn)
    times = np.linspace(0.0, end, max(int(frames), 2))
    L = scene.length_scale
    local = _local_outline(scene)

    def at(r: RegionRun, t: float) -> TraceFrame:
        k = max(0, int(np.searchsorted([f.readout.t for f in r.frames], t, "right")) - 1)
        return r.frames[k]

    shown = [[at(r, t) for r in drawn] for t in times]
    outlines = [[_posed(local, f.readout.pose) for f in row] for row in shown]
    pts = np.vstack([o for row in outlines for o in row]
                    + [np.array([f.position for f in scene.fixels])])
    lo, hi = pts.min(axis=0) - 0.25 * L, pts.max(axis=0) + 0.25 * L
    fig = Figure(figsize=(5.0, 4.0))
    ax = fig.add_subplot(1, 1, 1)
    ax.set_aspect("equal")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    cmap = colormaps["viridis"]
    bodies = [Polygon(outlines[0][j][:-1], closed=True, fc=cmap(j / max(len(drawn) - 1, 1)),
                      ec="k", lw=0.5, alpha=0.35) for j in range(len(drawn))]
    for b in bodies:
        ax.add_patch(b)
    for fx in scene.fixels:
        ax.add_patch(Circle(fx.position, max(fx.radius, 0.03 * L), fc="0.3", ec="k"))
    title = ax.set_title("", fontsize=9)
    seated = sum(r.result.success for r in drawn)

    def draw(k: int):
        for b, o in zip(bodies, outlines[k]):
            b.set_xy(o[:-1])
        segs = sorted({f.segment + 1 for f in shown[k]})
        title.set_text(f"t = {times[k]:.3f} s   {len(drawn)} starts in "
                       f"{plan.start_region.text()}\nsegments {segs}; "
                       f"{seated} of {len(drawn)} seated at the end")
        return [*bodies, title]

    return _save(FuncAnimation(fig, draw, frames=len(times), blit=False), path, dpi)


def _local_outline(scene: Scene) -> np.ndarray:
    """The workpiece's outline (:func:`.drawing.outline`) in the workpiece frame."""
    x, y, th = scene.pose
    c, s = math.cos(th), math.sin(th)
    w = outline(scene) - np.array([x, y])
    return np.column_stack([c * w[:, 0] + s * w[:, 1], -s * w[:, 0] + c * w[:, 1]])


def _posed(local: np.ndarray, pose) -> np.ndarray:
    """The outline at a simulated pose (x, y, theta), world frame."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    return np.column_stack([x + c * local[:, 0] - s * local[:, 1],
                            y + s * local[:, 0] + c * local[:, 1]])


__all__ = ["FPS", "MAX_FRAMES", "REGION_PICTURE_GRID", "REGION_PICTURE_STARTS", "RegionDrawing", "RegionRun",
           "SEGMENT_COLOURS", "animate_plan", "animate_region", "draw_region", "region_runs"]
