# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Which way to push: force directions, force regions and path sweeps for a contact mode.

A tilted tray (gravity through the centre of mass) or a spring (a force through a point of
the workpiece) applies a *pure force* at a point. This module answers the question the
other way round from :func:`~wrenchcone_ros.core.batch.wrench_cone`: which force directions
at that point realise a mode, which realise only that mode, which one is most robust.

The plane of a force family
---------------------------
A force f = (f_x, f_y) (N, fixture frame) applied at a point p of the workpiece (workpiece
frame, m) is the wrench about the centre of mass

    w(f) = B f,   B = [[1, 0], [0, 1], [-r_y, r_x]],   r = R(theta) (p - com)  (world axes).

B has rank 2 for every p (its force rows are the identity), so the family is a 2-D plane
P = range(B) of wrench space; p = com gives the plane tau = 0. Intersecting the mode's cone
{F g <= 0, E g = 0} with P gives the 2-D cone of forces

    K = {f : (F B) f <= 0, (E B) f = 0}

whose rows, the *traces* of the facets and equalities on P, are computed in the cone's
nondimensional metric (F_hat (S B), S = diag(1, 1, 1/L)). The direction phi (f = (cos phi,
sin phi)) is in K iff it meets every trace row. A trace row t changes sign only at the two
directions +-rot90(t), so membership of directions can change only at these *breakpoints*;
between two consecutive breakpoints it is constant. The intervals are therefore read off
exactly: test each breakpoint and one probe direction inside each gap between breakpoints
(:func:`_arcs`). No sampling is involved; the endpoints are breakpoints, i.e. directions
where a facet trace vanishes. A wildcard mode (a union of cones) and the exclusive set
(the mode minus every other valid mode) change membership only at breakpoints of one of
the cones involved, so the same procedure answers them with the union of breakpoints.

In float arithmetic membership is :meth:`Cone.contains` of the wrench w(phi) (tolerance
CONE_TOLERANCE on the unit nondimensional direction: endpoints are accurate to about
1e-9 rad). With ``exact=True`` the cones are computed in rational arithmetic (cddlib GMP),
B from the scene's numbers as written, every breakpoint is an exact rational direction
vector, its sign tests are exact, and the intervals carry those vectors
(``lo_direction``, ``hi_direction``); only the angles are rounded (atan2 of the exact
vector). cos/sin of a pose angle other than 0 are rounded once (docs/numerics.md).

Closedness. Cones are closed, so are the intervals. The exclusive set is reported as its
closure (interval endpoints are where another mode begins); a single direction inside an
exclusive interval where another mode's cone only touches the plane P is not removed.

