# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Pictures of a scene and of a mode's wrench cone (matplotlib; for the CLI and notebooks).

    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.plot import figure
    fig = figure(load_scene("examples/pawl_polygon.yaml"), "arr", wrench=(0.5, -1, 0))
    fig.savefig("pawl.png")                    # or draw into your own axes:
    plot_scene(ax1, scene, "arr"); plot_cone_map(ax2, wrench_cone(scene, "arr"))

matplotlib is imported inside the functions (``wrenchcone_ros.core`` never imports this
module), and only its object-oriented API is used (``matplotlib.figure.Figure``, no
pyplot): no display, no global state, safe under the Agg backend and in threads.

Left panel, :func:`plot_scene` (world frame, metres): the workpiece at its pose, its
centre of mass, the fixels (pins drawn with their radius), at each contact the normal
n_i and the friction cone n_i +- mu_i t_i, the force edges the mode's letter allows drawn
solid in the letter's colour (rolling: the whole cone; sliding: one edge; approaching,
separating: none, the cone dashed), the letter at each fixel; the wrench as its line of
force (Mason), coloured by the verdict; and, when given, the consistent force directions
at a point as shaded fans.

Right panel, :func:`plot_cone_map`: the cone itself. A cone in R^3 is fixed by the
directions it contains, a region of the unit sphere of nondimensional wrenches
u = (f_x, f_y, tau / L) / |.|. The panel maps that sphere to the plane with
phi = atan2(f_y, f_x) (where the force points, the horizontal axis) and
psi = atan2(tau / L, |f|) (vertical; tan psi = d / L where d is the signed distance of
the line of force from the com, so the axis also reads as "where the line of force
passes"). Why this map and not another:

* it shows every cone the core produces: a central (gnomonic) projection cannot show a
  cone that contains a line or is a half-space (both occur: sliding modes, free fixels),
  and Mason's moment labelling shows the wrenches of positive combinations of contact
  forces, not the cones of accelerating modes, which also contain M xdd;
* its axes are the two numbers a person pushing a part thinks in: the direction of the
  push and where its line of action passes;
* facets are great circles (e . u = 0), drawn exactly as curves; generators are points.

The consistent directions are shaded (max_i F_hat_i u <= 0 on a grid), the boundary is
the zero contour, generators are dots, lines of the cone (lineality) are diamonds at both
ends; a cone with an empty interior is drawn as what it is: an arc of the great circle of
its one equality, or the one or two points of its line, or "{0}"; an infeasible mode says
so. The wrench, when given, is a star at its direction.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .batch import wrench_cone
from .cones import Cone
from .drawing import (
    LETTER_COLOURS,
    best_arrow,
    break_wraps,
    contact_sketches,
    great_circle,
    line_of_force,
    outline,
    sphere_angles,
    sphere_directions,
    to_world,
)
from .modes import MODE_TABLE
from .scene import Scene

#: Grid of the cone map (phi x psi samples); 0.5 degree steps.
MAP_GRID = (721, 361)
#: Formats `wrenchcone plot` writes (by the output file's extension).
FORMATS = ("png", "svg", "pdf")
CONSISTENT_COLOUR = (0.0, 0.55, 0.0)
INCONSISTENT_COLOUR = (0.80, 0.0, 0.0)
FAN_COLOUR = (0.85, 0.65, 0.0)


def _verdict(cone: Cone | None, wrench: Sequence[float] | None):
    if cone is None or wrench is None:
        return None
    return cone.check(wrench)


def _deg(a):
    return np.degrees(a)


def plot_scene(ax: Any, scene: Scene, mode: str | None = None,
               wrench: Sequence[float] | None = None, *, cone: Cone | None = None,
               point: Sequence[float] | None = None, directions: Sequence[Any] | None = None
               ) -> None:
    """Draw the scene into matplotlib axes ``ax`` (module docstring, left panel).

    ``cone`` (the mode's cone) gives the wrench's verdict. ``point`` is a point of the
    workpiece (workpiece frame, m; drawn at its place in the world); ``directions`` are
    intervals of force directions applied there (objects with ``lo``, ``hi``, ``best`` in
    rad, fixture frame, counter-clockwise from +x), as the force-directions module
    returns them; each is drawn as a shaded fan at ``point`` (the com when ``point`` is
    None), ``best`` as a line.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw into.
    scene : Scene
        The scene.
    mode : str or None, optional
        A concrete mode: its letters colour the fixels and its force-cone edges are drawn.
    wrench : sequence of 3 float or None, optional
        (fx N, fy N, tz N m), drawn as its line of force.
    cone : Cone or None, optional
        The mode's cone, for the wrench's verdict.
    point : sequence of 2 float or None, optional
        A point of the workpiece (m, workpiece frame).
    directions : sequence or None, optional
        Intervals of force directions (``lo``, ``hi``, ``best`` in rad).

    Raises
    ------
    ModeError
        ``mode`` is not valid for the scene's contacts.
    """
    from matplotlib.patches import Circle, Polygon, Wedge

    L = scene.length_scale
    out = outline(scene)
    ax.add_patch(Polygon(out[:-1], closed=True, facecolor=(0.85, 0.87, 0.90),
                         edgecolor="black", linewidth=1.2, zorder=1))
    com = scene.com_world
    ax.plot(*com, marker="+", color="black", markersize=10, zorder=5)
    ax.annotate("com", com, textcoords="offset points", xytext=(4, 4), fontsize=7)
    sketches = contact_sketches(scene, mode)
    arrow = 0.35 * L
    pts = [out]
    for sk in sketches:
        colour = sk.colour
        if sk.radius > 0:
            ax.add_patch(Circle(sk.position, sk.radius, facecolor=(0.3, 0.3, 0.3, 0.35),
                                edgecolor="black", linewidth=0.8, zorder=3))
        ax.plot(*sk.position, marker="o", color="black", markersize=3.5, zorder=4)
        pts.append(sk.position[None, :] + np.array([[-sk.radius, -sk.radius],
                                                    [sk.radius, sk.radius]]))
        # label: fixel number and letter, outside the workpiece (along -n)
        label = f"{sk.index + 1}" + (f" {sk.letter}" if sk.letter else "")
        where = sk.position - (sk.radius + 0.18 * L) * sk.normal
        pts.append(where[None, :])
        ax.text(*where, label, color=colour, fontsize=10, fontweight="bold",
                ha="center", va="center", zorder=6)
        if not sk.in_contact:
            continue
        p = sk.point
        cone_pts = p + arrow * sk.full_cone
        loaded = sk.force_edges.shape[0] > 0
        ax.add_patch(Polygon(np.vstack([p, cone_pts]), closed=True,
                             facecolor=(*colour, 0.25 if sk.force_edges.shape[0] == 2 else 0.0),
                             edgecolor=colour if loaded else (0.5, 0.5, 0.5),
                             linestyle="-" if loaded else "--", linewidth=0.8, zorder=2))
        ax.annotate("", p + 0.6 * arrow * sk.normal, p,
                    arrowprops=dict(arrowstyle="->", color="black", linewidth=0.8), zorder=4)
        for e in sk.force_edges:
            ax.annotate("", p + arrow * e, p, arrowprops=dict(
                arrowstyle="-|>", color=colour, linewidth=2.0), zorder=4)
        pts.append(cone_pts)
    if point is not None or directions is not None:
        q = com if point is None else to_world(scene, point)
        ax.plot(*q, marker="x", color=FAN_COLOUR, markersize=8, zorder=6)
        for iv in directions or ():
            ax.add_patch(Wedge(q, 0.6 * L, _deg(iv.lo), _deg(iv.hi),
                               facecolor=(*FAN_COLOUR, 0.35), edgecolor=FAN_COLOUR,
                               linewidth=0.8, zorder=3))
            ax.plot(*best_arrow(q, iv.best, 0.6 * L).T, color=FAN_COLOUR, linewidth=1.5,
                    zorder=4)
        pts.append(q[None, :] + np.array([[-0.6 * L, -0.6 * L], [0.6 * L, 0.6 * L]]))
    verdict = _verdict(cone, wrench)
    if wrench is not None:
        colour = "black" if verdict is None else (
            CONSISTENT_COLOUR if verdict[0] else INCONSISTENT_COLOUR)
        line = line_of_force(scene, wrench)
        if line is None:  # a pure moment: a curved arrow round the com
            sign = 1.0 if wrench[2] > 0 else -1.0
            ax.annotate("", com + 0.3 * L * np.array([-sign * 0.5, -0.866]),
                        com + 0.3 * L * np.array([sign * 0.5, -0.866]),
                        arrowprops=dict(arrowstyle="-|>", color=colour, linewidth=2,
                                        connectionstyle=f"arc3,rad={0.8 * sign}"), zorder=7)
        else:
            q, d = line
            ax.plot(*np.vstack([q - 2 * L * d, q + 2 * L * d]).T, color=colour,
                    linestyle=":", linewidth=1.0, zorder=6)
            ax.annotate("", q + 0.5 * L * d, q - 0.5 * L * d, arrowprops=dict(
                arrowstyle="-|>", color=colour, linewidth=2.2), zorder=7)
    lo = np.min(np.vstack(pts), axis=0)
    hi = np.max(np.vstack(pts), axis=0)
    pad = 0.15 * max(hi - lo)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m), fixture frame")
    ax.set_ylabel("y (m)")
    title = "scene" if mode is None else f"mode '{mode}'"
    if wrench is not None:
        g = ", ".join(f"{v:.3g}" for v in wrench)
        title += f"\nwrench ({g})"
        if verdict is not None:
            title += (": consistent" if verdict[0] else ": NOT consistent") + \
                f", margin {verdict[1]:.3g}"
    ax.set_title(title, fontsize=10)
    if mode is not None:
        used = sorted(set(mode), key="aslrn".index)
        from matplotlib.lines import Line2D
        ax.legend(handles=[Line2D([], [], color=LETTER_COLOURS[c], linewidth=3,
                                  label=f"{c}: {MODE_TABLE[c].name}") for c in used],
                  loc="upper right", fontsize=7, framealpha=0.8)


