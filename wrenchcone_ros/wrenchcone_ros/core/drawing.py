# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What a picture of a scene and its cone shows, as plain numbers (no plotting library).

The matplotlib figures (:mod:`wrenchcone_ros.core.plot`) and the node's RViz markers draw the same things;
both take them from here, so the geometry is written once:

* :func:`outline` -- the workpiece boundary at its pose, world frame (:func:`to_world`);
* :func:`contact_sketches` -- per fixel: contact point p_i, normal n_i, tangent t_i, the
  mode's letter and the edges n_i + s mu_i t_i of the force cone that letter allows
  (Table 2 through :data:`~.modes.MODE_TABLE`: both edges when rolling, one when sliding,
  none when approaching or separating);
* :func:`line_of_force` -- a wrench (f, tau) with f != 0 is one force f acting along a line
  (Mason's lines of force): the line's point nearest the centre of mass is
  com + tau (f_y, -f_x) / |f|^2, since then r x f = tau;
* :func:`sphere_angles` and :func:`great_circle` -- the map of the unit sphere of
  nondimensional wrench directions u = (f_x, f_y, tau / L) / |.| used by the cone panel:
  phi = atan2(f_y, f_x) (the force's direction) and psi = atan2(tau / L, |f|) (the
  moment's share; tan psi = d / L with d the signed distance of the line of force from the
  com, positive when the force turns the body counter-clockwise).

Units: metres, radians; world (fixture) frame throughout.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .modes import MODE_TABLE, parse_mode
from .geometry import Disc
from .scene import Scene

#: Colour of each mode letter (RGB in [0, 1]) in plots and RViz markers.
LETTER_COLOURS: dict[str, tuple[float, float, float]] = {
    "a": (0.55, 0.55, 0.55),  # approaching: grey
    "s": (0.12, 0.47, 0.71),  # separating: blue
    "l": (1.00, 0.50, 0.05),  # sliding left: orange
    "r": (0.58, 0.40, 0.74),  # sliding right: purple
    "n": (0.17, 0.63, 0.17),  # rolling: green
}
#: Colour of a fixel with no letter (no mode given).
NO_LETTER_COLOUR = (0.3, 0.3, 0.3)
#: Points on a disc's outline (a polygon's outline is its vertices).
DISC_OUTLINE_SAMPLES = 96


def outline(scene: Scene, samples: int = DISC_OUTLINE_SAMPLES) -> np.ndarray:
    """Closed boundary of the workpiece at its pose, world frame (m): shape (k + 1, 2),
    the last point equal to the first. A disc is sampled at ``samples`` points.

    Parameters
    ----------
    scene : Scene
        The scene.
    samples : int, optional
        Points on a disc's outline.

    Returns
    -------
    numpy.ndarray
        Shape (k + 1, 2), m, world frame.
    """
    shape = scene.workpiece.shape
    if isinstance(shape, Disc):
        a = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
        local = shape.radius * np.column_stack([np.cos(a), np.sin(a)])
    else:
        local = np.asarray(shape.vertices, dtype=float)
    world = to_world(scene, local)
    return np.vstack([world, world[:1]])


def to_world(scene: Scene, points: Sequence[Sequence[float]]) -> np.ndarray:
    """Workpiece-frame points (m, rows or one point) in the world frame:
    R(theta) p + (x, y) with pose (x, y, theta).

    Parameters
    ----------
    scene : Scene
        The scene (its pose).
    points : sequence of (x, y)
        Points in the workpiece frame (m), rows or one point.

    Returns
    -------
    numpy.ndarray
        The points in the world frame (m), of the input's shape.
    """
    p = np.asarray(points, dtype=float)
    x, y, th = scene.pose
    c, s = math.cos(th), math.sin(th)
    return p @ np.array([[c, s], [-s, c]]) + np.array([x, y])


@dataclass(frozen=True)
class ContactSketch:
    """One fixel as drawn: position and pin radius, and where it touches, with what.

    Parameters
    ----------
    index : int
        The fixel's index (0-based).
    position : numpy.ndarray
        The fixel's centre (m).
    radius : float
        The pin's radius (m).
    point : numpy.ndarray
        p_i, the closest point of the workpiece (m).
    normal : numpy.ndarray
        n_i, unit, from the fixel into the workpiece.
    tangent : numpy.ndarray
        t_i, n_i rotated by +90 degrees.
    gap : float
        The gap (m).
    in_contact : bool
        Whether the fixel touches the workpiece.
    friction : float
        mu_i.
    letter : str or None
        The mode's letter at this fixel; None without a mode.
    force_edges : numpy.ndarray
        (k, 2) unit directions n + s mu t of the force cone the letter allows.
    """

    index: int  # 0-based fixel index
    position: np.ndarray  # fixel centre (m)
    radius: float  # pin radius (m)
    point: np.ndarray  # p_i, the closest workpiece point (m)
    normal: np.ndarray  # n_i, unit, from the fixel into the workpiece
    tangent: np.ndarray  # t_i = n_i rotated +90 degrees
    gap: float  # m
    in_contact: bool
    friction: float  # mu_i
    letter: str | None  # the mode's letter at this fixel, None without a mode
    force_edges: np.ndarray  # (k, 2) unit directions n + s mu t of the allowed force cone

    @property
    def colour(self) -> tuple[float, float, float]:
        """The colour of the fixel's letter (RGB in [0, 1]; :data:`LETTER_COLOURS`)."""
        return LETTER_COLOURS.get(self.letter or "", NO_LETTER_COLOUR)

    @property
    def full_cone(self) -> np.ndarray:
        """(2, 2) unit edges n - mu t, n + mu t of the whole friction cone."""
        return _unit(np.array([self.normal - self.friction * self.tangent,
                               self.normal + self.friction * self.tangent]))


def _unit(rows: np.ndarray) -> np.ndarray:
    rows = np.asarray(rows, dtype=float).reshape(-1, 2)
    if rows.shape[0] == 0:
        return rows
    return rows / np.linalg.norm(rows, axis=1)[:, None]


def contact_sketches(scene: Scene, mode: str | None = None) -> list[ContactSketch]:
    """Every fixel with its contact frame and, when ``mode`` is given (a concrete mode,
    one letter per fixel), the force-cone edges its letter allows (Table 2).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str or None, optional
        A concrete mode, one letter per fixel.

    Returns
    -------
    list of ContactSketch
        One per fixel, in fixel order.

    Raises
    ------
    ModeError
        ``mode`` is not valid for the scene's contacts.
    """
    letters: Sequence[str | None] = [None] * scene.n_fixels
    if mode is not None:  # validated against the contact state (raises ModeError)
        letters = [inter.letter for inter in parse_mode(
            mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)]
    out = []
    for c, fixel, letter in zip(scene.contacts, scene.fixels, letters):
        mu = scene.mu(c.index)
        n, t = np.asarray(c.n, dtype=float), np.asarray(c.t, dtype=float)
        edges = np.zeros((0, 2))
        if letter is not None and MODE_TABLE[letter].loaded and c.in_contact:
            edges = _unit(np.array([n + s * mu * t for s in MODE_TABLE[letter].c_t.edges]))
        out.append(ContactSketch(
            index=c.index, position=np.asarray(fixel.position, dtype=float),
            radius=fixel.radius, point=np.asarray(c.p, dtype=float), normal=n, tangent=t,
            gap=float(c.gap), in_contact=bool(c.in_contact), friction=mu, letter=letter,
            force_edges=edges))
    return out


def line_of_force(scene: Scene, wrench: Sequence[float]
                  ) -> tuple[np.ndarray, np.ndarray] | None:
    """(point, unit direction) of the wrench's line of force, world frame; the point is
    the line's point nearest the com. None for a pure moment (f = 0).

    Parameters
    ----------
    scene : Scene
        The scene (its centre of mass).
    wrench : sequence of 3 float
        (fx N, fy N, tz N m), world frame.

    Returns
    -------
    tuple of numpy.ndarray or None
        (point (m), unit direction), or None for a pure moment.
    """
    fx, fy, tz = (float(v) for v in wrench)
    f2 = fx * fx + fy * fy
    if f2 == 0.0:
        return None
    point = scene.com_world + tz / f2 * np.array([fy, -fx])
    return point, np.array([fx, fy]) / math.sqrt(f2)


def sphere_angles(u: np.ndarray) -> np.ndarray:
    """(phi, psi) in rad of nondimensional directions u = (f_x, f_y, tau / L), rows.

    phi = atan2(f_y, f_x) in (-pi, pi], psi = atan2(tau / L, |f|) in [-pi/2, pi/2].
    Accepts one vector (returns shape (2,)) or rows (returns (k, 2)).

    Parameters
    ----------
    u : numpy.ndarray
        One direction (3,) or rows (k, 3), nondimensional.

    Returns
    -------
    numpy.ndarray
        (phi, psi) in rad, shape (2,) or (k, 2).
    """
    u = np.asarray(u, dtype=float)
    rows = u.reshape(-1, 3)
    out = np.column_stack([np.arctan2(rows[:, 1], rows[:, 0]),
                           np.arctan2(rows[:, 2], np.hypot(rows[:, 0], rows[:, 1]))])
    return out[0] if u.ndim == 1 else out


def sphere_directions(phi: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 3) of the map coordinates: the inverse of :func:`sphere_angles`.

    Parameters
    ----------
    phi : numpy.ndarray
        The force's direction (rad).
    psi : numpy.ndarray
        The moment's share (rad), of phi's shape.

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape (..., 3).
    """
    cp = np.cos(psi)
    return np.stack([cp * np.cos(phi), cp * np.sin(phi), np.sin(psi)], axis=-1)


def great_circle(normal: Sequence[float], samples: int = 721) -> np.ndarray:
    """Unit vectors (samples, 3) of the great circle orthogonal to ``normal``.

    Parameters
    ----------
    normal : sequence of 3 float
        The circle's normal (any length but zero).
    samples : int, optional
        Points on the circle (the first and the last coincide).

    Returns
    -------
    numpy.ndarray
        Shape (samples, 3).
    """
    e = np.asarray(normal, dtype=float)
    e = e / np.linalg.norm(e)
    a = np.eye(3)[int(np.argmin(np.abs(e)))]
    b1 = np.cross(e, a)
    b1 /= np.linalg.norm(b1)
    b2 = np.cross(e, b1)
    t = np.linspace(0.0, 2.0 * math.pi, samples)
    return np.outer(np.cos(t), b1) + np.outer(np.sin(t), b2)


def fan_triangles(point: Sequence[float], lo: float, hi: float, radius: float,
                  step: float = math.radians(5.0)) -> np.ndarray:
    """Triangles (k, 3, 2) filling the circular sector of ``radius`` (m) at ``point`` from
    angle ``lo`` to ``hi`` (rad, counter-clockwise, hi >= lo), each at most ``step`` wide:
    a fan of force directions as a triangle list (RViz).

    Parameters
    ----------
    point : sequence of 2 float
        The fan's apex (m).
    lo, hi : float
        The first and the last angle (rad).
    radius : float
        The fan's radius (m).
    step : float, optional
        The widest angle of one triangle (rad).

    Returns
    -------
    numpy.ndarray
        Shape (k, 3, 2), m.

    Raises
    ------
    ValueError
        ``hi < lo``.
    """
    if hi < lo:
        raise ValueError(f"fan from {lo} to {hi} rad: hi must be >= lo")
    k = max(1, math.ceil((hi - lo) / step))
    a = np.linspace(lo, hi, k + 1)
    rim = np.asarray(point, dtype=float) + radius * np.column_stack([np.cos(a), np.sin(a)])
    centre = np.broadcast_to(np.asarray(point, dtype=float), (k, 2))
    return np.stack([centre, rim[:-1], rim[1:]], axis=1)


def best_arrow(point: Sequence[float], best: float, radius: float) -> np.ndarray:
    """(2, 2): the tail ``point`` (m) and the tip, ``radius`` (m) along direction ``best``
    (rad): the most robust force direction of an interval drawn over its fan.

    Parameters
    ----------
    point : sequence of 2 float
        The tail (m).
    best : float
        The arrow's direction (rad).
    radius : float
        The arrow's length (m).

    Returns
    -------
    numpy.ndarray
        (2, 2): tail and tip (m).
    """
    tail = np.asarray(point, dtype=float).reshape(2)
    return np.vstack([tail, tail + radius * np.array([math.cos(best), math.sin(best)])])


def break_wraps(angles: np.ndarray) -> np.ndarray:
    """(phi, psi) rows of a path with NaN rows inserted where phi jumps by more than pi
    (the path crosses the map's seam at phi = +-pi), so a line plot does not cross it.

    Parameters
    ----------
    angles : numpy.ndarray
        (phi, psi) rows (rad).

    Returns
    -------
    numpy.ndarray
        The rows, with NaN rows at the seam.
    """
    angles = np.asarray(angles, dtype=float).reshape(-1, 2)
    if angles.shape[0] < 2:
        return angles
    jumps = np.nonzero(np.abs(np.diff(angles[:, 0])) > math.pi)[0]
    return np.insert(angles, jumps + 1, np.nan, axis=0)


__all__ = ["LETTER_COLOURS", "ContactSketch", "outline", "to_world", "contact_sketches", "line_of_force",
           "sphere_angles", "sphere_directions", "great_circle", "fan_triangles",
           "best_arrow", "break_wraps"]