The most robust direction (``best``)
------------------------------------
The margin of a direction is :meth:`Cone.margin` of w(phi) (wildcards: the largest piece
margin, :class:`~.wrenchset.WrenchSet`); for ``exclusive`` it is min(margin in the mode, distance of
the unit nondimensional direction to every other mode's cone), the distance to the
nearest wrench that is outside the mode or inside another mode. ``best`` maximises it
over the interval by a bounded optimiser: a grid of :data:`BEST_GRID` directions over the
interval picks a bracket, then Brent's bounded method (scipy ``minimize_scalar``) refines
it to BEST_DIRECTION_XATOL (core/tolerances.py). Why that finds the maximum for a concrete mode: inside a full-
dimensional cone the margin is min_i(-F_hat_i u) with u the unit vector of S B f in the
2-D plane S P; parametrised by its angle psi in that plane (a monotone reparametrisation
of phi) each term is rho_i cos(psi - gamma_i) and non-negative on the interval, hence
concave there, and a minimum of concave functions is concave: unimodal, so the refinement
of the best grid bracket is the global maximum. Unions and exclusive sets are not
unimodal; the grid then decides which local maximum is refined (tested against dense
sampling in test/core/test_directions.py). Cones with an empty interior have margin 0 on
their directions; ``best`` is then the middle of the interval.

Tray tilt (:func:`tilt_gravity_force`, :func:`tilt_directions`)
---------------------------------------------------------------
A tray (the fixture plane) tilted by angle alpha (rad, 0 < alpha <= pi/2) whose direction
of steepest descent, projected on the fixture plane, has angle psi (rad, fixture frame,
counter-clockwise from x) pulls the workpiece of mass m in its plane with the force
m g sin(alpha) (cos psi, sin psi) at the centre of mass (g = STANDARD_GRAVITY = 9.80665 m/s^2); the normal
component m g cos(alpha) presses it onto the tray and is not part of the planar model
(support friction of the tray is neglected, as in the paper). A tilt about a horizontal
axis of direction angle k (right-hand rule, positive alpha) has psi = k - pi/2. So the
downhill directions that produce a mode are exactly ``force_directions(scene, mode)``
at the com, whatever alpha; the magnitude matters only when another force is present
(a spring preload), which is what :func:`force_region` with an ``offset`` answers.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import cdd
import numpy as np

from .batch import mode_union
from .classify import ModeClassifier, ModeMatch, consistent_modes
from .cones import Cone, _matrix, margins_at
from .modes import ModeError
from .numbers import EXACT, to_exact
from .robust import robust_direction_cones
from .scene import Scene, SceneError
from .uncertainty import Uncertainty, or_nominal
from .wrenchset import Guarantee
from .tolerances import (
    ANGLE_RESOLUTION,
    BEST_DIRECTION_XATOL,
    CONE_TOLERANCE,
    MARGIN_TIE_TOLERANCE,
)

#: Standard gravity, m/s^2 (the tray-tilt convention).
STANDARD_GRAVITY: float = 9.80665

#: Number of grid directions over an interval from which ``best`` is refined (see the
#: module docstring); dimensionless.
BEST_GRID: int = 64


_TWO_PI = 2.0 * math.pi


# --- results ---------------------------------------------------------------------------
@dataclass(frozen=True)
class DirectionInterval:
    """Force directions phi in [lo, hi] (rad, counter-clockwise from lo to hi).

    lo in [-pi, pi), hi in [lo, lo + 2 pi]; a single direction has lo == hi; the whole
    circle is lo = -pi, hi = pi.

    Parameters
    ----------
    lo, hi : float
        The interval's ends (rad, fixture frame).
    best : float
        The direction of largest margin in the interval (in [lo, hi]).
    margin : float
        That margin (dimensionless; for a robust answer the worst case over the models).
    lo_direction, hi_direction : tuple of 2 Fraction or None, optional
        The exact rational direction vectors (x, y) of the endpoints when computed with
        ``exact=True`` (None otherwise, and for the whole circle).
    guarantee : Guarantee or None, optional
        The guarantee of a robust answer.
    """

    lo: float
    hi: float
    best: float
    margin: float
    lo_direction: tuple[Fraction, Fraction] | None = None
    hi_direction: tuple[Fraction, Fraction] | None = None
    guarantee: Guarantee | None = None  # of a robust answer

    @property
    def width(self) -> float:
        """hi - lo (rad)."""
        return self.hi - self.lo

    @property
    def whole_circle(self) -> bool:
        """Whether the interval is the whole circle (lo = -pi, hi = pi)."""
        return self.lo == -math.pi and self.hi == math.pi

    def contains(self, phi: float, tol: float = ANGLE_RESOLUTION) -> bool:
        """Whether direction phi (rad, any branch) lies in the interval.

        Parameters
        ----------
        phi : float
            A direction (rad).
        tol : float, optional
            Slack at the ends (rad).

        Returns
        -------
        bool
            True inside.
        """
        if self.whole_circle:
            return True
        d = (phi - self.lo) % _TWO_PI
        return d <= self.width + tol or d >= _TWO_PI - tol

    def to_dict(self) -> dict:
        """The interval as JSON-able data (angles also in degrees; exact ends as strings).

        Returns
        -------
        dict
            ``lo``, ``hi``, ``best``, ``margin``, their degrees, and the exact directions and
            guarantee where given.
        """
        d = {"lo": self.lo, "hi": self.hi, "best": self.best, "margin": self.margin,
             "lo_deg": math.degrees(self.lo), "hi_deg": math.degrees(self.hi),
             "best_deg": math.degrees(self.best)}
        if self.lo_direction is not None:
            d["lo_direction"] = [str(x) for x in self.lo_direction]
            d["hi_direction"] = [str(x) for x in self.hi_direction]
        if self.guarantee is not None:
            d["guarantee"] = str(self.guarantee)
        return d


# --- the plane of a force family --------------------------------------------------------
def force_point(scene: Scene, point: Sequence[float] | None) -> tuple[float, float]:
    """The application point (workpiece frame, m); None means the centre of mass."""
    if point is None:
        return tuple(float(v) for v in scene.workpiece.com)
    if isinstance(point, (str, bytes)) or len(point) != 2:
        raise ValueError(f"point must be a pair (x, y) in metres, workpiece frame; got {point!r}")
    x, y = (float(v) for v in point)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"point must be finite, got {list(point)}")
    return x, y


def force_basis(scene: Scene, point: Sequence[float] | None = None, exact: bool = False
                ) -> np.ndarray:
    """B (3 x 2, SI): the wrench about the com of a force f at ``point`` is B f.

    Columns (1, 0, -r_y) and (0, 1, r_x), r = R(theta) (p - com) in world axes (m).
    ``exact=True``: Fractions from the scene's numbers as written (cos/sin of theta != 0
    rounded once, :mod:`.numbers`).

    Parameters
    ----------
    scene : Scene
        The scene (its pose and com).
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    exact : bool, optional
        Fractions instead of floats.

    Returns
    -------
    numpy.ndarray
        B, 3 x 2.

    Raises
    ------
    ValueError
        ``point`` is not two finite numbers.
    """
    px, py = force_point(scene, point)
    ar = EXACT if exact else None
    conv = ar.convert if exact else float
    cx, cy = (conv(v) for v in scene.workpiece.com)
    c, s = EXACT.cos_sin(conv(scene.pose[2])) if exact else (
        math.cos(scene.pose[2]), math.sin(scene.pose[2]))
    dx, dy = conv(px) - cx, conv(py) - cy
    rx, ry = c * dx - s * dy, s * dx + c * dy
    one, zero = conv(1), conv(0)
    return np.array([[one, zero], [zero, one], [-ry, rx]], dtype=object if exact else float)