def cone_map_values(cone: Cone, grid: tuple[int, int] = MAP_GRID):
    """(phi, psi, value) grids (rad, rad, -) of the cone map: value = max_i F_hat_i u
    over the facets, <= 0 exactly on the directions u in a full-dimensional cone.

    Parameters
    ----------
    cone : Cone
        The cone.
    grid : tuple of int, optional
        The number of phi and psi samples.

    Returns
    -------
    phi, psi, value : numpy.ndarray
        Grids of shape (grid[1], grid[0]).
    """
    phi = np.linspace(-math.pi, math.pi, grid[0])
    psi = np.linspace(-math.pi / 2, math.pi / 2, grid[1])
    P, S = np.meshgrid(phi, psi)
    u = sphere_directions(P, S)
    if cone.F_hat.shape[0] == 0:
        value = -np.ones_like(P)
    else:
        value = np.max(u @ cone.F_hat.T, axis=-1)
    return P, S, value


def _in_cone(cone: Cone, u: np.ndarray) -> np.ndarray:
    """Cone.contains of each nondimensional direction u = (f_x, f_y, tau / L) (rows)."""
    g = np.asarray(u, dtype=float).reshape(-1, 3) * np.array([1.0, 1.0, cone.length_scale])
    return cone.contains_many(g)


