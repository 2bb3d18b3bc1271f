# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The fixture-design problem as data: the part, the plate, the uncertainty, the actuator
and the loading task.

Units: SI (metres, kilograms, radians), REP-103 (x right, y up, angles counter-clockwise).
The plate frame is the fixture frame: hole (i, j) is at (i * pitch, j * pitch) m, i in
0 .. nx - 1, j in 0 .. ny - 1. The plate's usable area is the rectangle half a pitch around
the outermost holes, [-pitch / 2, (nx - 1/2) pitch] x [-pitch / 2, (ny - 1/2) pitch]; a
placed part must lie inside it.

Plate YAML (every key but ``pitch``, ``extent`` and one of ``pin_radius`` /
``pin_radii`` optional)::

    pitch: 0.01              # m between neighbouring holes
    extent: [12, 10]         # holes along x and y
    pin_radius: 0.003        # m, every locating pin (the one-size shorthand), or
    # pin_radii: [0.002, 0.004]  # m, the pin sizes at hand: each hole takes any of them
    keep_out:                # rectangles [x0, y0, x1, y1] (m, plate frame): no pin there
      - [0.0, 0.0, 0.02, 0.09]
    fixed_pins: [[3, 2]]     # holes (i, j) holding pins already: every design uses them;
                             # [i, j, r] gives the pin's own radius r (m), which a plate
                             # of several radii requires

A design chooses the radius of each of its three pins among ``pin_radii`` (a fixed pin
keeps its own): the geometry stage solves every one of the K^3 radius assignments of a
pin triple (K <= MAX_PIN_RADII radii; fewer with fixed pins), so it costs up to K^3 times
a one-size plate's.

The loading task is a start offset (m) along the loading direction: the part starts at
its seat moved back by ``start_offset`` against the actuator's pull of the design (the
hold's best tilt), and must be brought into the seat by the seating planner: the tilt that holds the part is
the one that drives it in, so one number (how far from the seat a gripper or a chute
releases it) states the task for every design alike, and its plan is checked in the
physics engine.

On top of that one start, the loading task may take a **start region**: a box of poses
(x +- dx, y +- dy, theta +- dtheta) around the loading start, the placement error of a
gripper or a chute (DEFAULT_START_REGION: +-2 mm, +-2 mm, +-5 degrees). The plan found
from the loading start is then run from a cover of that box (the planner's
``certify_region``, with the work counts of :class:`RegionWork`), the box is shrunk per
axis until it holds, and the design is ranked by the size of what holds
(docs/fixture_design.md, "Ranking by region"). ``start_region=None`` (the default of
:class:`DesignProblem` and ``design_fixtures``) plans from the one start only; the
command ``wrenchcone design`` asks DEFAULT_START_REGION unless ``--no-start-region``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..core.geometry import Polygon
from ..core.plan.results import PlanError, StartRegion
from ..core.scene import Scene
from ..core.scene_yaml import check_keys, load_scene, read_yaml
from ..core.simulate import Actuator
from ..core.uncertainty import NOMINAL, Uncertainty, UncertaintyError, as_uncertainty

#: Default start offset of the loading task (m): how far from its seat the part starts.
DEFAULT_START_OFFSET_M: float = 0.002

#: Default start region of the loading task: half-widths (dx m, dy m, dtheta rad), a
#: gripper's placement error of +-2 mm and +-5 degrees around the loading start.
DEFAULT_START_REGION: tuple[float, float, float] = (0.002, 0.002, math.radians(5.0))

#: The work counts of a design's start region (:class:`RegionWork`, the planner's
#: ``certify_region``): cover points per axis, bisection steps per stage of the
#: shrinking (the certified half-widths to a quarter of the asked ones), models drawn
#: from the uncertainty per cover point, starts drawn uniformly per box. Smaller than
#: the planner's own (REGION_GRID 5, REGION_BISECTIONS 3, 8 models, 688 draws), which
#: take about 30 s for one pawl region: a design run plans a region for each of its
#: planned designs, so these keep one region to seconds up to about half a minute on one
#: core (docs/fixture_design.md); the same counts on every machine, so the same rows.
DESIGN_REGION_GRID: int = 3
DESIGN_REGION_BISECTIONS: int = 2
DESIGN_REGION_SAMPLED: int = 2
DESIGN_REGION_DRAWS: int = 50