def _nondim_basis(scene: Scene, B: np.ndarray, exact: bool) -> np.ndarray:
    """S B, S = diag(1, 1, 1/L) (L as the cones use it)."""
    L = to_exact(scene.length_scale) if exact else float(scene.length_scale)
    out = B.copy()
    out[2, :] = out[2, :] / L
    return out


def trace_rows(cone: Cone, B_hat: np.ndarray, exact: bool = False
               ) -> tuple[list, list]:
    """The traces on the force plane of the cone's facets and equalities: rows of
    F_hat (S B) (``f`` meets facet i iff row_i . f <= 0) and of E_hat (S B) (= 0).

    ``exact=True`` uses the cone's exact representation (Fractions).

    Parameters
    ----------
    cone : Cone
        The cone.
    B_hat : numpy.ndarray
        S B, 3 x 2.
    exact : bool, optional
        Use the cone's exact rows.

    Returns
    -------
    F : list of list
        The facets' traces, (k, 2).
    E : list of list
        The equalities' traces, (e, 2).
    """
    if exact:
        rep = cone.exact_rep
        F = np.array(rep.F, dtype=object).reshape(-1, 3)
        E = np.array(rep.E, dtype=object).reshape(-1, 3)
    else:
        F, E = cone.F_hat, cone.E_hat
    return [list(r) for r in (F @ B_hat)], [list(r) for r in (E @ B_hat)]


def breakpoints(rows: Sequence[Sequence]) -> list[tuple]:
    """+-rot90(t) for every nonzero trace row t: the only directions where t . f changes
    sign.

    Parameters
    ----------
    rows : sequence of rows
        Trace rows (2 numbers each).

    Returns
    -------
    list of tuple
        Direction vectors (x, y), two per nonzero row.
    """
    out = []
    for t in rows:
        if t[0] != 0 or t[1] != 0:
            out += [(-t[1], t[0]), (t[1], -t[0])]
    return out


# --- the circle of directions -----------------------------------------------------------
def _angle(d) -> float:
    """atan2 in [-pi, pi)."""
    a = math.atan2(float(d[1]), float(d[0])) + 0.0  # no -0.0
    return -math.pi if a >= math.pi else a


def _half(d) -> int:
    return 0 if (d[1] > 0 or (d[1] == 0 and d[0] > 0)) else 1


def _cmp_angle(a, b) -> int:
    """Exact comparison of the polar angles of a and b in [0, 2 pi)."""
    ha, hb = _half(a), _half(b)
    if ha != hb:
        return -1 if ha < hb else 1
    cr = a[0] * b[1] - a[1] * b[0]
    return -1 if cr > 0 else (1 if cr < 0 else 0)


def _sorted_unique(dirs: list, exact: bool) -> list:
    """Directions sorted by polar angle, duplicates (same direction) removed."""
    if not exact:
        angs = sorted({_angle(d) for d in dirs})
        return [(math.cos(a), math.sin(a)) for a in angs]
    out: list = []
    for d in sorted(dirs, key=functools.cmp_to_key(_cmp_angle)):
        if not out or _cmp_angle(out[-1], d) != 0:
            out.append(d)
    return out


def _probe(d1, d2, exact: bool, single: bool = False):
    """A direction strictly inside the counter-clockwise gap from d1 to d2."""
    if not exact:
        a1 = _angle(d1)
        gap = _TWO_PI if single else (_angle(d2) - a1) % _TWO_PI
        a = a1 + gap / 2
        return (math.cos(a), math.sin(a))
    if single:
        return (-d1[0], -d1[1])
    cr = d1[0] * d2[1] - d1[1] * d2[0]
    if cr > 0:  # gap < pi
        return (d1[0] + d2[0], d1[1] + d2[1])
    if cr < 0:  # gap > pi: the opposite of the sum points into it
        return (-(d1[0] + d2[0]), -(d1[1] + d2[1]))
    return (-d1[1], d1[0])  # gap == pi


Member = Callable[[tuple], bool]
WHOLE = "whole"


