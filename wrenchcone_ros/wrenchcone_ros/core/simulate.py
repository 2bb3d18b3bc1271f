# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Forward motion of a scene's workpiece under a constant applied force, in pymunk.

The cones answer one instant: which modes a force gives to a part at rest. This module
moves the part, with the 2-D rigid-body engine pymunk (Chipmunk2D: Coulomb friction,
impulses on contacts), and reads back what happened at every fixel in the letters of
the paper's Table 2 (core/modes.py), so that predictions can be checked on a body that
moves. pymunk is an optional dependency (``pip install .[sim]``), imported inside the
functions that need it.

The scene in the engine (:func:`build_space`)
----------------------------------------------
* The workpiece is one dynamic body: mass m, moment of inertia about the com (the scene's
  ``inertia``), ``center_of_gravity`` = the com; its shapes are given in the workpiece
  frame, so the body's position and angle are the scene's pose (x, y, theta). A disc is a
  circle; a polygon is cut into convex pieces (:func:`convex_pieces`: ear clipping, then
  diagonals removed while the pieces stay convex, Hertel-Mehlhorn), so a boundary edge
  is never split and a fixel sliding along it meets no seam.
* Each fixel is a circle on the static body: its pin radius plus SIM_SLOP / 2 (L times);
  a point fixel is a circle of radius SIM_SLOP / 2 L, which rounds the corners it meets.
  The collision slop of the space is SIM_SLOP L, so a fixel that touches exactly overlaps
  the workpiece by less than the slop: it is a contact from the first step and the engine
  does not push it apart.
