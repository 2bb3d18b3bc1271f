# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Tray tilts: the gravity pull of a tilted tray and the tilts that give a set of force
directions.

A tray (the fixture plane) tilted by angle alpha (rad, 0 < alpha <= pi/2) whose direction
of steepest descent, projected on the fixture plane, has angle psi (rad, fixture frame,
counter-clockwise from x) pulls the workpiece of mass m in its plane with the force
m g sin(alpha) (cos psi, sin psi) at the centre of mass (g = STANDARD_GRAVITY = 9.80665 m/s^2); the normal
component m g cos(alpha) presses it onto the tray and is not part of the planar model
(support friction of the tray is neglected, as in the paper). A tilt about a horizontal
axis of direction angle k (right-hand rule, positive alpha) has psi = k - pi/2. So the
downhill directions that produce a mode are exactly ``force_directions(scene, mode)``
at the com (:func:`.directions.force_directions`), whatever alpha; the magnitude matters only when another force is present
(a spring preload), which is what :func:`.regions.force_region` with an ``offset``
answers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from .directions import DirectionInterval

#: Standard gravity, m/s^2 (the tray-tilt convention).
STANDARD_GRAVITY: float = 9.80665


# --- tray tilt ---------------------------------------------------------------------------
def tilt_gravity_force(mass: float, alpha: float, psi: float,
                       g: float = STANDARD_GRAVITY) -> tuple[float, float]:
    """In-plane gravity force (N, fixture frame) on a workpiece of ``mass`` (kg) on a tray
    tilted by ``alpha`` (rad) with steepest descent along ``psi`` (rad):
    m g sin(alpha) (cos psi, sin psi), applied at the com (module docstring).

    Parameters
    ----------
    mass : float
        kg.
    alpha : float
        The tilt (rad).
    psi : float
        The steepest-descent direction (rad, fixture frame).
    g : float, optional
        Gravity (m/s^2).

    Returns
    -------
    tuple of 2 float
        (fx, fy), N.
    """
    k = mass * g * math.sin(alpha)
    return (k * math.cos(psi), k * math.sin(psi))


@dataclass(frozen=True)
class TiltInterval:
    """Tray tilts that produce a force direction interval: steepest-descent directions
    psi in [downhill_lo, downhill_hi] (rad), equivalently tilt axes (right-hand rule,
    positive tilt) of direction angle in [axis_lo, axis_hi] = psi + pi/2.

    Parameters
    ----------
    downhill_lo, downhill_hi : float
        The steepest-descent directions' ends (rad).
    axis_lo, axis_hi : float
        The tilt axes' ends (rad).
    best_downhill : float
        The steepest-descent direction of largest margin (rad).
    """

    downhill_lo: float
    downhill_hi: float
    axis_lo: float
    axis_hi: float
    best_downhill: float


def tilt_directions(intervals: Sequence[DirectionInterval]) -> list[TiltInterval]:
    """The tray tilts whose gravity pull (at the com) lies in ``intervals`` (computed with
    the default point, the com): any tilt angle 0 < alpha <= pi/2 with its steepest
    descent in the interval.

    Parameters
    ----------
    intervals : sequence of DirectionInterval
        Force directions at the com.

    Returns
    -------
    list of TiltInterval
        One per interval.
    """
    return [TiltInterval(iv.lo, iv.hi, iv.lo + math.pi / 2, iv.hi + math.pi / 2, iv.best)
            for iv in intervals]


__all__ = ["STANDARD_GRAVITY", "TiltInterval", "tilt_directions", "tilt_gravity_force"]