def _arcs(dirs: list, member: Member, exact: bool,
          members: Callable[[list], list] | None = None) -> list | str:
    """Closed arcs (lo_vec, hi_vec) of the directions d with ``member(d)``, given every
    direction where membership may change (module docstring); WHOLE for the circle.
    ``members``: ``member`` of a list of directions at once (the same answers, faster:
    a robust request's hundreds of pieces tested with numpy).

    A breakpoint is included when it is a member or an adjacent gap is (the closure)."""
    pts = _sorted_unique(dirs, exact)
    m = len(pts)
    if m == 0:
        return WHOLE if member((1, 0) if exact else (1.0, 0.0)) else []
    probes = [_probe(pts[k], pts[(k + 1) % m], exact, single=(m == 1)) for k in range(m)]
    if members is None:
        gaps = [member(d) for d in probes]
        atpt = [member(d) for d in pts]
    else:
        got = members(probes + pts)
        gaps, atpt = got[:m], got[m:]
    inpt = [atpt[k] or gaps[k] or gaps[k - 1] for k in range(m)]
    if all(gaps):
        return WHOLE
    # the cyclic sequence point 0, gap 0, point 1, ..., gap m-1, read from just after a
    # gap that is out: maximal runs of members start and end at breakpoints
    start = next(k for k in range(m) if not gaps[k]) + 1
    arcs, run = [], None
    for step in range(2 * m):
        e = (2 * start + step) % (2 * m)
        k = e // 2
        inside = inpt[k] if e % 2 == 0 else gaps[k]
        if inside and run is None:
            run = k
        elif not inside and run is not None:
            arcs.append((pts[run], pts[(k if e % 2 == 1 else k - 1) % m]))
            run = None
    if run is not None:
        arcs.append((pts[run], pts[(start - 1) % m]))
    return arcs


def _arcs_to_angles(arcs: list | str) -> list[tuple[float, float, tuple | None, tuple | None]]:
    if arcs == WHOLE:
        return [(-math.pi, math.pi, None, None)]
    out = []
    for lo_v, hi_v in arcs:
        lo = _angle(lo_v)
        hi = lo + (_angle(hi_v) - lo) % _TWO_PI
        out.append((lo, hi, lo_v, hi_v))
    return sorted(out, key=lambda x: x[0])


# --- what the user asked: a mode (concrete or wildcard), possibly exclusive -------------
@dataclass
class _Request:
    """Membership and margin of force directions for (scene, mode, point, exclusive)."""

    scene: Scene
    mode: str
    B: np.ndarray  # float SI basis
    pieces: list[Cone]
    others: list[Cone]
    exclusive: bool
    exact: bool
    B_exact_hat: np.ndarray | None = None
    _rows: dict = field(default_factory=dict)
    guarantee: Guarantee | None = None  # of a robust request (.robust)

    def wrench(self, phi: float) -> np.ndarray:
        return self.B @ np.array([math.cos(phi), math.sin(phi)])

    def _exact_rows(self, cone: Cone):
        key = id(cone)
        if key not in self._rows:
            self._rows[key] = trace_rows(cone, self.B_exact_hat, exact=True)
        return self._rows[key]

    def _in(self, cone: Cone, d) -> bool:
        if not self.exact:
            return cone.contains(self.B @ np.asarray(d, dtype=float))
        if not cone.feasible:
            return False
        F, E = self._exact_rows(cone)
        return (all(t[0] * d[0] + t[1] * d[1] <= 0 for t in F)
                and all(e[0] * d[0] + e[1] * d[1] == 0 for e in E))

    def member(self, d) -> bool:
        if not any(self._in(c, d) for c in self.pieces):
            return False
        return not (self.exclusive and any(self._in(c, d) for c in self.others))

    def members(self, dirs: list) -> list[bool]:
        """:meth:`member` of every direction in ``dirs`` (float requests: each cone's
        ``check_many`` over all of them; exact requests: one by one)."""
        if self.exact:
            return [self.member(d) for d in dirs]
        D = np.asarray(dirs, dtype=float).reshape(-1, 2)
        G = np.array([self.B @ d for d in D]).reshape(-1, 3)  # as _in computes them

        def any_of(cones: list[Cone]) -> np.ndarray:
            out = np.zeros(len(D), dtype=bool)
            for c in cones:
                out |= c.contains_many(G)
            return out
        inside = any_of(self.pieces)
        if self.exclusive and inside.any():
            inside &= ~any_of(self.others)
        return inside.tolist()

    def breakpoints(self) -> list:
        out = []
        B_hat = self.B_exact_hat if self.exact else _nondim_basis(self.scene, self.B, False)
        for c in self.pieces + (self.others if self.exclusive else []):
            if c.feasible:
                F, E = trace_rows(c, B_hat, exact=self.exact)
                out += breakpoints(F + E)
        return out

    def margin(self, phi: float) -> float:
        g = self.wrench(phi)  # margins_at: each cone's margin(g), the same doubles
        m = max(margins_at(self.pieces, g), default=-1.0)
        if self.exclusive:
            m = min([m] + [-v for v in margins_at(self.others, g)])
        return m

    def margins(self, phis) -> np.ndarray:
        """:meth:`margin` of every direction in ``phis`` (each cone's ``margin_many``,
        elementwise identical to its scalar margin)."""
        G = np.array([self.wrench(float(p)) for p in phis]).reshape(-1, 3)
        m = np.full(len(G), -1.0)
        for k, c in enumerate(self.pieces):
            v = c.margin_many(G)
            m = v if k == 0 else np.maximum(m, v)
        if self.exclusive:
            for c in self.others:
                m = np.minimum(m, -c.margin_many(G))
        return m


