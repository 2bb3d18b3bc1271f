# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A recorded run replayed through the core: the cone at every recorded pose.

For every tilt command of the run (:func:`replay`):

* the pose it was computed from: the recorded pose whose stamp is the command's stamp
  (the loop's controller stamps each command with its pose's stamp), else the last pose
  recorded before it; the fixels last recorded before it (their radii and friction from
  the scene);
* the wrench of the command: m a (cos phi, sin phi) at the centre of mass, torque 0
  (a tray's pull; m the scene's mass, a the magnitude, phi the direction);
* the cone of ``mode`` at that pose (:func:`wrenchcone_ros.core.wrench_cone`) and the
  command's margin in it (dimensionless, positive inside), or why there is none (the
  pose makes no valid scene, the mode's letters contradict the contacts there);
* the letters recorded nearest before it (the simulator's truth) and the modes the core
  finds the command consistent with at that pose (:func:`~wrenchcone_ros.core.
  consistent_modes`, best first).

``left``: the times (s) at which the command left the cone (consistent at the previous
command, not at this one), ``entered`` the times it came back. Commands of magnitude 0
(a level tray) pull nowhere and are listed without a margin.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, replace

from ..core import consistent_modes, wrench_cone
from ..core.modes import ModeError
from ..core.numbers import rescale_wrench
from ..core.scene import Scene, SceneError
from .bag import RecordedRun


@dataclass(frozen=True)
class ReplayRow:
    """One command replayed (module docstring); ``margin`` NaN when there is none.

    Parameters
    ----------
    t : float
        The command's recording time (s since the bag's start).
    stamp : float
        Its header stamp (s).
    direction : float
        The pull's direction (rad, fixture frame).
    magnitude : float
        The pull's acceleration (m/s^2).
    pose : tuple of 3 float or None
        The pose it was computed from (x m, y m, theta rad); None when none was recorded.
    consistent : bool
        Whether the command's wrench is in the mode's cone at that pose.
    margin : float
        Its margin (dimensionless, positive inside); NaN when there is none.
    letters : str
        The letters recorded nearest before it.
    classified : tuple of str
        The modes the core finds the command consistent with, best first.
    note : str
        Why there is no margin (empty otherwise).
    """

    t: float
    stamp: float
    direction: float
    magnitude: float
    pose: tuple[float, float, float] | None
    consistent: bool
    margin: float
    letters: str
    classified: tuple[str, ...]
    note: str


@dataclass(frozen=True)
class Replay:
    """The rows, in recording order, and the times the command left / entered the cone.

    Parameters
    ----------
    mode : str
        The mode replayed.
    rows : tuple of ReplayRow
        One per command, in recording order.
    left : tuple of float
        The times (s) the command left the cone.
    entered : tuple of float
        The times (s) it came back.
    """

    mode: str
    rows: tuple[ReplayRow, ...]
    left: tuple[float, ...]
    entered: tuple[float, ...]

    def summary(self) -> str:
        """A few lines for a reader.

        Returns
        -------
        str
            The number of commands and those inside the cone, the smallest margin, the times
            it left and entered the cone, and the sequence of recorded letters.
        """
        rows = [r for r in self.rows if not math.isnan(r.margin)]
        inside = sum(r.consistent for r in rows)
        span = self.rows[-1].t - self.rows[0].t if self.rows else 0.0
        lines = [f"{len(self.rows)} command(s) over {span:.3f} s; mode {self.mode!r}: "
                 f"{inside} of {len(rows)} with a margin inside the cone"
                 + (f", {len(self.rows) - len(rows)} without one" if len(rows) < len(self.rows)
                    else "")]
        if rows:
            lo = min(rows, key=lambda r: r.margin)
            lines.append(f"smallest margin {lo.margin:.4f} at t = {lo.t:.3f} s")
        lines.append("left the cone at t = " + (", ".join(f"{t:.3f}" for t in self.left)
                                               or "(never)") + " s")
        if self.entered:
            lines.append("back in it at t = " + ", ".join(f"{t:.3f}" for t in self.entered)
                         + " s")
        letters = [r.letters for r in self.rows if r.letters]
        if letters:
            seq = [x for i, x in enumerate(letters) if i == 0 or x != letters[i - 1]]
            lines.append("recorded letters: " + " -> ".join(seq))
        return "\n".join(lines)


def margin_at(scene: Scene, pose, mode: str, direction: float, magnitude: float = 1.0
              ) -> tuple[bool, float]:
    """(consistent, margin) of a tray's pull along ``direction`` (rad) in ``mode`` at
    ``pose``; SceneError or ModeError when the pose or the mode do not allow one.

    Parameters
    ----------
    scene : Scene
        The scene (its fixels and mass).
    pose : tuple of 3 float
        (x m, y m, theta rad).
    mode : str
        The mode, wildcards allowed.
    direction : float
        The pull's direction (rad, fixture frame).
    magnitude : float, optional
        The pull's acceleration (m/s^2); the margin does not depend on it.

    Returns
    -------
    consistent : bool
        Whether the pull's wrench is in the cone.
    margin : float
        Its margin (dimensionless, in [-1, 1]).

    Raises
    ------
    SceneError
        The pose makes no valid scene.
    ModeError
        The mode is not valid for the contacts at that pose.
    """
    s = scene.with_pose(*pose)
    m = scene.workpiece.mass * magnitude
    g = rescale_wrench((m * math.cos(direction), m * math.sin(direction), 0.0))
    cone = wrench_cone(s, mode)
    return bool(cone.contains(g)), float(cone.margin(g))


def _latest(rows, t: float):
    """The last row recorded at or before t (None)."""
    k = bisect.bisect_right([r.t for r in rows], t)
    return rows[k - 1] if k else None


def scene_with_fixels(scene: Scene, positions) -> Scene:
    """The scene with recorded fixel positions (radii and friction kept), or the scene
    unchanged when they agree; SceneError when the count differs.

    Parameters
    ----------
    scene : Scene
        The scene.
    positions : sequence of (x, y)
        The recorded fixel positions (m).

    Returns
    -------
    Scene
        The scene with those positions.

    Raises
    ------
    SceneError
        The number of positions is not the scene's number of fixels, or a fixel
        penetrates the workpiece.
    """
    if len(positions) != scene.n_fixels:
        raise SceneError(f"the bag has {len(positions)} fixels, the scene {scene.n_fixels}")
    if all(math.dist(p, f.position) <= 1e-12 for p, f in zip(positions, scene.fixels)):
        return scene
    return replace(scene, fixels=tuple(replace(f, position=tuple(p))
                                       for f, p in zip(scene.fixels, positions)))


def replay(run: RecordedRun, scene: Scene, mode: str, classify: bool = True) -> Replay:
    """Every command of ``run`` in ``mode`` at its recorded pose (module docstring).

    Parameters
    ----------
    run : RecordedRun
        The recorded run.
    scene : Scene
        The scene it ran on.
    mode : str
        The mode to replay the commands in, wildcards allowed.
    classify : bool, optional
        Also list the modes each command is consistent with.

    Returns
    -------
    Replay
        The rows and the times the command left and entered the cone.
    """
    by_stamp = {p.stamp: p for p in run.poses}
    rows, left, entered = [], [], []
    prev: bool | None = None
    for c in run.commands:
        direction, magnitude = c.value
        pose_row = by_stamp.get(c.stamp) or _latest(run.poses, c.t)
        fix = _latest(run.fixels, c.t)
        let = _latest(run.letters, c.t)
        letters = let.value[0] if let is not None else ""
        pose = pose_row.value if pose_row is not None else None
        consistent, margin, classified, note = False, math.nan, (), ""
        if pose is None:
            note = "no pose recorded before this command"
        elif magnitude == 0.0:
            note = "level tray: no pull"
        else:
            try:
                s = scene_with_fixels(scene, fix.value) if fix is not None else scene
                consistent, margin = margin_at(s, pose, mode, direction, magnitude)
                if classify:
                    m = s.workpiece.mass * magnitude
                    g = (m * math.cos(direction), m * math.sin(direction), 0.0)
                    classified = tuple(x.mode for x in consistent_modes(s.with_pose(*pose), g))
            except (SceneError, ModeError) as exc:
                note = " ".join(str(exc).split())
        if not math.isnan(margin):
            if prev is True and not consistent:
                left.append(c.t)
            if prev is False and consistent:
                entered.append(c.t)
            prev = consistent
        rows.append(ReplayRow(c.t, c.stamp, direction, magnitude, pose, consistent, margin,
                              letters, classified, note))
    return Replay(mode, tuple(rows), tuple(left), tuple(entered))


def plot(rep: Replay, path: str) -> None:
    """The margin over time (top; shaded where the command is outside the cone) and the
    recorded letters (bottom), written to ``path`` (matplotlib).

    Parameters
    ----------
    rep : Replay
        The replay.
    path : str
        The output file (.png, .svg or .pdf).
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(2, 1, sharex=True, figsize=(8, 5),
                                 gridspec_kw={"height_ratios": [2, 1]})
    t = [r.t for r in rep.rows]
    ax.plot(t, [r.margin for r in rep.rows], ".-", color="C0", label=f"margin in {rep.mode}")
    ax.axhline(0.0, color="k", lw=0.8)
    for r in rep.rows:
        if not math.isnan(r.margin) and not r.consistent:
            ax.axvline(r.t, color="C3", alpha=0.15, lw=3)
    for x in rep.left:
        ax.axvline(x, color="C3", ls="--", lw=1)
    ax.set_ylabel("margin (dimensionless)")
    ax.legend(loc="best")
    ax.set_title(f"commands replayed in mode {rep.mode}: red, outside the cone")
    seq = [r.letters or "?" for r in rep.rows]
    names = list(dict.fromkeys(seq))
    bx.step(t, [names.index(x) for x in seq], where="post", color="C2")
    bx.set_yticks(range(len(names)), names)
    bx.set_ylabel("letters (recorded)")
    bx.set_xlabel("time since the recording started (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


__all__ = ["Replay", "ReplayRow", "margin_at", "plot", "replay", "scene_with_fixels"]
