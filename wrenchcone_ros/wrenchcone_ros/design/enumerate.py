# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Stage 1, geometry and location: every placement of three pins in the plate's holes
and every pose of the part touching all three, up to the lattice's translations.

Pin triples are enumerated modulo translation (Brost and Goldberg's reduction): the
lexicographically smallest hole of a triple is moved to (0, 0), so a triple is a pair of
hole offsets h2 < h3, both > (0, 0) (lexicographic order), no two pins farther apart
than the part's diameter plus two pin radii (no part can touch both). For each triple
every assignment of contact features (edges and convex vertices, :class:`Features`) to
the three pins that the pin distances allow (:func:`feature_triples`) is solved in
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
are among its pins, and the part lies inside the plate's usable area (up to
DESIGN_POSE_TOLERANCE_M). Placements with
none are dropped (counted as ``outside``); the others keep the smallest such translation
(lexicographic) as their position and the number of them as ``placements``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from .geometry import Features, PinContact, locate, pin_contacts, pin_gaps, solve_poses
from .problem import DESIGN_CONTACT_TOLERANCE_M, DESIGN_POSE_TOLERANCE_M, DesignProblem

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

    @property
    def design_id(self) -> str:
        """The design's name: ``"a,b;c,d#k"`` (the triple's offsets, the pose's index)."""
        (a, b), (c, d) = self.triple
        return f"{a},{b};{c},{d}#{self.index}"


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
    reach = diameter(problem.vertices) + 2 * plate.pin_radius
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


def _distance_bounds(F: Features) -> tuple[np.ndarray, np.ndarray]:
    """For every pair of features: the smallest and largest distance (m) two pin centres
    touching them can have (the features' own distances, minus / plus 2 r)."""
    V, n = F.vertices, F.n_edges
    segs = [(V[k], V[(k + 1) % n]) for k in range(n)] + [(V[v], V[v]) for v in F.convex]

    def pt_seg(p, a, b):
        e = b - a
        den = float(e @ e)
        t = 0.0 if den == 0 else min(1.0, max(0.0, float((p - a) @ e) / den))
        return float(np.linalg.norm(p - (a + t * e)))

    m = len(segs)
    lo, hi = np.zeros((m, m)), np.zeros((m, m))
    for i, (a, b) in enumerate(segs):
        for j, (c, d) in enumerate(segs):
            near = min(pt_seg(a, c, d), pt_seg(b, c, d), pt_seg(c, a, b), pt_seg(d, a, b))
            far = max(np.linalg.norm(p - q) for p in (a, b) for q in (c, d))
            lo[i, j] = max(0.0, near - 2 * F.r) - 1e-12
            hi[i, j] = far + 2 * F.r + 1e-12
    return lo, hi


class Enumerator:
    """The geometry stage for one problem (features and distance bounds made once).

    Parameters
    ----------
    problem : DesignProblem
        The problem.
    """

    def __init__(self, problem: DesignProblem):
        self.problem = problem
        self.F = Features.of(problem.vertices, problem.plate.pin_radius)
        self.codes = self.F.codes
        self.lo, self.hi = _distance_bounds(self.F)
        self.L = problem.part.length_scale
        self.com = problem.part.workpiece.com
        self.V = np.asarray(problem.vertices, dtype=float)

    def feature_triples(self, pins: np.ndarray) -> np.ndarray:
        """Feature triples (codes, (N, 3)) that the three pins' distances allow.

        Parameters
        ----------
        pins : numpy.ndarray
            The pins' centres, (3, 2), m.

        Returns
        -------
        numpy.ndarray
            Feature codes, (N, 3).
        """
        def ok(a, b):
            d = float(np.linalg.norm(pins[a] - pins[b]))
            return (self.lo <= d) & (d <= self.hi)
        m = ok(0, 1)[:, :, None] & ok(0, 2)[:, None, :] & ok(1, 2)[None, :, :]
        idx = np.argwhere(m)
        return self.codes[idx]

    def poses(self, triple: Triple) -> list[tuple[tuple, tuple]]:
        """Distinct poses (x, y, theta) touching the pins of ``triple`` with pin 1 at
        the origin (module docstring), and the largest gap of each, in a fixed order.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.

        Returns
        -------
        list of (tuple, float)
            (pose (x m, y m, theta rad), its largest pin gap (m)).
        """
        p = self.problem.plate.pitch
        pins = np.array([(0.0, 0.0), (triple[0][0] * p, triple[0][1] * p),
                         (triple[1][0] * p, triple[1][1] * p)])
        codes = self.feature_triples(pins)
        poses, _rows = solve_poses(self.F, pins, codes, self.L)
        if not len(poses):
            return []
        gaps, _feats = pin_gaps(self.V, poses, np.broadcast_to(pins, (len(poses), 3, 2)),
                                self.F.r)
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

    def fit(self, triple: Triple, pose) -> tuple[int, tuple[int, int] | None]:
        """Translations of the placement that fit the plate (module docstring): how many,
        and the smallest.

        Parameters
        ----------
        triple : Triple
            The offsets of pins 2 and 3 from pin 1.
        pose : tuple of 3 float
            The pose with pin 1 at the origin.

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
        p = self.problem.plate.pitch
        for k, (pose, _gap) in enumerate(self.poses(triple)):
            count, first = self.fit(triple, pose)
            if not count:
                outside += 1
                continue
            a, b = first
            holes = ((a, b), (a + triple[0][0], b + triple[0][1]),
                     (a + triple[1][0], b + triple[1][1]))
            pos = tuple((i * p, j * p) for i, j in holes)
            world = (pose[0] + a * p, pose[1] + b * p, pose[2])
            contacts = tuple(pin_contacts(self.F, world, c, DESIGN_CONTACT_TOLERANCE_M)
                             for c in pos)
            c, s = math.cos(world[2]), math.sin(world[2])
            comw = (world[0] + c * self.com[0] - s * self.com[1],
                    world[1] + s * self.com[0] + c * self.com[1])
            located, acc = locate(self.F, [ct for cs in contacts for ct in cs], comw, self.L)
            labels = tuple("+".join(ct.label for ct in cs) or "?" for cs in contacts)
            out.append(Placement(triple, k, holes, pos, world, labels, located, acc, count,
                                 contacts))
        return out, outside


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
           "pin_triples"]