def _request(scene: Scene, mode: str, point, exclusive: bool, exact: bool,
             classifier: ModeClassifier | None, uncertainty: Uncertainty) -> _Request:
    """The cones a direction question is answered from
    (:func:`.robust.robust_direction_cones`): the mode's "all" cone and the other modes'
    "any" pieces; for the zero-width uncertainty the nominal cones (wildcards allowed),
    in float from ``classifier``'s cache."""
    clf = classifier or ModeClassifier(scene)
    pieces, others, guarantee = robust_direction_cones(scene, mode, uncertainty, point,
                                                       exclusive, exact, nominal=clf.cone)
    B = force_basis(scene, point)
    Bx = _nondim_basis(scene, force_basis(scene, point, exact=True), True) if exact else None
    return _Request(scene, mode, B, pieces, others, exclusive, exact, Bx, guarantee=guarantee)


def _best(margin: Callable[[float], float], lo: float, hi: float,
          margins: Callable[[np.ndarray], np.ndarray] | None = None) -> tuple[float, float]:
    """The direction of largest margin in [lo, hi] and that margin (module docstring);
    ``margins``: ``margin`` of an array of directions at once (the same values)."""
    if hi == lo:
        return lo, margin(lo)
    grid = np.linspace(lo, hi, BEST_GRID + 1)
    vals = (np.array([margin(float(p)) for p in grid]) if margins is None
            else np.asarray(margins(grid), dtype=float))
    top = float(vals.max())
    ties = np.flatnonzero(vals >= top - MARGIN_TIE_TOLERANCE)
    mid = 0.5 * (lo + hi)
    k = int(ties[np.argmin(np.abs(grid[ties] - mid))])
    best, val = float(grid[k]), float(vals[k])
    a, b = float(grid[max(k - 1, 0)]), float(grid[min(k + 1, BEST_GRID)])
    from scipy.optimize import minimize_scalar  # lazy: 0.6 s to import

    res = minimize_scalar(lambda p: -margin(p), bounds=(a, b), method="bounded",
                          options={"xatol": BEST_DIRECTION_XATOL})
    if res.success and -res.fun > val + MARGIN_TIE_TOLERANCE:
        best, val = float(res.x), float(-res.fun)
    return best, val


def _intervals(spans, margin: Callable[[float], float], guarantee: Guarantee | None = None,
               margins: Callable[[np.ndarray], np.ndarray] | None = None
               ) -> list[DirectionInterval]:
    out = []
    for lo, hi, lo_v, hi_v in spans:
        best, val = _best(margin, lo, hi, margins)
        if hi - lo >= _TWO_PI and best >= math.pi:
            best -= _TWO_PI
        ex = lo_v is not None and isinstance(lo_v[0], Fraction)
        out.append(DirectionInterval(lo, hi, best, val, tuple(lo_v) if ex else None,
                                     tuple(hi_v) if ex else None, guarantee))
    return out


def force_directions(scene: Scene, mode: str, point: Sequence[float] | None = None,
                     exclusive: bool = False, exact: bool = False,
                     classifier: ModeClassifier | None = None,
                     uncertainty: Uncertainty | None = None) -> list[DirectionInterval]:
    """The directions phi (rad, fixture frame) of a pure force (cos phi, sin phi) at
    ``point`` (workpiece frame, m; default the com) that are consistent with ``mode``.

    ``exclusive=True``: consistent with ``mode`` and with no other valid mode of the
    scene (closure). Wildcard modes give the union. Intervals sorted by lo, disjoint; an
    empty list when no direction works. Endpoints from the facets' traces on the force
    plane (module docstring), in rational arithmetic with ``exact=True``. Raises
    ModeError for a mode the contact state does not allow, ValueError for a bad point.

    ``uncertainty`` (:class:`~.uncertainty.Uncertainty`, a concrete mode): the directions
    that give the mode for every model (:func:`.robust.robust_direction_cones`; with
    ``exclusive``, and no other mode for any model); ``margin`` and ``best`` are then the
    worst case over the models; each interval carries the answer's ``guarantee``.

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The mode, wildcards allowed.
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    exclusive : bool, optional
        Only directions consistent with no other mode.
    exact : bool, optional
        Endpoints in rational arithmetic.
    classifier : ModeClassifier or None, optional
        A classifier of the scene whose cached cones are reused.
    uncertainty : Uncertainty or None, optional
        The model set (None: the nominal model).

    Returns
    -------
    list of DirectionInterval
        Sorted by lo, disjoint; empty when no direction works.

    Raises
    ------
    ModeError
        The mode is not valid for the scene's contacts.
    ValueError
        A bad point.
    """
    req = _request(scene, mode, point, exclusive, exact, classifier, or_nominal(uncertainty))
    arcs = _arcs(req.breakpoints(), req.member, exact, req.members)
    return _intervals(_arcs_to_angles(arcs), req.margin, req.guarantee, req.margins)