#: Pin triples per stage-1 batch of a design run (about 13 s for the pawl on one core:
#: docs/performance.md).
DEFAULT_BATCH_TRIPLES: int = 600
#: Designs per stage-2 batch: one, as a design's plan search takes from 2 s to tens of
#: seconds (it ends after DEFAULT_PLAN_CANDIDATES candidates), so that the scheduler
#: balances the uneven searches over the workers; its overhead per task is a few ms.
DEFAULT_BATCH_PLANS: int = 1
#: The most candidate plans the seating planner puts to the capture test per design (its
#: ``max_candidates``): the bound that ends a design's search, the same on every worker
#: and every machine, so that a design's row does not depend on where it was computed.
#: It keeps a design's search to tens of seconds where it would otherwise try hundreds
#: of candidates for minutes (docs/performance.md); ``design_fixtures(...,
#: plan_candidates=N)`` and ``wrenchcone design --plan-candidates N`` change it.
DEFAULT_PLAN_CANDIDATES: int = 30
#: Designs planned (stage 2), designs run in Monte Carlo (stage 3), runs per design, seed.
DEFAULT_PLANS: int = 20
DEFAULT_TOP: int = 5
DEFAULT_RUNS: int = 50
DEFAULT_SEED: int = 0

#: Metres: a pin gap within this is a contact of the design's seated pose (the pose solve
#: reaches about 1e-15 m; the scene built from a design uses the same tolerance). A pin
#: touches every feature (edge, vertex) whose gap is within it: all of them are its
#: contacts (two at a concave corner).
DESIGN_CONTACT_TOLERANCE_M: float = 1e-9

#: Dimensionless: a placement is located when the smallest singular value of its
#: nondimensional contact Jacobian (one row (n, (p - com) x n / L) per contact, rows of
#: norm >= 1) exceeds this, i.e. when its locating accuracy 1 / sigma_min is below 1000 m
#: per m. Rounding in a pose solved to 1e-15 m moves sigma_min by about 1e-13; at a double
#: root (normals parallel or concurrent) the solve's error grows to the square root of
#: the residual, about 1e-8 m, and sigma_min by up to about 1e-5: far below this.
LOCATING_SIGMA_MIN: float = 1e-3

#: Metres (in x, y and L theta): poses of one pin triple closer than this are one
#: placement, and the plate-area test lets a part stick out of the usable area by this
#: much. It is DESIGN_CONTACT_TOLERANCE_M / LOCATING_SIGMA_MIN: a located pose whose gaps
#: are within the contact tolerance lies within it of the exact pose (pose error <= gap
#: error / sigma_min), and the poses the vertex solve returns twice near an edge's end
#: differ by 1e-11 to 1e-8 m.
DESIGN_POSE_TOLERANCE_M: float = DESIGN_CONTACT_TOLERANCE_M / LOCATING_SIGMA_MIN

#: The most pin radii a plate offers: each pin triple is solved for every one of the
#: K^3 assignments of K radii to its pins (64 at most), the cost of the geometry stage.
MAX_PIN_RADII: int = 4


class DesignError(ValueError):
    """Bad design input: says what was wrong and what is allowed."""


def _num(v: Any, what: str, positive: bool = False) -> float:
    if isinstance(v, bool):
        raise DesignError(f"{what} must be a number, got {v!r}")
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise DesignError(f"{what} must be a number, got {v!r}") from None
    if not math.isfinite(x) or (positive and x <= 0):
        raise DesignError(f"{what} must be a finite number{' > 0' if positive else ''}, "
                          f"got {v!r}")
    return x