def plot_cone_map(ax: Any, cone: Cone, wrench: Sequence[float] | None = None) -> None:
    """Draw the cone on the (phi, psi) map of the sphere of directions (module docstring).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw into.
    cone : Cone
        The cone.
    wrench : sequence of 3 float or None, optional
        (fx N, fy N, tz N m), drawn as a point of the map.
    """
    ax.set_xlim(-180, 180)
    ax.set_ylim(-90, 90)
    ax.set_xticks(range(-180, 181, 90))
    ax.set_yticks(range(-90, 91, 45))
    ax.grid(True, linewidth=0.3, alpha=0.6)
    ax.set_xlabel("force direction  phi = atan2(fy, fx)  (deg)")
    ax.set_ylabel("psi = atan2(tz / L, |f|)  (deg)")
    colour = (0.17, 0.42, 0.75)
    n_eq = cone.E_hat.shape[0] if cone.feasible else 3
    if not cone.feasible:
        ax.text(0, 0, "infeasible mode:\nno wrench is consistent", ha="center",
                va="center", color=INCONSISTENT_COLOUR, fontsize=11)
    elif n_eq == 0:
        P, S, value = cone_map_values(cone)
        ax.contourf(_deg(P), _deg(S), value, levels=[-2.0, 0.0], colors=[(*colour, 0.35)])
        if cone.F_hat.shape[0]:
            ax.contour(_deg(P), _deg(S), value, levels=[0.0], colors=[colour],
                       linewidths=1.2)
    elif n_eq == 1:  # an arc of the equality's great circle
        circle = great_circle(cone.E_hat[0], 1441)
        arc = np.where(_in_cone(cone, circle)[:, None], circle, np.nan)
        ang = break_wraps(sphere_angles(arc))
        ax.plot(_deg(ang[:, 0]), _deg(ang[:, 1]), color=colour, linewidth=3)
        ax.plot([], [], color=colour, linewidth=3, label="cone (1 equality: an arc)")
    elif n_eq == 2:  # a ray or a line
        d = np.cross(cone.E_hat[0], cone.E_hat[1])
        for v in (d, -d):
            if _in_cone(cone, v)[0]:
                a = _deg(sphere_angles(v / np.linalg.norm(v)))
                ax.plot(*a, marker="o", color=colour, markersize=9)
    else:
        ax.text(0, 0, "cone = {0}: only the zero wrench", ha="center", va="center",
                fontsize=11)
    if cone.feasible:
        for k, g in enumerate(cone.G_hat):
            a = _deg(sphere_angles(g))
            ax.plot(*a, marker="o", color="black", markersize=5, zorder=5)
            ax.annotate(f"g{k + 1}", a, textcoords="offset points", xytext=(4, 4),
                        fontsize=7)
        for line in cone.L_hat:
            for v in (line, -line):
                ax.plot(*_deg(sphere_angles(v)), marker="D", color="black", markersize=5,
                        zorder=5)
    if wrench is not None:
        u = cone.nondimensional(wrench)
        if np.linalg.norm(u) > 0:
            ok, margin = cone.check(wrench)
            ax.plot(*_deg(sphere_angles(u)), marker="*", markersize=14, zorder=6,
                    color=CONSISTENT_COLOUR if ok else INCONSISTENT_COLOUR,
                    markeredgecolor="black", label=f"wrench (margin {margin:.3g})")
    eq = "" if not cone.feasible or n_eq == 0 else f", {n_eq} equalit{'y' if n_eq == 1 else 'ies'}"
    ax.set_title(f"cone of mode '{cone.mode}' on the sphere of (fx, fy, tz/L), "
                 f"L = {cone.length_scale:.3g} m\n{cone.F_hat.shape[0]} facets, "
                 f"{cone.G_hat.shape[0]} generators{eq}", fontsize=9)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="lower right", fontsize=7, framealpha=0.8)


