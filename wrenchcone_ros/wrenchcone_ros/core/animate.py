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
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .drawing import LETTER_COLOURS, outline
from .plan import Plan, TraceFrame, trace
from .scene import Scene

#: Frames per second of the animation, and the most frames it may have (the trace is
#: subsampled evenly beyond that, keeping every change of direction).
FPS: int = 15
MAX_FRAMES: int = 90


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
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle, FancyArrow, Polygon

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"animation file must end in .gif or .mp4, got {str(path)!r}")
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

    anim = FuncAnimation(fig, draw, frames=len(frames), blit=False)
    writer = PillowWriter(fps=FPS) if suffix == ".gif" else FFMpegWriter(fps=FPS)
    path.parent.mkdir(parents=True, exist_ok=True)
    anim.save(str(path), writer=writer, dpi=dpi)
    return path


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


__all__ = ["animate_plan", "FPS", "MAX_FRAMES"]