def _count(v: Any, what: str) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise DesignError(f"{what} must be a whole number >= 1, got {v!r}")
    return v


@dataclass(frozen=True)
class Plate:
    """A modular fixture plate: a lattice of holes (module docstring).

    Parameters
    ----------
    pitch : float
        The distance between neighbouring holes (m), > 0.
    extent : tuple of 2 int
        The number of holes along x and y, each >= 1.
    pin_radius : float or None, optional
        The radius of every locating pin (m), in [0, pitch / 2): the one-size shorthand
        of ``pin_radii``. None when the plate offers several radii (read back as None
        then).
    keep_out : tuple of (x0, y0, x1, y1), optional
        Rectangles (m, plate frame) where no pin may go.
    fixed_pins : tuple of (i, j) or (i, j, r), optional
        Holes holding pins already (at most 3): every design uses them. ``r`` is the
        pin's own radius (m, in [0, pitch / 2)); without it the pin has the plate's one
        radius (required with several). Read back as (i, j), the radii in
        ``fixed_radii``.
    pin_radii : tuple of float, optional
        The radii (m) the plate offers, 1 to MAX_PIN_RADII distinct values, each in
        [0, pitch / 2): each hole of a design takes any of them. Give this or
        ``pin_radius``; read back sorted ascending (one value with ``pin_radius``).
    fixed_radii : tuple of float, optional
        The radius (m) of each fixed pin given as (i, j), in their order (as a checked
        plate holds them; an (i, j, r) entry's own r comes first). Read back for every
        fixed pin.

    Raises
    ------
    DesignError
        A value outside the ranges above, neither or both of ``pin_radius`` and
        ``pin_radii``, a malformed rectangle, or a fixed pin outside the plate, in a
        keep-out, repeated, or without its radius on a plate of several radii.
    """

    pitch: float
    extent: tuple[int, int]
    pin_radius: float | None = None
    keep_out: tuple[tuple[float, float, float, float], ...] = ()
    fixed_pins: tuple[tuple[int, int], ...] = ()
    pin_radii: tuple[float, ...] = ()
    fixed_radii: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "pitch", _num(self.pitch, "plate pitch (m)", positive=True))
        ext = self.extent
        if isinstance(ext, (str, bytes)) or not isinstance(ext, Sequence) or len(ext) != 2:
            raise DesignError(f"plate extent must be [nx, ny] holes, got {ext!r}")
        set_(self, "extent", (_count(ext[0], "plate extent nx"), _count(ext[1],
                                                                         "plate extent ny")))
        radii = self.pin_radii
        if self.pin_radius is not None and radii is not None and len(radii) and tuple(
                radii) != (self.pin_radius,):  # both: only as a checked plate has them
            raise DesignError("give pin_radius (one size) or pin_radii (several), not both")
        if self.pin_radius is not None:
            radii = (self._radius(self.pin_radius, "pin_radius"),)
        elif (radii is None or isinstance(radii, (str, bytes)) or not isinstance(
                radii, Sequence) or not 1 <= len(radii) <= MAX_PIN_RADII):
            raise DesignError(f"pin_radii must be a list of 1 to {MAX_PIN_RADII} radii (m), "
                              f"got {radii!r}")
        else:
            radii = tuple(self._radius(r, f"pin_radii {k + 1}") for k, r in enumerate(radii))
            if len({f"{r * 1000:.6g}" for r in radii}) != len(radii):
                raise DesignError(f"pin_radii must be distinct (to 6 significant digits "
                                  f"in mm), got {list(radii)}")
            radii = tuple(sorted(radii))
        set_(self, "pin_radii", radii)
        set_(self, "pin_radius", radii[0] if len(radii) == 1 else None)
        boxes = []
        for k, b in enumerate(self.keep_out):
            if isinstance(b, (str, bytes)) or not isinstance(b, Sequence) or len(b) != 4:
                raise DesignError(f"keep_out {k + 1} must be [x0, y0, x1, y1] (m), got {b!r}")
            x0, y0, x1, y1 = (_num(v, f"keep_out {k + 1}") for v in b)
            if not (x0 < x1 and y0 < y1):
                raise DesignError(f"keep_out {k + 1} must have x0 < x1 and y0 < y1, got {b!r}")
            boxes.append((x0, y0, x1, y1))
        set_(self, "keep_out", tuple(boxes))
        pins, fixed_r = [], []
        given_r = tuple(self.fixed_radii) if self._normalised() else ()
        for k, h in enumerate(self.fixed_pins):
            if (isinstance(h, (str, bytes)) or not isinstance(h, Sequence)
                    or len(h) not in (2, 3)):
                raise DesignError(f"fixed pin {k + 1} must be a hole [i, j] or a hole and "
                                  f"its radius [i, j, r], got {h!r}")
            i, j = h[0], h[1]
            if len(h) == 3:
                fixed_r.append(self._radius(h[2], f"fixed pin {k + 1}'s radius"))
            elif given_r:
                fixed_r.append(self._radius(given_r[k], f"fixed pin {k + 1}'s radius"))
            elif len(radii) == 1:
                fixed_r.append(radii[0])
            else:
                raise DesignError(f"fixed pin {k + 1} must give its radius [i, j, r] (m): "
                                  f"the plate offers several, {list(radii)}; got {h!r}")
            if (isinstance(i, bool) or isinstance(j, bool) or not isinstance(i, int)
                    or not isinstance(j, int) or not (0 <= i < self.extent[0])
                    or not (0 <= j < self.extent[1])):
                raise DesignError(f"fixed pin {k + 1} must be a hole [i, j] with 0 <= i < "
                                  f"{self.extent[0]} and 0 <= j < {self.extent[1]}, got {h!r}")
            if self.blocked(i, j):
                raise DesignError(f"fixed pin {k + 1} at hole {[i, j]} lies in a keep-out")
            pins.append((i, j))
        if len(set(pins)) != len(pins) or len(pins) > 3:
            raise DesignError(f"fixed_pins must be at most 3 distinct holes, got {pins}")
        set_(self, "fixed_pins", tuple(pins))
        set_(self, "fixed_radii", tuple(fixed_r))
        every = set((*radii, *fixed_r))
        if len({f"{r * 1000:.6g}" for r in every}) != len(every):
            raise DesignError(f"the radii of the pins and fixed pins must be equal or "
                              f"differ in 6 significant digits (mm), got {sorted(every)}")

    def _normalised(self) -> bool:
        """Whether ``fixed_radii`` came with the fixed pins (a copy of a checked plate)."""
        return bool(self.fixed_radii) and len(self.fixed_radii) == len(self.fixed_pins)

    def _radius(self, v: Any, what: str) -> float:
        r = _num(v, f"{what} (m)")
        if r < 0 or r >= self.pitch / 2:
            raise DesignError(f"{what} must be in [0, pitch / 2) = [0, {self.pitch / 2:g}) m "
                              f"(two pins in neighbouring holes must not overlap), got {v!r}")
        return r

    @property
    def mixed(self) -> bool:
        """Whether the pins of a design may differ in radius (several radii offered, or a
        fixed pin of a radius other than the plate's one)."""
        return len(set((*self.pin_radii, *self.fixed_radii))) > 1

    def fixed_radius(self, i: int, j: int) -> float | None:
        """The radius (m) of the fixed pin in hole (i, j), None when no pin is fixed there.

        Parameters
        ----------
        i, j : int
            The hole's indices along x and y.

        Returns
        -------
        float or None
            m.
        """
        for h, r in zip(self.fixed_pins, self.fixed_radii):
            if h == (i, j):
                return r
        return None

    def hole(self, i: int, j: int) -> tuple[float, float]:
        """Position (m, plate frame) of hole (i, j).

        Parameters
        ----------
        i, j : int
            The hole's indices along x and y.

        Returns
        -------
        tuple of 2 float
            (x, y) = (i pitch, j pitch), m.
        """
        return (i * self.pitch, j * self.pitch)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """The usable area (x0, y0, x1, y1), m: half a pitch around the outermost holes."""
        h = self.pitch / 2
        return (-h, -h, (self.extent[0] - 1) * self.pitch + h,
                (self.extent[1] - 1) * self.pitch + h)

    def blocked(self, i: int, j: int) -> bool:
        """Whether hole (i, j) lies in a keep-out rectangle (boundary included).

        Parameters
        ----------
        i, j : int
            The hole's indices along x and y.

        Returns
        -------
        bool
            True when a pin may not go there.
        """
        x, y = self.hole(i, j)
        return any(x0 <= x <= x1 and y0 <= y <= y1 for x0, y0, x1, y1 in self.keep_out)

    def to_dict(self) -> dict:
        """The plate in the YAML schema of the module docstring.

        Returns
        -------
        dict
            ``pitch``, ``extent``, ``pin_radius`` (one size) or ``pin_radii``,
            ``keep_out``, ``fixed_pins`` ([i, j], or [i, j, r] for a pin whose radius is
            not the plate's one).
        """
        one = self.pin_radius
        d = {"pitch": self.pitch, "extent": list(self.extent)}
        d.update({"pin_radius": one} if one is not None else {"pin_radii": list(self.pin_radii)})
        d.update(keep_out=[list(b) for b in self.keep_out],
                 fixed_pins=[list(h) if r == one else [*h, r]
                             for h, r in zip(self.fixed_pins, self.fixed_radii)])
        return d