def figure(scene: Scene, mode: str, wrench: Sequence[float] | None = None, *,
           point: Sequence[float] | None = None, directions: Sequence[Any] | None = None,
           cone: Cone | None = None):
    """A two-panel matplotlib Figure: the scene (:func:`plot_scene`) and the mode's cone
    on the sphere of wrench directions (:func:`plot_cone_map`).

    Parameters
    ----------
    scene : Scene
        The workpiece at its pose and the fixels.
    mode : str
        A concrete mode (no wildcard).
    wrench : sequence of 3 float, optional
        (fx N, fy N, tz N m), drawn on both panels with its verdict.
    point : sequence of 2 float, optional
        Where a force acts (m, workpiece frame), for the force directions drawn.
    directions : sequence, optional
        Direction intervals (``force_directions``) drawn as fans.
    cone : Cone, optional
        The cone to draw (default: ``wrench_cone(scene, mode)``).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ModeError
        A bad mode.
    ValueError
        A mode with wildcards (a union of cones).
    """
    from matplotlib.figure import Figure

    if cone is None:
        cone = plotted_cone(scene, mode)
    fig = Figure(figsize=(11.5, 5.0), layout="constrained")
    left, right = fig.subplots(1, 2, width_ratios=[1.0, 1.15])
    plot_scene(left, scene, mode, wrench, cone=cone, point=point, directions=directions)
    plot_cone_map(right, cone, wrench)
    return fig


