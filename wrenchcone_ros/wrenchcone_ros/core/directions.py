# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Which way to push: the force directions that give a contact mode.

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

Force regions (forces with a preload) are in :mod:`.regions`, sweeps along a path in
:mod:`.sweeps`, tray tilts in :mod:`.tilt`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .classify import ModeClassifier
from .cones import Cone, margins_at
from .engines import ConeChecks, default_engine
from .modes import expand_mode, is_wildcard
from .numbers import EXACT, to_exact
from .robust import robust_cones
from .scene import Scene
from .uncertainty import Uncertainty, as_uncertainty
from .wrenchset import Guarantee
from .tolerances import (
    ANGLE_RESOLUTION,
    BEST_DIRECTION_XATOL,
    MARGIN_TIE_TOLERANCE,
)

#: Number of grid directions over an interval from which ``best`` is refined (see the
#: module docstring); dimensionless.
BEST_GRID: int = 64


_TWO_PI = 2.0 * math.pi


# --- the robust cones a force-direction question is answered from -----------------------
def robust_direction_cones(scene: Scene, mode: str, uncertainty: Uncertainty, point,
                           exclusive: bool, exact: bool,
                           nominal: Callable[[str], Cone] | None = None
                           ) -> tuple[list[Cone], list[Cone], Guarantee]:
    """The cones a force-direction question is answered from: ``pieces`` = the feasible
    pieces of the mode's "all" set, ``others`` (``exclusive``) = the feasible "any"
    pieces of every valid mode not in ``mode`` (a wildcard's concrete modes are its
    own), and the guarantee. A force at the com (``point`` None) acts at each model's
    own com (``frame="com"``), a force at a point of the workpiece is a wrench about the
    nominal com (``frame="nominal"``). Its margin in the "all" cone is the worst case
    over the models (docs/theory.md). The zero-width uncertainty gives the nominal
    cones (:func:`.robust.robust_cones`), and only it takes a mode with wildcards.

    Parameters
    ----------
    scene : Scene
        The nominal scene.
    mode : str
        A concrete mode (wildcards only for the zero-width uncertainty).
    uncertainty : Uncertainty
        The model set.
    point : sequence of 2 float or None
        Where the force acts (m, workpiece frame); None: the com.
    exclusive : bool
        Also the other modes' "any" pieces.
    exact : bool
        Rational arithmetic (friction intervals only).
    nominal : callable or None, optional
        mode -> its nominal cone (a classifier's cache), for the zero-width uncertainty.

    Returns
    -------
    pieces : list of Cone
        The feasible pieces of the mode's "all" set.
    others : list of Cone
        The other modes' feasible "any" pieces (empty unless ``exclusive``).
    guarantee : Guarantee
        The answer's guarantee.
    """
    frame = "com" if point is None else "nominal"
    mine = robust_cones(scene, [mode], uncertainty, "all", exact=exact, frame=frame,
                        nominal=nominal)[0]
    pieces = [c for c in mine.pieces if c.feasible]
    others: list[Cone] = []
    if exclusive:
        own = set(expand_mode(mode, scene.in_contact)) if is_wildcard(mode) else {mode}
        rest = [m for m in expand_mode("*" * scene.n_fixels, scene.in_contact)
                if m not in own]
        for rc in robust_cones(scene, rest, uncertainty, "any", exact=exact, frame=frame,
                               nominal=nominal):
            others += [c for c in rc.pieces if c.feasible]
    return pieces, others, mine.guarantee


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
        if self._checks is not None:  # the same booleans, compiled
            pieces, others = self._checks
            inside = pieces.check(G)[0].any(axis=1)
            if self.exclusive and inside.any():
                inside &= ~others.check(G)[0].any(axis=1)
            return inside.tolist()

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

    @functools.cached_property
    def _checks(self) -> tuple[ConeChecks, ConeChecks] | None:
        """The engine's compiled checks of the pieces and the others (the same doubles as
        each cone's check), or None: float requests on an engine without them, and exact
        requests, use each cone's own methods."""
        if self.exact:
            return None
        make = getattr(default_engine(), "cone_checks", None)  # an engine of a user's
        pieces = make(self.pieces) if make is not None else None  # may not have it
        if pieces is None:
            return None
        return pieces, make(self.others if self.exclusive else [])

    def _margins_of(self, k: int, G: np.ndarray) -> list[np.ndarray]:
        """Each cone's margins at the (N, 3) wrenches G, cone by cone: of the pieces
        (k = 0) or of the others (k = 1)."""
        if self._checks is not None:
            M = self._checks[k].check(G)[1]
            return [M[:, j] for j in range(M.shape[1])]
        return [c.margin_many(G) for c in (self.pieces, self.others)[k]]

    def margin(self, phi: float) -> float:
        g = self.wrench(phi)  # each cone's margin(g), the same doubles
        if self._checks is not None:
            m = max(self._checks[0].check(g)[1][0].tolist(), default=-1.0)
            if self.exclusive:
                m = min([m] + [-v for v in self._checks[1].check(g)[1][0].tolist()])
            return m
        m = max(margins_at(self.pieces, g), default=-1.0)
        if self.exclusive:
            m = min([m] + [-v for v in margins_at(self.others, g)])
        return m

    def margins(self, phis) -> np.ndarray:
        """:meth:`margin` of every direction in ``phis`` (each cone's ``margin_many``,
        elementwise identical to its scalar margin)."""
        G = np.array([self.wrench(float(p)) for p in phis]).reshape(-1, 3)
        m = np.full(len(G), -1.0)
        for k, v in enumerate(self._margins_of(0, G)):
            m = v if k == 0 else np.maximum(m, v)
        if self.exclusive:
            for v in self._margins_of(1, G):
                m = np.minimum(m, -v)
        return m


def _request(scene: Scene, mode: str, point, exclusive: bool, exact: bool,
             classifier: ModeClassifier | None, uncertainty: Uncertainty) -> _Request:
    """The cones a direction question is answered from
    (:func:`robust_direction_cones`): the mode's "all" cone and the other modes'
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
    that give the mode for every model (:func:`robust_direction_cones`; with
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
    req = _request(scene, mode, point, exclusive, exact, classifier, as_uncertainty(uncertainty))
    arcs = _arcs(req.breakpoints(), req.member, exact, req.members)
    return _intervals(_arcs_to_angles(arcs), req.margin, req.guarantee, req.margins)


__all__ = ["DirectionInterval", "force_basis", "force_directions", "trace_rows",
           "breakpoints", "BEST_GRID"]