_PLATE_KEYS = {"pitch", "extent", "pin_radius", "pin_radii", "keep_out", "fixed_pins"}


def plate_from_dict(d: Any) -> Plate:
    """A :class:`Plate` from the YAML schema of the module docstring.

    Parameters
    ----------
    d : Mapping
        The plate's keys.

    Returns
    -------
    Plate
        The plate.

    Raises
    ------
    DesignError
        ``d`` is not a mapping, misses a required key, has an unknown key or a bad value.
    """
    check_keys(d, _PLATE_KEYS, "plate", DesignError)
    for key in ("pitch", "extent"):
        if key not in d:
            raise DesignError(f"plate: missing required key {key!r}")
    if "pin_radius" not in d and "pin_radii" not in d:
        raise DesignError("plate: missing required key 'pin_radius' (or 'pin_radii', "
                          "several sizes)")
    if "pin_radius" in d and "pin_radii" in d:
        raise DesignError("plate: give pin_radius (one size) or pin_radii (several), "
                          "not both")
    if "pin_radius" in d and d["pin_radius"] is None:
        raise DesignError("pin_radius (m) must be a number, got None")
    radii = d.get("pin_radii")
    return Plate(d["pitch"], tuple(d["extent"]) if isinstance(d["extent"], list)
                 else d["extent"], d.get("pin_radius"), tuple(d.get("keep_out") or ()),
                 tuple(tuple(h) if isinstance(h, list) else h
                       for h in (d.get("fixed_pins") or ())),
                 tuple(radii) if isinstance(radii, list) else radii)