* Friction: Chipmunk multiplies the two shapes' coefficients; the workpiece's shapes have
  1 and fixel i has mu_i (the scene's, or a sampled model's). Elasticity 0 (inelastic
  impacts) unless a ``restitution`` is given (its product with the fixels' 1 is the
  impacts' coefficient of restitution: the robustness checks of plans use it), no gravity
  in the space (the tray's pull is the applied force), no damping.

The actuator (:class:`Actuator`)
--------------------------------
A tray tilt pulls with m g sin(alpha) at the com in the downhill direction phi
(:func:`~wrenchcone_ros.core.tilt.tilt_gravity_force`, alpha = ``tilt``). A spring
pulls at a point of the workpiece (workpiece frame) with a constant magnitude, its
direction phi fixed in the fixture frame (a long spring anchored far away), or, with
``follow=True``, turning with the part (phi is then its direction at the start pose).
The force is applied at every step (apply_force_at_world_point); its magnitude may be
scaled between steps (:meth:`Simulation.set_direction`, ``scale``: a plan's segment that
eases off, i.e. a smaller tray tilt).

The readout (:meth:`Simulation.readout`)
----------------------------------------
For every fixel: the closest point p of the workpiece to its centre, the gap (distance
minus pin radius, m), the normal n from the fixel into the workpiece and t = n rotated by
+90 degrees (the package's convention), the velocity of the workpiece's material point at
p along n and t, and the impulse the engine applied in the last step. With v_tol =
SIM_VELOCITY_TOLERANCE times the speed a free body reaches in min(t, T):

* gap > SIM_CONTACT_BAND L (free): ``a`` when v_n < -v_tol (approaching), else ``s``;
* in contact: ``s`` when v_n > v_tol and no impulse (separating); else ``n`` when
  |v_t| <= v_tol, ``l`` when v_t > 0, ``r`` when v_t < 0.

Times are in units of T = sqrt(m L / |F|); the step is SIM_TIME_STEP T, 40 solver
iterations, a collision slop of SIM_SLOP L (:class:`EngineSettings` scales each: a plan's
guarantee is checked over ENGINE_VARIATIONS of :mod:`.plan.execution`). The accuracy of the engine against the cones is measured in
benchmarks/plan_cost.py and test/core/test_simulate.py (docs/planning.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .tilt import STANDARD_GRAVITY
from .geometry import Disc
from .pymunk_boundary import ArbiterImpulses, ShapeQuery
from .scene import Scene
from .tolerances import (
    SIM_CONTACT_BAND,
    SIM_SLOP,
    SIM_TIME_STEP,
    SIM_VELOCITY_TOLERANCE,
)

#: Default tray tilt (rad): the tilt angle alpha of a plan's tray (10 degrees). Only the
#: time scale depends on it: the modes of a pure force do not depend on its magnitude.
DEFAULT_TILT: float = math.radians(10.0)

#: Chipmunk solver iterations per step (pymunk's default is 10).
SOLVER_ITERATIONS: int = 40


class SimulationUnavailable(RuntimeError):
    """pymunk is not installed (``pip install .[sim]`` or ``pip install pymunk``)."""


def _pymunk():
    try:
        import pymunk
    except ImportError:  # pragma: no cover - exercised only without the extra
        raise SimulationUnavailable(
            "the simulation needs pymunk: pip install 'wrenchcone_ros[sim]' "
            "(or pip install pymunk)") from None
    return pymunk


# --- the actuator ------------------------------------------------------------------
@dataclass(frozen=True)
class Actuator:
    """What pulls the workpiece: a tray tilt (force at the com) or a spring at a point.

    Parameters
    ----------
    kind : str, optional
        ``"tilt"`` or ``"spring"``.
    tilt : float, optional
        The tray's tilt angle alpha (rad, in (0, pi/2]); the pull is m g sin(alpha).
    point : tuple of 2 float or None, optional
        The spring's hook (m, workpiece frame); None for a tilt.
    magnitude : float or None, optional
        The spring's force (N); None: the tilt's pull.
    follow : bool, optional
        The spring's direction turns with the part (default: fixed in the fixture frame).

    Raises
    ------
    ValueError
        An unknown kind, a tilt outside (0, pi/2], a tilt with a point or ``follow``, a
        spring without a finite hook point, or a magnitude that is not a positive number.
    """

    kind: str = "tilt"
    tilt: float = DEFAULT_TILT
    point: tuple[float, float] | None = None
    magnitude: float | None = None
    follow: bool = False

    def __post_init__(self) -> None:
        if self.kind not in ("tilt", "spring"):
            raise ValueError(f"actuator kind must be 'tilt' or 'spring', got {self.kind!r}")
        if not (isinstance(self.tilt, (int, float)) and 0 < self.tilt <= math.pi / 2):
            raise ValueError(f"tilt must be an angle in (0, pi/2] rad, got {self.tilt!r}")
        if self.kind == "tilt" and (self.point is not None or self.follow):
            raise ValueError("a tray tilt pulls at the com: no point, no follow")
        if self.kind == "spring":
            if self.point is None:
                raise ValueError("a spring needs its hook point (x, y) m, workpiece frame")
            p = tuple(float(v) for v in self.point)
            if len(p) != 2 or not all(math.isfinite(v) for v in p):
                raise ValueError(f"spring point must be two finite numbers (m), got "
                                 f"{self.point!r}")
            object.__setattr__(self, "point", p)
        if self.magnitude is not None and not (
                math.isfinite(self.magnitude) and self.magnitude > 0):
            raise ValueError(f"magnitude must be a positive force (N), got {self.magnitude!r}")

    @staticmethod
    def parse(value: str | Actuator | None) -> Actuator:
        """An Actuator from "tilt", "spring:X,Y" or an Actuator (None: a tilt).

        Parameters
        ----------
        value : str, Actuator or None
            ``"tilt"``, ``"spring:X,Y"`` (hook point, m, workpiece frame), an Actuator or None.

        Returns
        -------
        Actuator
            The actuator.

        Raises
        ------
        ValueError
            Any other text, or a spring point that is not two numbers.
        """
        if value is None:
            return Actuator()
        if isinstance(value, Actuator):
            return value
        if value == "tilt":
            return Actuator()
        if isinstance(value, str) and value.startswith("spring:"):
            try:
                x, y = (float(v) for v in value[len("spring:"):].split(","))
            except ValueError:
                raise ValueError(f"spring actuator must read 'spring:X,Y' (hook point, m, "
                                 f"workpiece frame), got {value!r}") from None
            return Actuator("spring", point=(x, y))
        raise ValueError(f"actuator must be 'tilt' or 'spring:X,Y', got {value!r}")

    def force_magnitude(self, scene: Scene) -> float:
        """|F| (N): the spring's magnitude, else m g sin(tilt).

        Parameters
        ----------
        scene : Scene
            The scene (the workpiece's mass).

        Returns
        -------
        float
            |F| (N).
        """
        if self.magnitude is not None:
            return float(self.magnitude)
        return scene.workpiece.mass * STANDARD_GRAVITY * math.sin(self.tilt)

    def application_point(self, scene: Scene) -> tuple[float, float]:
        """Where the force acts (workpiece frame, m): the com for a tilt.

        Parameters
        ----------
        scene : Scene
            The scene (the workpiece's com).

        Returns
        -------
        tuple of 2 float
            The point (m, workpiece frame).
        """
        return tuple(self.point) if self.point is not None else tuple(scene.workpiece.com)

    @property
    def directions_point(self) -> tuple[float, float] | None:
        """The ``point`` argument of force_directions / sweep (None: the com)."""
        return self.point

    def to_dict(self) -> dict:
        """The actuator as JSON-able data.

        Returns
        -------
        dict
            ``kind``, ``tilt`` (rad), ``point`` (m), ``magnitude`` (N), ``follow``.
        """
        return {"kind": self.kind, "tilt": self.tilt, "point": self.point,
                "magnitude": self.magnitude, "follow": self.follow}


# --- geometry: convex pieces of a simple polygon -------------------------------------
def _cross(o, a, b) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _in_triangle(p, a, b, c) -> bool:
    return _cross(a, b, p) >= 0 and _cross(b, c, p) >= 0 and _cross(c, a, p) >= 0


def _ear_clip(pts: Sequence[tuple[float, float]]) -> list[list[int]]:
    """Triangles (vertex indices, counter-clockwise) of a simple CCW polygon."""
    idx = list(range(len(pts)))
    tris = []
    while len(idx) > 3:
        for k in range(len(idx)):
            i0, i1, i2 = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = pts[i0], pts[i1], pts[i2]
            if _cross(a, b, c) <= 0:
                continue  # reflex or flat corner
            if any(_in_triangle(pts[j], a, b, c) for j in idx if j not in (i0, i1, i2)):
                continue
            tris.append([i0, i1, i2])
            del idx[k]
            break
        else:  # pragma: no cover - a simple polygon always has an ear
            raise ValueError("polygon could not be triangulated (is it simple?)")
    tris.append(idx)
    return tris


def _convex(pts, poly: list[int]) -> bool:
    n = len(poly)
    return all(_cross(pts[poly[k - 1]], pts[poly[k]], pts[poly[(k + 1) % n]]) >= 0
               for k in range(n))


def convex_pieces(vertices: Sequence[Sequence[float]]) -> list[list[tuple[float, float]]]:
    """Convex pieces (CCW vertex lists) whose union is the simple CCW polygon.

    Ear clipping, then Hertel-Mehlhorn: a diagonal shared by two pieces is removed when
    the merged piece is convex. Pieces use only the polygon's vertices, so no boundary
    edge is split. A convex polygon is one piece.

    Parameters
    ----------
    vertices : sequence of (x, y)
        A simple polygon, counter-clockwise.

    Returns
    -------
    list of list of (float, float)
        The convex pieces, counter-clockwise.
    """
    pts = [tuple(map(float, v)) for v in vertices]
    if _convex(pts, list(range(len(pts)))):
        return [pts]
    pieces = _ear_clip(pts)
    merged = True
    while merged:
        merged = False
        for i in range(len(pieces)):
            for j in range(i + 1, len(pieces)):
                a, b = pieces[i], pieces[j]
                for k in range(len(a)):
                    u, v = a[k], a[(k + 1) % len(a)]
                    if u in b and v in b and b[(b.index(v) + 1) % len(b)] == u:
                        # a runs u -> v, b runs v -> u: join along the diagonal
                        ka, kb = (k + 1) % len(a), (b.index(u) + 1) % len(b)
                        joined = ([a[(ka + m) % len(a)] for m in range(len(a))]
                                  + [b[(kb + m) % len(b)] for m in range(len(b) - 2)])
                        if _convex(pts, joined):
                            pieces[i] = joined
                            del pieces[j]
                            merged = True
                        break
                if merged:
                    break
            if merged:
                break
    return [[pts[k] for k in piece] for piece in pieces]


# --- the space -----------------------------------------------------------------------
@dataclass
class SceneSpace:
    """A scene in pymunk: the space, the workpiece body and shapes, one circle per fixel.

    Parameters
    ----------
    space : pymunk.Space
        The space.
    body : pymunk.Body
        The workpiece.
    shapes : list
        The workpiece's shapes (one circle, or one convex polygon per piece).
    fixels : list
        One static circle per fixel.
    length_scale : float
        L (m).
    time_scale : float
        T (s), :func:`time_scale`.
    """

    space: object
    body: object
    shapes: list
    fixels: list
    length_scale: float
    time_scale: float


def time_scale(scene: Scene, force: float) -> float:
    """T = sqrt(m L / |F|) (s): a free body moves L / 2 in time T under force F.

    Parameters
    ----------
    scene : Scene
        The scene (the workpiece's mass and L).
    force : float
        |F| (N), > 0.

    Returns
    -------
    float
        T (s).
    """
    return math.sqrt(scene.workpiece.mass * scene.length_scale / force)


@dataclass(frozen=True)
class EngineSettings:
    """The engine's numerical settings, as factors on the defaults: the time step
    (SIM_TIME_STEP T), the solver iterations per step (SOLVER_ITERATIONS) and the
    collision slop (SIM_SLOP L). A result that holds for the defaults only is an
    artefact of the engine; a plan's guarantee is checked over several
    (:data:`~.plan.execution.ENGINE_VARIATIONS`).

    Parameters
    ----------
    step : float, optional
        Factor on the time step, > 0.
    iterations : float, optional
        Factor on the solver iterations, > 0 (rounded, at least 1 iteration).
    slop : float, optional
        Factor on the collision slop, > 0.

    Raises
    ------
    ValueError
        A factor that is not a finite number > 0.
    """

    step: float = 1.0
    iterations: float = 1.0
    slop: float = 1.0

    def __post_init__(self) -> None:
        for name in ("step", "iterations", "slop"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) \
                    or not math.isfinite(v) or v <= 0:
                raise ValueError(f"engine setting {name} must be a factor > 0, got {v!r}")

    @property
    def label(self) -> str:
        """'step x0.25, iterations x4' ('defaults' when every factor is 1)."""
        parts = [f"{name} x{getattr(self, name):g}" for name in ("step", "iterations", "slop")
                 if getattr(self, name) != 1.0]
        return ", ".join(parts) or "defaults"


#: The engine's default settings.
DEFAULT_ENGINE = EngineSettings()


def build_space(scene: Scene, force: float, friction: Sequence[float] | None = None,
                restitution: float = 0.0, engine: EngineSettings = DEFAULT_ENGINE
                ) -> SceneSpace:
    """The scene in a new pymunk space (module docstring), the workpiece at the scene's
    pose, at rest. ``force``: the magnitude of the applied force (N), which sets the time
    step; ``friction``: one mu per fixel (default: the scene's); ``restitution``: the
    workpiece's elasticity in [0, 1] (0: inelastic impacts).

    Parameters
    ----------
    scene : Scene
        The scene.
    force : float
        |F| (N), > 0.
    friction : sequence of float or None, optional
        One mu per fixel.
    restitution : float, optional
        In [0, 1].
    engine : EngineSettings, optional
        Factors on the solver iterations and the collision slop (the time step is the
        caller's).

    Returns
    -------
    SceneSpace
        The space, the body, the shapes and the fixels.

    Raises
    ------
    ValueError
        A friction list of the wrong length or with a negative value, or a restitution
        outside [0, 1].
    SimulationUnavailable
        pymunk is not installed.
    """
    pymunk = _pymunk()
    L = scene.length_scale
    T = time_scale(scene, force)
    mus = [scene.mu(i) for i in range(scene.n_fixels)] if friction is None else list(friction)
    if len(mus) != scene.n_fixels or not all(math.isfinite(m) and m >= 0 for m in mus):
        raise ValueError(f"friction must be {scene.n_fixels} coefficients >= 0, got {mus}")
    if not (math.isfinite(restitution) and 0.0 <= restitution <= 1.0):
        raise ValueError(f"restitution must be in [0, 1], got {restitution!r}")
    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    space.iterations = max(1, round(SOLVER_ITERATIONS * engine.iterations))
    space.collision_slop = SIM_SLOP * engine.slop * L
    wp = scene.workpiece
    body = pymunk.Body(wp.mass, wp.inertia)
    body.center_of_gravity = tuple(wp.com)
    x, y, th = scene.pose
    body.angle = th  # first: pymunk turns the body about its com
    body.position = (x, y)
    if isinstance(wp.shape, Disc):
        shapes = [pymunk.Circle(body, wp.shape.radius)]
    else:
        shapes = [pymunk.Poly(body, piece) for piece in convex_pieces(wp.shape.vertices)]
    for s in shapes:
        s.friction = 1.0
        s.elasticity = float(restitution)
    space.add(body, *shapes)
    fixels = []
    for fx, mu in zip(scene.fixels, mus):
        c = pymunk.Circle(space.static_body, fx.radius + 0.5 * SIM_SLOP * L,
                          offset=tuple(fx.position))
        c.friction = float(mu)
        c.elasticity = 1.0  # Chipmunk multiplies: the impacts' restitution is the body's
        fixels.append(c)
    space.add(*fixels)
    return SceneSpace(space, body, shapes, fixels, L, T)


# --- the readout ---------------------------------------------------------------------
@dataclass(frozen=True)
class Readout:
    """One instant of a simulation: time (s), pose (x m, y m, theta rad), each fixel's
    gap (m), normal and tangential speed of the workpiece at its closest point (m/s),
    impulse of the last step (N s), and the letters (one per fixel, Table 2).

    Parameters
    ----------
    t : float
        Time (s).
    pose : tuple of 3 float
        (x m, y m, theta rad), fixture frame.
    gaps : tuple of float
        Each fixel's gap (m).
    v_n : tuple of float
        Each fixel's normal speed at the closest point (m/s).
    v_t : tuple of float
        Each fixel's tangential speed at the closest point (m/s).
    impulses : tuple of float
        Each fixel's impulse in the last step (N s).
    letters : str
        One letter per fixel (Table 2).
    """

    t: float
    pose: tuple[float, float, float]
    gaps: tuple[float, ...]
    v_n: tuple[float, ...]
    v_t: tuple[float, ...]
    impulses: tuple[float, ...]
    letters: str


@dataclass
class Simulation:
    """A workpiece pulled by an actuator in a pymunk space (module docstring).

    ``direction`` (rad, fixture frame) and the force's ``scale`` (a fraction of the
    actuator's magnitude) may change between steps (:meth:`set_direction`); the time step
    is the full force's. ``restitution``: the impacts' coefficient (0: inelastic).

    Parameters
    ----------
    scene : Scene
        The scene: the workpiece starts at rest at its pose.
    actuator : Actuator
        What pulls.
    direction : float
        Where the force points (rad, fixture frame).
    friction : sequence of float or None, optional
        One mu per fixel (default: the scene's).
    restitution : float, optional
        In [0, 1].
    scale : float, optional
        The fraction of the actuator's force applied.
    engine : EngineSettings, optional
        Factors on the engine's time step, solver iterations and collision slop.

    Raises
    ------
    SimulationUnavailable
        pymunk is not installed.
    """

    scene: Scene
    actuator: Actuator
    direction: float
    friction: Sequence[float] | None = None
    restitution: float = 0.0
    scale: float = 1.0
    engine: EngineSettings = DEFAULT_ENGINE
    sp: SceneSpace = field(init=False)
    t: float = field(init=False, default=0.0)

    def __post_init__(self) -> None:
        self.force = self.actuator.force_magnitude(self.scene)
        self.sp = build_space(self.scene, self.force, self.friction, self.restitution,
                              self.engine)
        self.dt = SIM_TIME_STEP * self.engine.step * self.sp.time_scale
        self.theta0 = self.scene.pose[2]
        self.point = self.actuator.application_point(self.scene)
        self._impulses = [0.0] * self.scene.n_fixels
        self._index = {id(s): i for i, s in enumerate(self.sp.fixels)}
        self.a_ref = self.force / self.scene.workpiece.mass
        self._points = tuple((fx.position, fx.radius) for fx in self.scene.fixels)
        self._query = ShapeQuery.of(self.sp.shapes)
        self._arbiters = ArbiterImpulses.of(self.sp.body, self.sp.fixels)

    def set_direction(self, phi: float, scale: float = 1.0) -> None:
        """Pull along ``phi`` (rad) with ``scale`` times the actuator's force.

        Parameters
        ----------
        phi : float
            The force's direction (rad, fixture frame).
        scale : float, optional
            The fraction of the actuator's force.
        """
        self.direction = float(phi)
        self.scale = float(scale)

    @property
    def pose(self) -> tuple[float, float, float]:
        """The workpiece's pose now: (x m, y m, theta rad), fixture frame."""
        b = self.sp.body
        p = b.position
        return (float(p.x), float(p.y), float(b.angle))

    def twist(self) -> tuple[float, float, float]:
        """The workpiece's velocity now.

        Returns
        -------
        tuple of 3 float
            Its centre of mass's (vx, vy) in m/s and its angular velocity omega in rad/s,
            fixture frame.
        """
        b = self.sp.body
        return (float(b.velocity.x), float(b.velocity.y), float(b.angular_velocity))

    def set_twist(self, twist: Sequence[float]) -> None:
        """Set the workpiece's velocity: (vx, vy) of its centre of mass (m/s) and omega
        (rad/s), fixture frame (a state to start from other than rest).

        Parameters
        ----------
        twist : sequence of 3 float
            (vx, vy, omega).
        """
        vx, vy, w = (float(v) for v in twist)
        self.sp.body.velocity = (vx, vy)
        self.sp.body.angular_velocity = w

    def _force(self) -> tuple[float, float]:
        phi = self.direction
        if self.actuator.follow:
            phi += self.sp.body.angle - self.theta0
        f = self.force * self.scale
        return (f * math.cos(phi), f * math.sin(phi))

    def step(self) -> None:
        """One time step under the actuator's force (applied at its point)."""
        body = self.sp.body
        body.apply_force_at_world_point(self._force(), body.local_to_world(self.point))
        self.sp.space.step(self.dt)
        self.t += self.dt
        if self._arbiters is not None:
            self._impulses = self._arbiters.impulses()
            return
        self._impulses = self._impulses_reference()

    def _impulses_reference(self) -> list[float]:
        """Each fixel's impulse in the last step through pymunk's public
        ``Body.each_arbiter`` (the reference :class:`~.pymunk_boundary.ArbiterImpulses` is tested against)."""
        body = self.sp.body
        imp = [0.0] * self.scene.n_fixels

        def collect(arb) -> None:
            for s in arb.shapes:
                i = self._index.get(id(s))
                if i is not None:
                    imp[i] += arb.total_impulse.length
        body.each_arbiter(collect)
        return imp

    def gaps(self) -> list[float]:
        """Each fixel's gap (m): distance from its centre to the workpiece minus its pin
        radius (negative: overlap).

        Returns
        -------
        list of float
            One gap per fixel (m).
        """
        q = self._query
        if q is None:
            return self._gaps_reference()
        distance = q.distance
        return [distance(p) - r for p, r in self._points]

    def _gaps_reference(self) -> list[float]:
        """:meth:`gaps` through pymunk's public ``Shape.point_query`` (the reference the
        fast path is tested against)."""
        out = []
        for fx in self.scene.fixels:
            d = min(s.point_query(fx.position).distance for s in self.sp.shapes)
            out.append(d - fx.radius)
        return out

    def closest(self, i: int) -> tuple[float, object, object]:
        """Distance (m) from fixel i's centre to the workpiece, the closest point and the
        unit normal from the fixel into the workpiece (pymunk Vec2d). A centre on the
        boundary (a point fixel that touches) gets no closest point from pymunk; the
        point is then the centre and the normal is read just outside it.

        Parameters
        ----------
        i : int
            The fixel's index (0-based).

        Returns
        -------
        distance : float
            m.
        point : pymunk.Vec2d
            The closest point of the workpiece (m, fixture frame).
        normal : pymunk.Vec2d
            The unit normal, from the fixel into the workpiece.
        """
        fx = self.scene.fixels[i]
        if self._query is not None:
            distance, p, n = self._query.closest(fx.position)
        else:
            info = min((s.point_query(fx.position) for s in self.sp.shapes),
                       key=lambda q: q.distance)
            distance, n, p = info.distance, -info.gradient, info.point
        if all(math.isfinite(v) for v in (n.x, n.y, p.x, p.y)):
            return distance, p, n
        # the centre is on the boundary: the normal seen from just outside, away from
        # the com (SIM_SLOP / 100 L), the closest point the centre itself
        c = self.sp.body.local_to_world(self.scene.workpiece.com)
        f = type(p)(*fx.position)
        u = (f - c).normalized()
        q = min((s.point_query(f + u * (0.01 * SIM_SLOP * self.sp.length_scale))
                 for s in self.sp.shapes), key=lambda r: r.distance)
        return distance, f, -q.gradient

    def velocity_tolerance(self) -> float:
        """v_tol (m/s): SIM_VELOCITY_TOLERANCE times a_ref min(t, T).

        Returns
        -------
        float
            m/s.
        """
        return SIM_VELOCITY_TOLERANCE * self.a_ref * min(max(self.t, self.dt),
                                                         self.sp.time_scale)

    def readout(self) -> Readout:
        """Pose, gaps, contact speeds, impulses and letters now (module docstring).

        Returns
        -------
        Readout
            The state now.
        """
        body, L = self.sp.body, self.sp.length_scale
        vtol = self.velocity_tolerance()
        gaps, vns, vts, letters = [], [], [], []
        for i, fx in enumerate(self.scene.fixels):
            distance, point, n = self.closest(i)
            gap = distance - fx.radius
            v = body.velocity_at_world_point(point)
            vn = v.x * n.x + v.y * n.y
            vt = -v.x * n.y + v.y * n.x  # t = rot90(n)
            if gap > SIM_CONTACT_BAND * L:
                ch = "a" if vn < -vtol else "s"
            elif vn > vtol and self._impulses[i] == 0.0:
                ch = "s"
            elif abs(vt) <= vtol:
                ch = "n"
            else:
                ch = "l" if vt > 0 else "r"
            gaps.append(gap)
            vns.append(vn)
            vts.append(vt)
            letters.append(ch)
        return Readout(self.t, self.pose, tuple(gaps), tuple(vns), tuple(vts),
                       tuple(self._impulses), "".join(letters))

    def speed(self) -> float:
        """Largest speed of the workpiece's com (m/s) plus |omega| L.

        Returns
        -------
        float
            m/s.
        """
        b = self.sp.body
        return float(b.velocity.length + abs(b.angular_velocity) * self.sp.length_scale)

    def run(self, duration: float, stop: Callable[[Simulation], str | None] | None = None,
            record_every: int = 1) -> Trajectory:
        """Step for ``duration`` seconds or until ``stop(self)`` returns a reason; the
        readouts every ``record_every`` steps (and the last) form the trajectory.

        Parameters
        ----------
        duration : float
            The longest simulated time (s).
        stop : callable or None, optional
            Called after every step; a reason (str) stops the run.
        record_every : int, optional
            Steps between readouts (0: none).

        Returns
        -------
        Trajectory
            The readouts and the reason the run stopped.
        """
        frames, reason = self._run(duration, stop, record_every, self.readout)
        return Trajectory(tuple(f for _, f in frames), reason)

    def run_poses(self, duration: float,
                  stop: Callable[[Simulation], str | None] | None = None,
                  record_every: int = 1) -> tuple[list[tuple[float, float, float]], str]:
        """:meth:`run`, recording only the poses of its readouts: the same steps, the
        same stop, the same poses at the same instants as the trajectory's frames,
        without computing the rest of each readout (gaps, speeds, letters).

        Parameters
        ----------
        duration : float
            The longest simulated time (s).
        stop : callable or None, optional
            Called after every step; a reason (str) stops the run.
        record_every : int, optional
            Steps between recorded poses (0: none).

        Returns
        -------
        poses : list of tuple of 3 float
            The poses (x m, y m, theta rad) of :meth:`run`'s frames.
        reason : str
            Why the run stopped.
        """
        frames, reason = self._run(duration, stop, record_every, lambda: self.pose)
        return [f for _, f in frames], reason

    def _run(self, duration: float, stop, record_every: int, frame) -> tuple[list, str]:
        """The loop of :meth:`run`: (time, ``frame()``) recorded as it records readouts."""
        steps = max(1, int(math.ceil(duration / self.dt)))
        frames = [(self.t, frame())] if record_every else []
        reason = "time"
        for k in range(steps):
            self.step()
            why = stop(self) if stop is not None else None
            if record_every and ((k + 1) % record_every == 0 or why):
                frames.append((self.t, frame()))
            if why:
                reason = why
                break
        if record_every and frames[-1][0] != self.t:
            frames.append((self.t, frame()))
        return frames, reason


@dataclass(frozen=True)
class Trajectory:
    """Readouts of a simulation in time order and why it stopped ("time" or the stop
    condition's reason).

    Parameters
    ----------
    frames : tuple of Readout
        The readouts, in time order.
    reason : str
        Why the run stopped.
    """

    frames: tuple[Readout, ...]
    reason: str

    @property
    def poses(self) -> np.ndarray:
        """The poses of the frames, shape (k, 3): x (m), y (m), theta (rad)."""
        return np.array([f.pose for f in self.frames], dtype=float).reshape(-1, 3)

    @property
    def letters(self) -> tuple[str, ...]:
        """The letters of the frames, one string per frame."""
        return tuple(f.letters for f in self.frames)


def simulate(scene: Scene, direction: float, actuator: Actuator | str | None = None,
             duration: float | None = None, friction: Sequence[float] | None = None,
             record_every: int = 1) -> Trajectory:
    """The workpiece pulled along ``direction`` (rad, fixture frame) from rest at the
    scene's pose for ``duration`` seconds (default: 2 T), read out every
    ``record_every`` steps (:class:`Readout`).

    Parameters
    ----------
    scene : Scene
        The scene: the workpiece at rest at its pose.
    direction : float
        rad, fixture frame: where the force points.
    actuator : Actuator, str or None, optional
        ``"tilt"`` (default), ``"spring:X,Y"`` or an :class:`Actuator`.
    duration : float or None, optional
        Simulated time (s); None: 2 T.
    friction : sequence of float or None, optional
        One mu per fixel (default: the scene's).
    record_every : int, optional
        Steps between readouts.

    Returns
    -------
    Trajectory
        The readouts.

    Raises
    ------
    SimulationUnavailable
        pymunk is not installed.
    """
    sim = Simulation(scene, Actuator.parse(actuator), direction, friction)
    return sim.run(2.0 * sim.sp.time_scale if duration is None else duration,
                   record_every=record_every)


def initial_mode(scene: Scene, direction: float, actuator: Actuator | str | None = None,
                 friction: Sequence[float] | None = None, time: float | None = None) -> str:
    """The contact mode the simulation shows just after the start from rest.

    To compare with ``consistent_modes`` of the same force: the mode at t = 0 in the
    physics engine (pymunk), an independent check of the cones.

    Parameters
    ----------
    scene : Scene
        The part at rest at its pose.
    direction : float
        rad, fixture frame: where the force points.
    actuator : Actuator or str, optional
        ``"tilt"`` (default), ``"spring:X,Y"`` or an :class:`Actuator`.
    friction : sequence of float, optional
        One mu per fixel (default: the scene's).
    time : float, optional
        When to read the letters, in time scales T. Default 0.05 T, shortened so that a
        free body would close at most a quarter of the smallest free gap
        (T sqrt(gap / 2 L)): the readout must see the start of the motion, not the next
        contact.

    Returns
    -------
    str
        One letter per fixel (Table 2).

    Raises
    ------
    SimulationUnavailable
        pymunk is not installed.
    """
    sim = Simulation(scene, Actuator.parse(actuator), direction, friction)
    if time is None:
        free = [g for g, c in zip(scene.gaps, scene.in_contact) if not c]
        time = min([0.05] + [math.sqrt(g / (2.0 * scene.length_scale)) for g in free])
    steps = max(1, int(round(time / SIM_TIME_STEP)))
    for _ in range(steps):
        sim.step()
    return sim.readout().letters


__all__ = ["Actuator", "DEFAULT_ENGINE", "DEFAULT_TILT", "EngineSettings", "Readout",
           "SceneSpace", "Simulation",
           "SimulationUnavailable", "Trajectory", "build_space", "convex_pieces",
           "initial_mode", "simulate", "time_scale"]
