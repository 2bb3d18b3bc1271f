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

With a plan instead of one mode (:func:`replay` ``plan=``), each command is replayed in
the mode of the plan's segment in force when it was sent (:func:`segment_modes`): the
segment the recorded controller states name (``RECORDED``), or, for a plan's list of
segment modes, the segment found offline by the controller's own rule (the next segment
begins at the first command whose pose no longer allows the current segment's mode and
allows the next one's, or whose pose has a fixel inside the part beyond the contact
tolerance: an impact). With an uncertainty, each command also gets its robust margin:
in the cone of the wrenches consistent with the mode for every model
(:func:`wrenchcone_ros.core.robust_cone`, "all"; what the node answers under its
``uncertainty.*``).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, replace

from collections.abc import Sequence

from ..core import consistent_modes, robust_cone, wrench_cone
from ..core.modes import ModeError
from ..core.numbers import rescale_wrench
from ..core.geometry import SceneError
from ..core.scene import Scene
from ..core.uncertainty import NOMINAL, Uncertainty, as_uncertainty
from .bag import BagError, RecordedRun

#: ``plan=RECORDED``: the segment modes the recorded controller states name.
RECORDED = "recorded"


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
    mode : str, optional
        The mode replayed (the segment's, with a plan).
    robust_margin : float, optional
        The margin for every model of the uncertainty (NaN when none was given).
    robust_consistent : bool, optional
        Whether the command is in the robust ("all") cone.
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
    mode: str = ""
    robust_margin: float = math.nan
    robust_consistent: bool = False


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
    uncertainty : str, optional
        The uncertainty described, when robust margins were computed (else empty).
    """

    mode: str
    rows: tuple[ReplayRow, ...]
    left: tuple[float, ...]
    entered: tuple[float, ...]
    uncertainty: str = ""

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
        what = self.mode if " " in self.mode else f"mode {self.mode!r}"
        lines = [f"{len(self.rows)} command(s) over {span:.3f} s; {what}: "
                 f"{inside} of {len(rows)} with a margin inside the cone"
                 + (f", {len(self.rows) - len(rows)} without one" if len(rows) < len(self.rows)
                    else "")]
        if rows:
            lo = min(rows, key=lambda r: r.margin)
            lines.append(f"smallest margin {lo.margin:.4f} at t = {lo.t:.3f} s"
                         + (f" (mode {lo.mode})" if lo.mode != self.mode else ""))
        robust = [r for r in rows if not math.isnan(r.robust_margin)]
        if self.uncertainty:
            n_in = sum(r.robust_consistent for r in robust)
            lowest = min((r.robust_margin for r in robust), default=math.nan)
            lines.append(f"for every model ({self.uncertainty}): {n_in} of {len(rows)} "
                         f"inside" + (f", smallest robust margin {lowest:.4f}" if robust
                                      else ""))
        lines.append("left the cone at t = " + ", ".join(f"{t:.3f}" for t in self.left)
                     + " s" if self.left else "never left the cone")
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


def robust_margin_at(scene: Scene, pose, mode: str, direction: float,
                     uncertainty: Uncertainty, magnitude: float = 1.0) -> tuple[bool, float]:
    """(consistent for every model, margin) of a tray's pull along ``direction`` (rad) in
    ``mode`` at ``pose`` under ``uncertainty`` (the robust cone, "all").

    Parameters
    ----------
    scene : Scene
        The scene the run used.
    pose : sequence of 3 float
        (x m, y m, theta rad).
    mode : str
        A concrete mode.
    direction : float
        The pull's direction (rad, fixture frame).
    uncertainty : Uncertainty
        The models the answer must hold for.
    magnitude : float, optional
        The pull's acceleration (m/s^2).

    Returns
    -------
    tuple of (bool, float)
        Whether the wrench is in the robust cone, and its worst-case margin.

    Raises
    ------
    SceneError, ModeError
        As :func:`margin_at`.
    """
    s = scene.with_pose(*pose)
    m = scene.workpiece.mass * magnitude
    g = rescale_wrench((m * math.cos(direction), m * math.sin(direction), 0.0))
    cone = robust_cone(s, mode, uncertainty, "all")
    return bool(cone.contains(g)), float(cone.margin(g))


def _allows(scene: Scene, pose, mode: str) -> bool | None:
    """Does ``pose`` allow ``mode`` (its letters agree with the contacts there)? None
    when the pose makes no valid scene (a fixel penetrates the part beyond the contact
    tolerance: an impact)."""
    try:
        s = scene.with_pose(*pose)
    except SceneError:
        return None
    try:
        wrench_cone(s, mode)
    except (SceneError, ModeError):
        return False
    return True


def segment_modes(run: RecordedRun, scene: Scene, plan: str | Sequence[str]) -> list[str]:
    """The mode of the plan's segment in force at each command of ``run`` (module
    docstring): ``RECORDED``, the ``planned_mode`` of the controller state recorded
    next at or after the command (the state of the same control step; else the last
    one before it); or a list of segment modes, followed offline. Commands without a
    pose keep the segment.

    Parameters
    ----------
    run : RecordedRun
        The recorded run.
    scene : Scene
        The scene it ran on.
    plan : str or sequence of str
        ``RECORDED`` or the segments' modes.

    Returns
    -------
    list of str
        One mode per command of ``run``.

    Raises
    ------
    ValueError
        ``plan`` is another string, or an empty list.
    BagError
        ``RECORDED`` on a run without controller states.
    """
    if isinstance(plan, str):
        if plan != RECORDED:
            raise ValueError(f"plan must be {RECORDED!r} or a list of segment modes, got {plan!r}")
        states = [st for st in run.states if st.value[1]]
        if not states:
            raise BagError(f"{run.path}: no controller state with a planned mode "
                           "(wrenchcone_msgs/msg/ControllerState): give the plan (--plan FILE)")
        times = [st.t for st in states]
        out = []
        for c in run.commands:
            k = bisect.bisect_left(times, c.t)
            out.append(states[min(k, len(states) - 1)].value[1])
        return out
    modes = list(plan)
    if not modes:
        raise ValueError("the plan has no segments")
    by_stamp = {p.stamp: p for p in run.poses}
    k, out = 0, []
    for c in run.commands:
        pose_row = by_stamp.get(c.stamp) or _latest(run.poses, c.t)
        if pose_row is not None:
            fix = _latest(run.fixels, c.t)
            try:
                s = scene_with_fixels(scene, fix.value) if fix is not None else scene
            except SceneError:
                s = scene
            now = _allows(s, pose_row.value, modes[k])
            if now is None and k + 1 < len(modes):
                k += 1  # an impact: the contact was made
            while (k + 1 < len(modes) and now is False
                   and _allows(s, pose_row.value, modes[k + 1])):
                k += 1
                now = _allows(s, pose_row.value, modes[k])
        out.append(modes[k])
    return out


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


def replay(run: RecordedRun, scene: Scene, mode: str | None = None, classify: bool = True, *,
           plan: str | Sequence[str] | None = None,
           uncertainty: Uncertainty | None = None) -> Replay:
    """Every command of ``run`` at its recorded pose (module docstring), in ``mode`` or,
    with ``plan`` (``RECORDED`` or segment modes), in its segment's mode; with
    ``uncertainty``, its robust margin too.

    Parameters
    ----------
    run : RecordedRun
        The recorded run.
    scene : Scene
        The scene it ran on.
    mode : str or None, optional
        The mode to replay the commands in, wildcards allowed (exactly one of ``mode``
        and ``plan``).
    classify : bool, optional
        Also list the modes each command is consistent with.
    plan : str, sequence of str or None, optional
        ``RECORDED`` (the segment the recorded controller state names) or the segments'
        modes, followed offline by the controller's rule.
    uncertainty : Uncertainty or None, optional
        Also the robust margin of each command for every model of it.

    Returns
    -------
    Replay
        The rows and the times the command left and entered the cone.

    Raises
    ------
    ValueError
        Neither or both of ``mode`` and ``plan`` given.
    """
    if (mode is None) == (plan is None):
        raise ValueError("replay needs a mode or a plan (one of them)")
    modes = ([mode] * len(run.commands) if plan is None
             else segment_modes(run, scene, plan))
    uncertainty = as_uncertainty(uncertainty)
    with_robust = uncertainty != NOMINAL  # robust margins only when an uncertainty is given
    by_stamp = {p.stamp: p for p in run.poses}
    rows, left, entered = [], [], []
    prev: bool | None = None
    for c, seg_mode in zip(run.commands, modes):
        direction, magnitude = c.value
        pose_row = by_stamp.get(c.stamp) or _latest(run.poses, c.t)
        fix = _latest(run.fixels, c.t)
        let = _latest(run.letters, c.t)
        letters = let.value[0] if let is not None else ""
        pose = pose_row.value if pose_row is not None else None
        consistent, margin, classified, note = False, math.nan, (), ""
        robust, robust_ok = math.nan, False
        if pose is None:
            note = "no pose recorded before this command"
        elif magnitude == 0.0:
            note = "level tray: no pull"
        else:
            try:
                s = scene_with_fixels(scene, fix.value) if fix is not None else scene
                consistent, margin = margin_at(s, pose, seg_mode, direction, magnitude)
                if with_robust:
                    robust_ok, robust = robust_margin_at(s, pose, seg_mode, direction,
                                                         uncertainty, magnitude)
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
                              letters, classified, note, seg_mode, robust, robust_ok))
    name = mode if plan is None else ("the recorded plan" if isinstance(plan, str)
                                      else "plan " + " -> ".join(plan))
    return Replay(name, tuple(rows), tuple(left), tuple(entered),
                  uncertainty.describe() if with_robust else "")


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
    if rep.uncertainty:
        ax.plot(t, [r.robust_margin for r in rep.rows], ".-", color="C1",
                label=f"for every model ({rep.uncertainty})")
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


__all__ = ["RECORDED", "Replay", "ReplayRow", "margin_at", "plot", "replay",
           "robust_margin_at", "scene_with_fixels", "segment_modes"]