def load_plate(source: str | Path | Mapping | Plate) -> Plate:
    """A plate from a YAML file, a parsed dict, or a Plate.

    Parameters
    ----------
    source : str, Path, Mapping or Plate
        A YAML file, its parsed content, or a plate (returned as is).

    Returns
    -------
    Plate
        The plate.

    Raises
    ------
    DesignError
        The file cannot be read or parsed, or a key or value is invalid (the message names
        the file).
    """
    if isinstance(source, Plate):
        return source
    if isinstance(source, Mapping):
        return plate_from_dict(source)
    path = Path(source)
    data = read_yaml(path, DesignError, "plate file ")
    try:
        return plate_from_dict(data)
    except DesignError as exc:
        raise DesignError(f"{path}: {exc}") from None


@dataclass(frozen=True)
class RegionWork:
    """The work counts of a design's start region (the arguments of the planner's
    ``certify_region``): bounds of work, never of time, so that a design's region is the
    same on every machine.

    Parameters
    ----------
    grid : int, optional
        Cover points per axis (>= 1; DESIGN_REGION_GRID).
    bisections : int, optional
        Bisection steps per stage of the shrinking (>= 0; DESIGN_REGION_BISECTIONS).
    sampled : int, optional
        Models drawn from the uncertainty that each cover point is also run under
        (>= 0; DESIGN_REGION_SAMPLED).
    draws : int, optional
        Starts drawn uniformly in each box checked, each with a drawn model (>= 0;
        DESIGN_REGION_DRAWS).

    Raises
    ------
    DesignError
        A count that is not a whole number in range.
    """

    grid: int = DESIGN_REGION_GRID
    bisections: int = DESIGN_REGION_BISECTIONS
    sampled: int = DESIGN_REGION_SAMPLED
    draws: int = DESIGN_REGION_DRAWS

    def __post_init__(self) -> None:
        for name, least in (("grid", 1), ("bisections", 0), ("sampled", 0), ("draws", 0)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < least:
                raise DesignError(f"region work: {name} must be a whole number >= {least}, "
                                  f"got {v!r}")

    def to_dict(self) -> dict:
        """The counts by name.

        Returns
        -------
        dict
            ``grid``, ``bisections``, ``sampled``, ``draws``.
        """
        return {"grid": self.grid, "bisections": self.bisections, "sampled": self.sampled,
                "draws": self.draws}


def as_start_region(value) -> StartRegion | None:
    """A design's start region from None (none), a StartRegion or three half-widths
    (dx m, dy m, dtheta rad).

    Parameters
    ----------
    value : StartRegion, sequence of 3 float or None
        The region.

    Returns
    -------
    StartRegion or None

    Raises
    ------
    DesignError
        Not three finite half-widths >= 0 (dtheta at most pi).
    """
    if value is None:
        return None
    try:
        return StartRegion.of(value)
    except PlanError as exc:
        raise DesignError(str(exc)) from None


@dataclass(frozen=True)
class DesignProblem:
    """Everything a design run depends on.

    Parameters
    ----------
    part : Scene
        The workpiece of a scene (its polygon, mass, inertia, com; the scene's pose and
        fixels are not used, its friction is the nominal mu).
    plate : Plate
        The plate.
    uncertainty : Uncertainty or None, optional
        Friction intervals: the hold, funnel and plans are robust to them; None or
        NOMINAL: the nominal friction only (stored as NOMINAL).
    actuator : Actuator, optional
        A tray tilt by default, or a spring at a point of the part.
    start_offset : float, optional
        The loading task (m, module docstring).
    start_region : StartRegion, sequence of 3 float or None, optional
        The loading task's start region around the loading start, half-widths (dx m,
        dy m, dtheta rad), e.g. DEFAULT_START_REGION; None (default): the loading start
        only (module docstring).
    region_work : RegionWork, optional
        The work counts of the start region.

    Raises
    ------
    DesignError
        A part that is not a polygon scene, a plate that is not a Plate, a negative
        start offset, a bad start region, or an uncertainty other than one friction
        interval for every pin.
    """

    part: Scene
    plate: Plate
    uncertainty: Uncertainty = NOMINAL
    actuator: Actuator = field(default_factory=Actuator)
    start_offset: float = DEFAULT_START_OFFSET_M
    start_region: StartRegion | None = None
    region_work: RegionWork = field(default_factory=RegionWork)

    def __post_init__(self) -> None:
        if not isinstance(self.part, Scene):
            raise DesignError(f"part must be a Scene (its workpiece), got {self.part!r}")
        if not isinstance(self.part.workpiece.shape, Polygon):
            raise DesignError("the part must be a polygon (a disc has no locating "
                              "three-pin fixture: it turns freely about its centre)")
        if not isinstance(self.plate, Plate):
            raise DesignError(f"plate must be a Plate, got {self.plate!r}")
        object.__setattr__(self, "actuator", Actuator.parse(self.actuator))
        off = _num(self.start_offset, "start_offset (m)")
        if off < 0:
            raise DesignError(f"start_offset must be >= 0 m, got {self.start_offset!r}")
        object.__setattr__(self, "start_offset", off)
        object.__setattr__(self, "start_region", as_start_region(self.start_region))
        if not isinstance(self.region_work, RegionWork):
            raise DesignError(f"region_work must be a RegionWork, got {self.region_work!r}")
        try:
            object.__setattr__(self, "uncertainty", as_uncertainty(self.uncertainty))
        except (TypeError, UncertaintyError) as exc:
            raise DesignError(f"uncertainty: {exc}") from None
        if self.uncertainty.nonlinear(self.part):
            raise DesignError("fixture designs are checked in simulation for friction "
                              "intervals only: give Uncertainty(friction=(lo, hi))")
        f = self.uncertainty.friction
        if f is not None and not isinstance(f[0], (int, float)):
            raise DesignError("give one friction interval (lo, hi) for every pin: "
                              "the pins of a design are not known in advance")

    @property
    def vertices(self) -> tuple[tuple[float, float], ...]:
        """The part's polygon (m, workpiece frame, counter-clockwise)."""
        return self.part.workpiece.shape.vertices

    def friction_interval(self) -> tuple[float, float]:
        """The friction interval of every pin (the nominal mu twice when none is given).

        Returns
        -------
        tuple of 2 float
            [mu_lo, mu_hi].
        """
        if self.uncertainty.friction is None:
            return (self.part.friction, self.part.friction)
        return tuple(self.uncertainty.friction)

    def to_dict(self) -> dict:
        """A plain dict (what a worker needs to rebuild the problem).

        Returns
        -------
        dict
            ``part``, ``plate``, ``uncertainty``, ``actuator``, ``start_offset``,
            ``start_region`` (half-widths, or None), ``region_work``.
        """
        region = self.start_region
        return {"part": self.part.to_dict(), "plate": self.plate.to_dict(),
                "uncertainty": self.uncertainty.to_dict(),
                "actuator": self.actuator.to_dict(), "start_offset": self.start_offset,
                "start_region": None if region is None else list(region.half_widths),
                "region_work": self.region_work.to_dict()}

    @staticmethod
    def from_dict(d: Mapping) -> DesignProblem:
        """The problem that :meth:`to_dict` wrote.

        Parameters
        ----------
        d : Mapping
            The dict of :meth:`to_dict`.

        Returns
        -------
        DesignProblem
            The problem.
        """
        a = dict(d["actuator"])
        act = Actuator(a["kind"], a["tilt"], None if a["point"] is None else tuple(a["point"]),
                       a["magnitude"], a["follow"])
        unc = Uncertainty(**{k: (tuple(v) if isinstance(v, list) else v)
                             for k, v in (d["uncertainty"] or {}).items()})
        return DesignProblem(load_scene(d["part"]), plate_from_dict(d["plate"]), unc, act,
                             d["start_offset"], d.get("start_region"),
                             RegionWork(**d.get("region_work", {})))


__all__ = ["DEFAULT_BATCH_PLANS", "DEFAULT_BATCH_TRIPLES", "DEFAULT_PLAN_CANDIDATES",
           "DEFAULT_PLANS", "DEFAULT_RUNS",
           "DEFAULT_SEED", "DEFAULT_START_OFFSET_M", "DEFAULT_START_REGION", "DEFAULT_TOP",
           "DESIGN_CONTACT_TOLERANCE_M", "DESIGN_POSE_TOLERANCE_M", "DESIGN_REGION_BISECTIONS",
           "DESIGN_REGION_DRAWS", "DESIGN_REGION_GRID", "DESIGN_REGION_SAMPLED",
           "DesignError", "DesignProblem", "LOCATING_SIGMA_MIN", "MAX_PIN_RADII", "Plate",
           "RegionWork", "as_start_region", "load_plate", "plate_from_dict"]