# --- force regions ----------------------------------------------------------------------
@dataclass(frozen=True)
class ForceRegion:
    """The forces f (N, fixture frame) at a point with ``offset + B f`` consistent with one
    concrete mode: {f : A f <= b, A_eq f = b_eq}, a convex polygon, possibly unbounded,
    = conv(vertices) + cone(rays) + span(lines) (pycddlib, exact arithmetic on the float
    rows). Rows are the cone's nondimensional facets and equalities traced on the plane:
    A = F_hat S B, b = -F_hat S offset (and likewise for the equalities).

    Parameters
    ----------
    mode : str
        The concrete mode.
    A : numpy.ndarray
        Inequality rows, (k, 2), each scaled like a unit facet row.
    b : numpy.ndarray
        Their right-hand sides, (k,).
    A_eq : numpy.ndarray
        Equality rows, (e, 2).
    b_eq : numpy.ndarray
        Their right-hand sides, (e,).
    vertices : numpy.ndarray
        (v, 2), N.
    rays : numpy.ndarray
        (r, 2).
    lines : numpy.ndarray
        (l, 2).
    offset : tuple of 3 float
        The fixed extra wrench (fx N, fy N, tz N m).
    B : numpy.ndarray
        The force basis, 3 x 2 (:func:`force_basis`).
    length_scale : float
        L (m).
    """

    mode: str
    A: np.ndarray
    b: np.ndarray
    A_eq: np.ndarray
    b_eq: np.ndarray
    vertices: np.ndarray
    rays: np.ndarray
    lines: np.ndarray
    offset: tuple[float, float, float]
    B: np.ndarray
    length_scale: float

    @property
    def bounded(self) -> bool:
        """Whether the region is a polygon (no ray, no line)."""
        return self.rays.shape[0] == 0 and self.lines.shape[0] == 0

    def contains(self, f: Sequence[float], tol: float = CONE_TOLERANCE) -> bool:
        """f meets every row within ``tol`` times |S (offset + B f)| (CONE_TOLERANCE, the
        tolerance of :meth:`Cone.contains`, dimensionless).

        Parameters
        ----------
        f : sequence of 2 float
            A force (N, fixture frame).
        tol : float, optional
            Dimensionless tolerance.

        Returns
        -------
        bool
            True inside.
        """
        f = np.asarray(f, dtype=float).reshape(2)
        g = np.asarray(self.offset) + self.B @ f
        scale = tol * float(np.linalg.norm(g * np.array([1.0, 1.0, 1.0 / self.length_scale])))
        return bool(np.all(self.A @ f - self.b <= scale)
                    and np.all(np.abs(self.A_eq @ f - self.b_eq) <= scale))

    def to_dict(self) -> dict:
        """The region as JSON-able data.

        Returns
        -------
        dict
            ``mode``, ``A``, ``b``, ``A_eq``, ``b_eq``, ``vertices``, ``rays``, ``lines``.
        """
        return {k: (getattr(self, k).tolist() if isinstance(getattr(self, k), np.ndarray)
                    else getattr(self, k))
                for k in ("mode", "A", "b", "A_eq", "b_eq", "vertices", "rays", "lines")}


def _polygon(A: np.ndarray, b: np.ndarray, A_eq: np.ndarray, b_eq: np.ndarray):
    """Vertices, rays, lines of {A f <= b, A_eq f = b_eq} (cddlib GMP; rows of Fractions);
    None when empty."""
    rows = [[bi, *(-x for x in a)] for a, bi in zip(A.tolist(), b.tolist())]
    rows += [[bi, *(-x for x in a)] for a, bi in zip(A_eq.tolist(), b_eq.tolist())]
    if not rows:
        return np.zeros((1, 2)), np.zeros((0, 2)), np.eye(2)
    mat = _matrix(rows, range(A.shape[0], len(rows)), cdd.RepType.INEQUALITY, True)
    gen = cdd.gmp.copy_generators(cdd.gmp.polyhedron_from_matrix(mat))
    verts, rays, lines = [], [], []
    for k, row in enumerate(gen.array):
        if k in gen.lin_set:
            lines.append([float(row[1]), float(row[2])])
        elif row[0] != 0:
            verts.append([float(row[1] / row[0]), float(row[2] / row[0])])
        else:
            rays.append([float(row[1]), float(row[2])])
    if not verts:
        # cddlib lists no vertex for a cone (every b = 0): the apex, the origin, is implied
        if not (rays or lines) or any(x < 0 for x in b) or any(x != 0 for x in b_eq):
            return None
        verts = [[0.0, 0.0]]

    def arr(x):
        return np.array(x, dtype=float).reshape(-1, 2)

    return arr(verts), arr(rays), arr(lines)