def robust_figure(scene: Scene, mode: str, cone: Cone, robust: Cone, title: str,
                  wrench: Sequence[float] | None = None, *,
                  point: Sequence[float] | None = None,
                  directions: Sequence[Any] | None = None):
    """Three panels: the scene with the robust force directions (``directions``, from
    ``force_directions(..., uncertainty=...)``) as fans, and the nominal ``cone`` and the
    ``robust`` cone (the mode's "all" cone, a Cone) side by side on the sphere of
    directions; ``title`` names the set of models and the guarantee."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(16.5, 5.0), layout="constrained")
    left, mid, right = fig.subplots(1, 3, width_ratios=[1.0, 1.15, 1.15])
    plot_scene(left, scene, mode, wrench, cone=robust, point=point, directions=directions)
    left.set_title(f"force directions giving '{mode}' for every model", fontsize=9)
    plot_cone_map(mid, cone, wrench)
    mid.set_title("nominal " + mid.get_title(), fontsize=9)
    plot_cone_map(right, robust, wrench)
    right.set_title(f"every model of {title}\n" + right.get_title(), fontsize=8)
    return fig


def plotted_cone(scene: Scene, mode: str) -> Cone:
    """The cone :func:`figure` draws; ModeError for a bad mode, ValueError for wildcards.

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        A concrete mode.

    Returns
    -------
    Cone
        The mode's cone.

    Raises
    ------
    ModeError
        ``mode`` is not valid for the scene's contacts.
    ValueError
        ``mode`` has wildcards.
    """
    cone = wrench_cone(scene, mode)
    if not isinstance(cone, Cone):
        raise ValueError(f"mode {mode!r} has wildcards: a union of cones; plot a concrete "
                         "mode (letters from 'aslrn')")
    return cone


def output_format(path: str | Path) -> str:
    """The format of an output file, from its extension; ValueError if not in FORMATS.

    Parameters
    ----------
    path : str or Path
        The output file.

    Returns
    -------
    str
        Its format, one of ``FORMATS``.

    Raises
    ------
    ValueError
        The extension is not one of ``FORMATS``.
    """
    fmt = Path(path).suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise ValueError(f"output file {str(path)!r}: unknown format {fmt!r}; use one of "
                         + ", ".join(f".{f}" for f in FORMATS))
    return fmt


def save(fig: Any, path: str | Path, dpi: int = 90) -> Path:
    """Write a figure, the same bytes for the same figure (no date, no version inside).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, e.g. of :func:`figure`.
    path : str or Path
        The file; its extension gives the format (:data:`FORMATS`).
    dpi : int
        Dots per inch of a raster format.

    Returns
    -------
    Path

    Raises
    ------
    ValueError
        An extension not in :data:`FORMATS`.
    OSError
        The file cannot be written (the message names it).
    """
    path = Path(path)
    fmt = output_format(path)
    from matplotlib import rc_context

    try:
        with rc_context({"svg.hashsalt": "wrenchcone"}):  # fixed ids, not random ones
            fig.savefig(path, format=fmt, dpi=dpi, metadata=_metadata(fmt))
    except OSError as exc:
        raise OSError(f"cannot write {str(path)!r}: {exc.strerror}") from None
    return path


def _metadata(fmt: str) -> dict:
    """No creation date or software version in the file: the same command writes the
    same bytes (a committed picture can be checked by regenerating it)."""
    if fmt == "svg":
        return {"Date": None, "Creator": None}
    if fmt == "pdf":
        return {"CreationDate": None, "Producer": None, "Creator": None}
    return {"Software": None}


__all__ = ["plot_scene", "plot_cone_map", "cone_map_values", "figure", "save", "FORMATS",
           "plotted_cone", "output_format"]
