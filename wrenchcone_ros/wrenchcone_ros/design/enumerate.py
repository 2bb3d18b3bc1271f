# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Stage 1, geometry and location: every placement of three pins in the plate's holes
and every pose of the part touching all three, up to the lattice's translations.

Pin triples are enumerated modulo translation (Brost and Goldberg's reduction): the
lexicographically smallest hole of a triple is moved to (0, 0), so a triple is a pair of
hole offsets h2 < h3, both > (0, 0) (lexicographic order), no two pins farther apart
than the part's diameter plus two of the largest pin radius (no part can touch both).

Each pin of a triple takes any of the plate's radii (a fixed pin keeps its own): every
one of the K^3 radius assignments of a triple is solved (:meth:`Enumerator.
radius_assignments`; K = 1 on a plate of one pin size), each a placement family of its
own (another pin, another seat). The radii are chosen per triple, not per hole: a triple
is a set of hole offsets up to translation, and the radius is a property of the pin put
into a hole, chosen with the design; the candidates are the triples times at most
MAX_PIN_RADII^3 assignments. For each triple and assignment every assignment of contact
features (edges and convex vertices, :class:`Features` of each pin's radius) to the
three pins that the pin distances allow (:func:`feature_triples`) is solved in
closed form (:func:`.geometry.solve_poses`); a pose is kept when, measured on the whole
polygon, all three pins touch (gap within DESIGN_CONTACT_TOLERANCE_M) and none
penetrates. Its angle is taken in (-pi, pi]; poses of one triple within
DESIGN_POSE_TOLERANCE_M of each other (in x, y and L theta, the angle modulo 2 pi) are
one placement, found through several feature triples (a pin in a concave corner, or at
an edge's end) or twice by the solve: one row per physical placement. Each pin carries
every contact it makes there (:func:`.geometry.pin_contacts`: both edges of a concave
corner), and location and accuracy use them all (:func:`.geometry.locate`).

A placement is then put on the plate: the translations (a, b) (whole holes) at which
every pin is in a hole of the plate and outside every keep-out, the plate's fixed pins
are among its pins with their radii (every other pin of a radius the plate offers), and
the part lies inside the plate's usable area (up to DESIGN_POSE_TOLERANCE_M). Placements
with none are dropped (counted as ``outside``); the others keep the smallest such translation
(lexicographic) as their position and the number of them as ``placements``.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from .geometry import (
    Features,
    PinContact,
    convex_vertices,
    locate,
    pin_contacts,
    pin_gaps,
    solve_poses,
)
from .problem import DESIGN_CONTACT_TOLERANCE_M, DESIGN_POSE_TOLERANCE_M, DesignProblem, Plate

Triple = tuple[tuple[int, int], tuple[int, int]]


@dataclass(frozen=True)
class Placement:
    """A pose of the part touching three pins, on the plate.

    Parameters
    ----------
    triple : tuple of 2 (int, int)
        The offsets (holes) of pins 2 and 3 from pin 1.
    index : int
        The pose's number among the triple's poses.
    holes : tuple of 3 (int, int)
        The three pins' holes (i, j).
    positions : tuple of 3 (float, float)
        The three pins' centres (m, plate frame).
    pose : tuple of 3 float
        (x m, y m, theta rad), plate frame.
    features : tuple of 3 str
        The contact features of each pin ("e3": edge 3 from vertex 3 to vertex 4, "v2":
        vertex 2; "e2+e3": both edges of a concave corner, "e2+v3": edge 2 at its end).
    located : bool
        Whether the pins locate the part (:func:`.geometry.locating_accuracy`).
    accuracy : float
        ||N^-1||_2 (m per m; :func:`.geometry.locating_accuracy`).
    placements : int
        How many translations fit the plate.
    contacts : tuple of 3 tuple of PinContact, optional
        Every contact of each pin (:func:`.geometry.pin_contacts`).
    radii : tuple of 3 float, optional
        Each pin's radius (m).
    radius_tag : str, optional
        ``"@r1,r2,r3"`` (mm) in the design's name on a plate whose pins may differ in
        radius, empty on a plate of one pin size.
    """

    triple: Triple
    index: int
    holes: tuple[tuple[int, int], ...]
    positions: tuple[tuple[float, float], ...]
    pose: tuple[float, float, float]
    features: tuple[str, str, str]
    located: bool
    accuracy: float
    placements: int
    contacts: tuple[tuple[PinContact, ...], ...] = ()
    radii: tuple[float, ...] = ()
    radius_tag: str = ""

    @property
    def design_id(self) -> str:
        """The design's name: ``"a,b;c,d#k"`` (the triple's offsets, the pose's index),
        ``"a,b;c,d@r1,r2,r3#k"`` with the pins' radii (mm) on a plate of several."""
        (a, b), (c, d) = self.triple
        return f"{a},{b};{c},{d}{self.radius_tag}#{self.index}"


def radius_tag(radii) -> str:
    """``"@r1,r2,r3"``: the pins' radii in mm (6 significant digits), as design names
    carry them on a plate of several radii.

    Parameters
    ----------
    radii : sequence of float
        The pins' radii (m).

    Returns
    -------
    str
        The tag.
    """
    return "@" + ",".join(f"{r * 1000:.6g}" for r in radii)


def diameter(vertices) -> float:
    """The largest distance between two vertices of a polygon.

    Parameters
    ----------
    vertices : array_like
        The vertices, (n, 2), m.

    Returns
    -------
    float
        m.
    """
    V = np.asarray(vertices, dtype=float)
    return float(np.max(np.hypot(*(V[:, None, :] - V[None, :, :]).transpose(2, 0, 1))))


def pin_triples(problem: DesignProblem) -> list[Triple]:
    """Every pin triple modulo translation (module docstring), in a fixed order.

    Parameters
    ----------
    problem : DesignProblem
        The problem (the part's size, the plate).

    Returns
    -------
    list of Triple
        ((i2, j2), (i3, j3)): the offsets of pins 2 and 3 from pin 1.
    """
    plate = problem.plate
    reach = diameter(problem.vertices) + 2 * max((*plate.pin_radii, *plate.fixed_radii))
    k = int(math.floor(reach / plate.pitch))
    nx, ny = plate.extent
    offs = [(i, j) for i in range(0, min(k, nx - 1) + 1)
            for j in range(-min(k, ny - 1), min(k, ny - 1) + 1)
            if (i > 0 or j > 0) and math.hypot(i, j) * plate.pitch <= reach]
    offs.sort()
    out = []
    for a, h2 in enumerate(offs):
        for h3 in offs[a + 1:]:
            if (math.hypot(h3[0] - h2[0], h3[1] - h2[1]) * plate.pitch <= reach
                    and max(0, h2[0], h3[0]) - min(0, h2[0], h3[0]) < nx
                    and max(0, h2[1], h3[1]) - min(0, h2[1], h3[1]) < ny
                    and _may_hold_fixed((h2, h3), plate.fixed_pins)):
                out.append((h2, h3))
    return out


def _may_hold_fixed(triple: Triple, fixed) -> bool:
    """Whether some translation puts every fixed pin on a pin of the triple (always
    true without fixed pins): a triple that cannot is not enumerated at all."""
    if not fixed:
        return True
    offs = [(0, 0), *triple]
    fi, fj = fixed[0]
    for oi, oj in offs:  # the first fixed pin on one of the three pins
        a, b = fi - oi, fj - oj
        holes = {(a + i, b + j) for i, j in offs}
        if all(tuple(f) in holes for f in fixed):
            return True
    return False


def _feature_distances(V: np.ndarray, convex: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For every pair of features (the edges, then the ``convex`` vertices): their
    smallest and largest distance (m)."""
    n = len(V)
    segs = [(V[k], V[(k + 1) % n]) for k in range(n)] + [(V[v], V[v]) for v in convex]

    def pt_seg(p, a, b):
        e = b - a
        den = float(e @ e)
        t = 0.0 if den == 0 else min(1.0, max(0.0, float((p - a) @ e) / den))
        return float(np.linalg.norm(p - (a + t * e)))

    m = len(segs)
    near, far = np.zeros((m, m)), np.zeros((m, m))
    for i, (a, b) in enumerate(segs):
        for j, (c, d) in enumerate(segs):
            near[i, j] = min(pt_seg(a, c, d), pt_seg(b, c, d), pt_seg(c, a, b),
                             pt_seg(d, a, b))
            far[i, j] = max(np.linalg.norm(p - q) for p in (a, b) for q in (c, d))
    return near, far


def _distance_bounds(near: np.ndarray, far: np.ndarray, ra: float, rb: float
                     ) -> tuple[np.ndarray, np.ndarray]:
    """For every pair of features: the smallest and largest distance (m) two pin centres
    touching them can have, pins of radii ra and rb (the features' own distances, minus /
    plus ra + rb)."""
    return (np.maximum(0.0, near - (ra + rb)) - 1e-12, far + (ra + rb) + 1e-12)


class Enumerator:
    """The geometry stage for one problem (features per pin radius and distance bounds
    per pair of radii, each made once).

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    """

    def __init__(self, problem: DesignProblem):
        self.problem = problem
        plate = problem.plate
        self.V = np.asarray(problem.vertices, dtype=float)
        convex = convex_vertices(self.V)
        n = len(self.V)
        self.codes = np.concatenate([np.arange(n), n + convex])  # every pin radius's
        self._vertex = self.codes >= n
        self._near, self._far = _feature_distances(self.V, convex)
        self._features: dict[float, Features] = {}
        self._bounds: dict[tuple[float, float], tuple[np.ndarray, np.ndarray]] = {}
        self.F = self.features(plate.pin_radii[0])
        self.L = problem.part.length_scale
        self.com = problem.part.workpiece.com

    def features(self, r: float) -> Features:
        """The part's features for a pin of radius ``r`` (made once per radius).

        Parameters
        ----------
        r : float
            The pin radius (m).

        Returns
        -------
        Features
            The features.
        """
        if r not in self._features:
            self._features[r] = Features.of(self.V, r)
        return self._features[r]

    def _bounds_of(self, ra: float, rb: float) -> tuple[np.ndarray, np.ndarray]:
        if (ra, rb) not in self._bounds:
            self._bounds[(ra, rb)] = _distance_bounds(self._near, self._far, ra, rb)
        return self._bounds[(ra, rb)]

    def feature_triples(self, pins: np.ndarray, radii: Sequence[float] | None = None
                        ) -> np.ndarray:
        """Feature triples (codes, (N, 3)) that the three pins' distances allow (a
        vertex only for a pin of positive radius).

        Parameters
        ----------
        pins : numpy.ndarray
            The pins' centres, (3, 2), m.
        radii : sequence of 3 float or None, optional
            Each pin's radius (m); None: the plate's first radius for all three.

        Returns
        -------
        numpy.ndarray
            Feature codes, (N, 3).
        """
        r = tuple(radii) if radii is not None else (self.F.r,) * 3

        def ok(a, b):
            d = float(np.linalg.norm(pins[a] - pins[b]))
            lo, hi = self._bounds_of(r[a], r[b])
            return (lo <= d) & (d <= hi)
        m = ok(0, 1)[:, :, None] & ok(0, 2)[:, None, :] & ok(1, 2)[None, :, :]
        for k in range(3):
            if r[k] <= 0:  # a point pin touches no vertex alone
                shape = [1, 1, 1]
                shape[k] = -1
                m &= ~self._vertex.reshape(shape)
        idx = np.argwhere(m)
        return self.codes[idx]

    def radius_assignments(self, triple: Triple) -> list[tuple[float, float, float]]:
        """The radii (m) the three pins of ``triple`` may take, ascending (module
        docstring): every assignment of the plate's radii, a pin in a fixed pin's hole
        with that pin's radius, over the translations that put every fixed pin on the
        triple inside the plate. One assignment on a plate of one pin size.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.

        Returns
        -------
        list of tuple of 3 float
            The assignments, each pin's radius in the order of the triple's pins.
        """
        plate = self.problem.plate
        if not plate.mixed:
            return [(plate.pin_radii[0],) * 3]
        if not plate.fixed_pins:
            return list(itertools.product(plate.pin_radii, repeat=3))
        return sorted({a for t in _fixed_translations(plate, triple)
                       for a in itertools.product(*(
                           [plate.fixed_radius(*h)] if plate.fixed_radius(*h) is not None
                           else plate.pin_radii for h in t))})

    def poses(self, triple: Triple, radii: Sequence[float] | None = None
              ) -> list[tuple[tuple, tuple]]:
        """Distinct poses (x, y, theta) touching the pins of ``triple`` with pin 1 at
        the origin (module docstring), and the largest gap of each, in a fixed order.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.
        radii : sequence of 3 float or None, optional
            Each pin's radius (m); None: the plate's first radius for all three.

        Returns
        -------
        list of (tuple, float)
            (pose (x m, y m, theta rad), its largest pin gap (m)).
        """
        p = self.problem.plate.pitch
        pins = np.array([(0.0, 0.0), (triple[0][0] * p, triple[0][1] * p),
                         (triple[1][0] * p, triple[1][1] * p)])
        r = tuple(radii) if radii is not None else (self.F.r,) * 3
        codes = self.feature_triples(pins, r)
        poses, _rows = solve_poses(tuple(self.features(v) for v in r), pins, codes, self.L)
        if not len(poses):
            return []
        gaps, _feats = pin_gaps(self.V, poses, np.broadcast_to(pins, (len(poses), 3, 2)),
                                np.array(r))
        worst = np.max(np.abs(gaps), axis=1)
        good = np.flatnonzero(worst <= DESIGN_CONTACT_TOLERANCE_M)
        tol, L = DESIGN_POSE_TOLERANCE_M, self.L
        kept: list[tuple[list, float]] = []
        for i in good[np.argsort(worst[good], kind="stable")].tolist():  # best solved first
            q = poses[i].tolist()
            q[2] = math.remainder(q[2], 2 * math.pi)
            if q[2] <= -math.pi:
                q[2] += 2 * math.pi
            if not any(abs(q[0] - o[0]) <= tol and abs(q[1] - o[1]) <= tol
                       and abs(math.remainder(q[2] - o[2], 2 * math.pi)) * L <= tol
                       for o, _w in kept):
                kept.append((q, float(worst[i])))
        return [(tuple(v + 0.0 for v in q), w) for q, w in sorted(kept, key=lambda k: k[0])]

    def fit(self, triple: Triple, pose, radii: Sequence[float] | None = None
            ) -> tuple[int, tuple[int, int] | None]:
        """Translations of the placement that fit the plate (module docstring): how many,
        and the smallest.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.
        pose : tuple of 3 float
            The pose with pin 1 at the origin.
        radii : sequence of 3 float or None, optional
            Each pin's radius (m); None: the plate's radius (a plate of one pin size).

        Returns
        -------
        count : int
            The number of translations (whole holes) that fit.
        first : (int, int) or None
            The smallest, lexicographically; None when none fits.
        """
        plate = self.problem.plate
        nx, ny = plate.extent
        offs = [(0, 0), triple[0], triple[1]]
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)
        W = np.column_stack([x + c * self.V[:, 0] - s * self.V[:, 1],
                             y + s * self.V[:, 0] + c * self.V[:, 1]])
        x0, y0, x1, y1 = plate.bounds
        p = plate.pitch
        # part inside: x0 <= W + a p <= x1 for every vertex
        slack = DESIGN_POSE_TOLERANCE_M / p  # the pose's own error, in pitches
        a_lo = math.ceil((x0 - W[:, 0].min()) / p - slack)
        a_hi = math.floor((x1 - W[:, 0].max()) / p + slack)
        b_lo = math.ceil((y0 - W[:, 1].min()) / p - slack)
        b_hi = math.floor((y1 - W[:, 1].max()) / p + slack)
        count, first = 0, None
        fixed = set(plate.fixed_pins)
        for a in range(max(a_lo, -min(o[0] for o in offs)),
                       min(a_hi, nx - 1 - max(o[0] for o in offs)) + 1):
            for b in range(max(b_lo, -min(o[1] for o in offs)),
                           min(b_hi, ny - 1 - max(o[1] for o in offs)) + 1):
                holes = {(a + i, b + j) for i, j in offs}
                if any(plate.blocked(i, j) for i, j in holes) or not fixed <= holes:
                    continue
                if radii is not None and plate.mixed and not _radii_fit(
                        plate, [(a + i, b + j) for i, j in offs], radii):
                    continue
                count += 1
                if first is None:
                    first = (a, b)
        return count, first

    def placements(self, triple: Triple) -> tuple[list[Placement], int]:
        """The placements of one triple that fit the plate, and how many poses did not.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.

        Returns
        -------
        placements : list of Placement
            The placements that fit.
        outside : int
            The number of poses that fit nowhere.
        """
        out, outside = [], 0
        plate = self.problem.plate
        for radii in self.radius_assignments(triple):
            found, off = self._placements(triple, radii, radius_tag(radii) if plate.mixed
                                          else "")
            out += found
            outside += off
        return out, outside

    def _placements(self, triple: Triple, radii: tuple, tag: str
                    ) -> tuple[list[Placement], int]:
        out, outside = [], 0
        p = self.problem.plate.pitch
        for k, (pose, _gap) in enumerate(self.poses(triple, radii)):
            count, first = self.fit(triple, pose, radii)
            if not count:
                outside += 1
                continue
            a, b = first
            holes = ((a, b), (a + triple[0][0], b + triple[0][1]),
                     (a + triple[1][0], b + triple[1][1]))
            pos = tuple((i * p, j * p) for i, j in holes)
            world = (pose[0] + a * p, pose[1] + b * p, pose[2])
            contacts = tuple(pin_contacts(self.features(r), world, c,
                                          DESIGN_CONTACT_TOLERANCE_M)
                             for c, r in zip(pos, radii))
            c, s = math.cos(world[2]), math.sin(world[2])
            comw = (world[0] + c * self.com[0] - s * self.com[1],
                    world[1] + s * self.com[0] + c * self.com[1])
            located, acc = locate(self.F, [ct for cs in contacts for ct in cs], comw, self.L)
            labels = tuple("+".join(ct.label for ct in cs) or "?" for cs in contacts)
            out.append(Placement(triple, k, holes, pos, world, labels, located, acc, count,
                                 contacts, tuple(radii), tag))
        return out, outside


def _fixed_translations(plate: Plate, triple: Triple) -> list[tuple[tuple[int, int], ...]]:
    """The triple's holes at every translation that keeps it inside the plate and puts
    every fixed pin on one of its pins."""
    nx, ny = plate.extent
    offs = [(0, 0), *triple]
    out = []
    for a in range(-min(o[0] for o in offs), nx - max(o[0] for o in offs)):
        for b in range(-min(o[1] for o in offs), ny - max(o[1] for o in offs)):
            holes = tuple((a + i, b + j) for i, j in offs)
            if set(plate.fixed_pins) <= set(holes):
                out.append(holes)
    return out


def _radii_fit(plate: Plate, holes, radii) -> bool:
    """Whether pins of these radii may stand in these holes: a fixed pin's hole with its
    radius, every other hole with a radius the plate offers."""
    for h, r in zip(holes, radii):
        fr = plate.fixed_radius(*h)
        if (r != fr) if fr is not None else (r not in plate.pin_radii):
            return False
    return True


def enumerate_placements(problem: DesignProblem, triples: Sequence[Triple] | None = None
                         ) -> Iterator[Placement]:
    """Every placement of the problem (module docstring), triple by triple.

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    triples : sequence of Triple or None, optional
        The triples to place (default: every one, :func:`pin_triples`).

    Yields
    ------
    Placement
        Every placement that fits the plate.
    """
    en = Enumerator(problem)
    for t in (pin_triples(problem) if triples is None else triples):
        yield from en.placements(t)[0]


__all__ = ["Enumerator", "Placement", "diameter", "enumerate_placements",
           "pin_triples", "radius_tag"]