def force_region(scene: Scene, mode: str, point: Sequence[float] | None = None,
                 offset: Sequence[float] = (0.0, 0.0, 0.0)) -> list[ForceRegion]:
    """The forces f (N) at ``point`` such that ``offset + wrench(f)`` is consistent with
    ``mode``: one convex :class:`ForceRegion` per feasible concrete mode whose region is
    not empty (a wildcard mode gives the union of the list; a concrete mode at most one).

    ``offset`` (fx N, fy N, tz N m about the com, fixture frame) is a fixed extra wrench:
    a spring preload, gravity of a tilted tray. With offset 0 the region is the 2-D cone
    of :func:`force_directions`. The polygon is computed in rational arithmetic from the
    exact cone, the exact basis and the offset's floats taken exactly: float facet traces
    that are parallel in exact arithmetic would otherwise meet at spurious far vertices.
    Rows are returned as floats, each scaled like a unit facet row of the cone (F_hat).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The mode, wildcards allowed.
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    offset : sequence of 3 float, optional
        A fixed extra wrench (fx N, fy N, tz N m).

    Returns
    -------
    list of ForceRegion
        One per feasible concrete mode with a nonempty region.

    Raises
    ------
    ValueError
        ``offset`` is not three finite numbers, or a bad point.
    ModeError
        The mode is not valid for the scene's contacts.
    """
    o = np.asarray(offset, dtype=float).reshape(3)
    if not np.all(np.isfinite(o)):
        raise ValueError(f"offset must be three finite numbers (N, N, N m), got {list(offset)}")
    B = force_basis(scene, point)
    B_hat = _nondim_basis(scene, force_basis(scene, point, exact=True), True)
    L = to_exact(scene.length_scale)
    o_hat = np.array([Fraction(o[0]), Fraction(o[1]), Fraction(o[2]) / L], dtype=object)
    out = []
    for cone in mode_union(scene, mode, exact=True).pieces:
        rep = cone.exact_rep
        F = np.array(rep.F, dtype=object).reshape(-1, 3)
        E = np.array(rep.E, dtype=object).reshape(-1, 3)
        A, A_eq, b, b_eq = F @ B_hat, E @ B_hat, -(F @ o_hat), -(E @ o_hat)
        poly = _polygon(A, b, A_eq, b_eq)
        if poly is None:
            continue

        def unit(M, v, rows):
            n = np.array([math.sqrt(sum(float(x) ** 2 for x in r)) for r in rows])
            Mf = np.array(M, dtype=float).reshape(-1, 2) / n.reshape(-1, 1) if len(n) else \
                np.zeros((0, 2))
            return Mf, np.array(v, dtype=float).reshape(-1) / n if len(n) else np.zeros(0)

        (Af, bf), (Aef, bef) = unit(A, b, F), unit(A_eq, b_eq, E)
        out.append(ForceRegion(cone.mode, Af, bf, Aef, bef, *poly, tuple(o.tolist()), B,
                               float(scene.length_scale)))
    return out


# --- sweeps along a path ----------------------------------------------------------------
@dataclass(frozen=True)
class SweepResult:
    """:func:`force_directions` along a path of poses.

    ``intervals[k]``: the intervals at pose k, None from ``stop`` on. ``stop``: the first
    pose where the mode is not valid any more (its letters do not fit the contact state,
    ``stop_reason`` says why) or has no direction; None when it holds along the whole
    path. ``common``: the directions valid at every pose before ``stop`` (their
    intersection; ``best`` maximises the smallest margin over those poses).
    ``after``: when ``stop`` is a pose with a valid scene and ``common`` is not empty, the
    modes the force along ``common[0].best`` is consistent with at that pose.

    Parameters
    ----------
    mode : str
        The mode swept.
    poses : tuple of tuple of 3 float
        The path (x m, y m, theta rad).
    intervals : tuple
        Per pose, its intervals, or None from ``stop`` on.
    common : tuple of DirectionInterval
        The directions valid at every pose before ``stop``.
    stop : int or None
        The first pose where the mode stops being valid or has no direction.
    stop_reason : str
        Why (empty when ``stop`` is None).
    after : tuple of ModeMatch, optional
        The modes at ``stop`` of the force along ``common[0].best``.
    """

    mode: str
    poses: tuple[tuple[float, float, float], ...]
    intervals: tuple[tuple[DirectionInterval, ...] | None, ...]
    common: tuple[DirectionInterval, ...]
    stop: int | None
    stop_reason: str
    after: tuple[ModeMatch, ...] = ()


def _pose(p, k: int) -> tuple[float, float, float]:
    if isinstance(p, (str, bytes)) or not isinstance(p, Sequence) or len(p) != 3:
        raise ValueError(f"pose {k} must be [x m, y m, theta rad], got {p!r}")
    out = tuple(float(v) for v in p)
    if not all(math.isfinite(v) for v in out):
        raise ValueError(f"pose {k} must be finite, got {list(p)}")
    return out


def _in_intervals(phi: float, ivs: Sequence[DirectionInterval]) -> bool:
    return any(iv.contains(phi) for iv in ivs)


def common_directions(per: Sequence[Sequence[DirectionInterval]],
                      margin: Callable[[float], float], guarantee: Guarantee | None = None
                      ) -> list[DirectionInterval]:
    """The directions that lie in an interval of every list of ``per`` (the intersection
    of their unions), as intervals whose ``best`` and ``margin`` maximise ``margin``.

    Parameters
    ----------
    per : sequence of sequence of DirectionInterval
        The intervals at each pose.
    margin : callable
        The margin of a direction (rad -> dimensionless).
    guarantee : Guarantee or None, optional
        The guarantee the intervals carry.

    Returns
    -------
    list of DirectionInterval
        The intersection.
    """
    dirs = [(math.cos(a), math.sin(a)) for ivs in per for iv in ivs for a in (iv.lo, iv.hi)]

    def member(d) -> bool:
        phi = _angle(d)
        return all(_in_intervals(phi, ivs) for ivs in per)

    return _intervals(_arcs_to_angles(_arcs(dirs, member, False)), margin, guarantee)


def sweep(scene: Scene, poses: Sequence[Sequence[float]], mode: str,
          point: Sequence[float] | None = None, exclusive: bool = False,
          uncertainty: Uncertainty | None = None) -> SweepResult:
    """:func:`force_directions` at every pose (x m, y m, theta rad) of a path, their
    intersection, and the first pose where ``mode`` stops being valid (:class:`SweepResult`).

    A pose where a fixel penetrates the workpiece is an input error (SceneError naming
    the pose). ``uncertainty``: robust directions at every pose (:func:`force_directions`);
    ``after`` then lists the robust matches (certain / possible) at the stop.

    Parameters
    ----------
    scene : Scene
        The scene (its pose is replaced by each of ``poses``).
    poses : sequence of sequence of 3 float
        The path.
    mode : str
        The mode, wildcards allowed.
    point : sequence of 2 float or None, optional
        The application point (m, workpiece frame); None: the com.
    exclusive : bool, optional
        Only directions consistent with no other mode.
    uncertainty : Uncertainty or None, optional
        The model set (None: the nominal model).

    Returns
    -------
    SweepResult
        The sweep.

    Raises
    ------
    SceneError
        A fixel penetrates the workpiece at a pose.
    ValueError
        No pose, or a pose that is not three finite numbers.
    """
    poses = tuple(_pose(p, k) for k, p in enumerate(poses))
    if not poses:
        raise ValueError("poses must be a non-empty list of [x, y, theta]")
    uncertainty = or_nominal(uncertainty)
    scenes, reqs, per = [], [], []
    stop, reason = None, ""
    for k, pose in enumerate(poses):
        try:
            sc = scene.with_pose(*pose)
        except SceneError as exc:
            raise SceneError(f"pose {k} {list(pose)}: {exc}") from None
        scenes.append(sc)
        try:
            req = _request(sc, mode, point, exclusive, False, None, uncertainty)
        except ModeError as exc:
            stop, reason = k, str(exc)
            break
        arcs = _arcs(req.breakpoints(), req.member, False, req.members)
        ivs = _intervals(_arcs_to_angles(arcs), req.margin, req.guarantee, req.margins)
        if not ivs:
            stop, reason = k, f"no force direction at pose {k} is consistent with {mode!r}"
            break
        reqs.append(req)
        per.append(tuple(ivs))
    common: list[DirectionInterval] = []
    if per:
        def margin(phi: float) -> float:
            return min(r.margin(phi) for r in reqs)

        common = common_directions(per, margin, reqs[0].guarantee)
    after: tuple[ModeMatch, ...] = ()
    if stop is not None and common:
        g = force_basis(scenes[stop], point) @ np.array(
            [math.cos(common[0].best), math.sin(common[0].best)])
        after = tuple(consistent_modes(scenes[stop], g, uncertainty=uncertainty,
                                       frame="com" if point is None else "nominal"))
    intervals = tuple(per) + (None,) * (len(poses) - len(per))
    return SweepResult(mode, poses, intervals, tuple(common), stop, reason, after)


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


__all__ = ["DirectionInterval", "ForceRegion", "SweepResult", "TiltInterval",
           "common_directions", "force_basis", "force_directions", "force_region",
           "sweep", "tilt_directions",
           "tilt_gravity_force", "trace_rows", "breakpoints", "STANDARD_GRAVITY",
           "BEST_GRID"]
