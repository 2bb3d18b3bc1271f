# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Random scenes, modes and wrenches for tests and benchmarks.

Two layers over the same code:

* seeded generators taking a ``numpy.random.Generator`` (reproducible, fast, used by the
  randomized cross-check and by benchmarks): :func:`random_scene`, :func:`random_mode`,
  :func:`random_wrench`, :func:`wrench_from_cone`;
* hypothesis strategies built on them: :func:`scenes`, :func:`scenes_and_modes`,
  :func:`wrenches`.

Scenes are plain dicts in the scene-file schema (``load_scene`` accepts them). Contacts
are placed exactly on the boundary: for a disc at ``centre + (R + pin_radius) * dir``;
for a polygon at an interior point of an edge (away from its vertices), offset outward by
the pin radius along the edge's outward normal, and only where no other edge comes within
the pin radius (so the fixel neither penetrates nor touches twice). Free fixels are placed
with a gap well above the contact tolerance (at least 1 % of the workpiece size).

Every generated scene comes with the contact state it was built to have
(:attr:`GeneratedScene.in_contact`), so a test can check the core's geometry against it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

try:  # hypothesis is a test dependency; benchmarks use the seeded generators only
    from hypothesis import strategies as st
except ImportError:  # pragma: no cover
    st = None

#: Letters allowed per contact state (Table 2): kept literal so that the generators do not
#: depend on the code under test; test_lp_check checks MODE_TABLE against the same table.
CONTACT_LETTERS = "slrn"
FREE_LETTERS = "as"

SHAPES = ("disc", "convex", "nonconvex")


@dataclass
class GeneratedScene:
    """A scene dict plus what it was built to be."""

    data: dict
    in_contact: tuple[bool, ...]
    shape: str  # "disc", "convex" or "nonconvex"
    pin_radii: tuple[float, ...]
    size: float  # characteristic size of the workpiece (m), for the generator's own use
    notes: dict = field(default_factory=dict)

    @property
    def has_pins(self) -> bool:
        return any(r > 0 for r in self.pin_radii)

    @property
    def n_fixels(self) -> int:
        return len(self.in_contact)


# --------------------------------------------------------------------------- geometry


def _rot(theta: float) -> np.ndarray:
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s], [s, c]])


def _seg_dist(q: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    d = b - a
    t = float(np.clip(np.dot(q - a, d) / np.dot(d, d), 0.0, 1.0))
    return float(np.linalg.norm(q - (a + t * d)))


def _inside(q: np.ndarray, verts: np.ndarray) -> bool:
    """Even-odd point-in-polygon test."""
    x, y = q
    inside = False
    k = len(verts)
    for i in range(k):
        (x1, y1), (x2, y2) = verts[i], verts[(i + 1) % k]
        if (y1 > y) != (y2 > y):
            xc = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if xc > x:
                inside = not inside
    return inside


def _signed_area(verts: np.ndarray) -> float:
    x, y = verts[:, 0], verts[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def random_polygon(rng: np.random.Generator, convex: bool, size: float = 1.0) -> np.ndarray:
    """Counter-clockwise simple polygon around the origin, vertices (k, 2).

    Convex: points on a circle of radius ``size`` at sorted random angles (gaps between
    consecutive angles below pi so the origin is inside). Non-convex: a star-shaped
    polygon (sorted angles, radii in [0.35, 1] * size) with at least one reflex vertex.
    """
    while True:
        k = int(rng.integers(3, 8)) if convex else int(rng.integers(5, 10))
        ang = np.sort(rng.uniform(0, 2 * math.pi, k))
        gaps = np.diff(np.concatenate([ang, [ang[0] + 2 * math.pi]]))
        if gaps.min() < 0.25 or gaps.max() > 0.9 * math.pi:
            continue
        if convex:
            rad = np.full(k, size)
        else:
            rad = size * rng.uniform(0.35, 1.0, k)
        verts = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
        if _signed_area(verts) <= 0:
            continue
        reflex = _reflex_count(verts)
        if convex and reflex == 0:
            return verts
        if not convex and reflex > 0:
            return verts


def _reflex_count(verts: np.ndarray) -> int:
    k = len(verts)
    n = 0
    for i in range(k):
        a, b, c = verts[i - 1], verts[i], verts[(i + 1) % k]
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        if cross < 0:
            n += 1
    return n


def _polygon_fixel(rng: np.random.Generator, verts: np.ndarray, radius: float, gap: float,
                   size: float, edge: int | None = None, param: float | None = None,
                   touching: bool | None = None):
    """Fixel centre (workpiece frame) near a random edge at ``radius + gap`` outward.

    In contact (``touching``, default ``gap == 0``; a touching fixel may be given a gap
    within the contact tolerance): on an interior point of the edge (parameter in [0.15, 0.85]),
    offset by ``radius`` along the outward normal, and every other edge at least
    ``radius + 0.01 size`` away. Free: the centre is outside and its distance to the
    polygon exceeds ``radius + 0.5 gap``. ``edge`` and ``param`` fix the edge and the
    parameter along it instead of drawing them. Returns (centre, edge, param), or None when
    this draw does not qualify.
    """
    k = len(verts)
    j = int(rng.integers(k)) if edge is None else edge
    a, b = verts[j], verts[(j + 1) % k]
    e = b - a
    out = np.array([e[1], -e[0]]) / np.linalg.norm(e)  # outward for CCW
    tpar = rng.uniform(0.15, 0.85) if param is None else param
    q = a + tpar * e
    f = q + (radius + gap) * out
    if _inside(q + (radius + abs(gap) + 1e-6 * size) * out, verts):  # not on the boundary
        return None
    dists = [_seg_dist(f, verts[i], verts[(i + 1) % k]) for i in range(k)]
    if touching is None:
        touching = gap == 0.0
    if touching or edge is not None:
        others = [d for i, d in enumerate(dists) if i != j]
        if min(others) < radius + 0.01 * size:
            return None
    elif min(dists) < radius + 0.5 * gap:
        return None
    return f, j, tpar


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


# --------------------------------------------------------------------------- scenes


def random_scene(rng: np.random.Generator, *, shape: str | None = None,
                 n_fixels: int | None = None, n_contact: int | None = None,
                 pins: bool | None = None, mu: float | None = None,
                 extreme: bool = False, per_fixel_friction: bool = True,
                 degenerate: bool = False) -> GeneratedScene:
    """A random valid scene (dict in the scene-file schema) and its intended contact state.

    shape: "disc", "convex" or "nonconvex" (random when None). n_fixels: 1..5 by default;
    n_contact: how many of them touch (default: random, at least one). pins: whether the
    fixels have radii (random per scene when None; then each fixel is a pin with
    probability 1/2). mu: friction coefficient (random when None, 0 in about 1 of 8
    scenes); per_fixel_friction: about 1 fixel in 4 gets its own coefficient (a third of
    those 0). extreme=True widens mass, inertia, size and position ranges (mass 1e-4..1e4,
    I / (m L^2) 1e-4..1e2, positions up to 1e3 m). degenerate=True adds the awkward cases
    docs/numerics.md discusses: touching fixels at a gap of up to +-0.5 contact tolerance, free fixels
    at 2..10 tolerances, and one extra fixel (touching, appended last) a tiny distance
    (1e-7..1e-3 of the size) along the boundary from a touching one: nearly coincident
    fixels with nearly parallel normals.
    """
    shape = shape or SHAPES[int(rng.integers(len(SHAPES)))]
    if shape not in SHAPES:
        raise ValueError(f"shape must be one of {SHAPES}, got {shape!r}")
    n_fixels = int(rng.integers(1, 6)) if n_fixels is None else int(n_fixels)
    if n_contact is None:
        n_contact = int(rng.integers(1, n_fixels + 1)) if n_fixels else 0
    n_contact = min(int(n_contact), n_fixels)
    if pins is None:
        pins = bool(rng.integers(2))
    if mu is None:
        u = rng.uniform()
        mu = 0.0 if u < 0.125 else (_log_uniform(rng, 0.02, 1.5) if u < 0.9
                                    else _log_uniform(rng, 1.5, 10.0))

    if extreme:
        size = _log_uniform(rng, 1e-3, 1e2)
        mass = _log_uniform(rng, 1e-4, 1e4)
        ratio = _log_uniform(rng, 1e-4, 1e2)
        reach = _log_uniform(rng, 1e-3, 1e3)
    else:
        size = _log_uniform(rng, 0.05, 5.0)
        mass = _log_uniform(rng, 0.05, 20.0)
        ratio = _log_uniform(rng, 0.05, 1.0)
        reach = 10.0 * size
    inertia = mass * ratio * size * size
    theta = float(rng.uniform(-math.pi, math.pi))
    trans = rng.uniform(-reach, reach, 2)
    com_local = rng.uniform(-0.3, 0.3, 2) * size
    R = _rot(theta)

    contact_flags = [True] * n_contact + [False] * (n_fixels - n_contact)
    rng.shuffle(contact_flags)
    radii = [(_log_uniform(rng, 0.005, 0.2) * size if (pins and rng.integers(2)) else 0.0)
             for _ in range(n_fixels)]

    if shape == "disc":
        shape_d = {"type": "disc", "radius": size}
        verts = None
    else:
        verts = random_polygon(rng, convex=(shape == "convex"), size=size)
        shape_d = {"type": "polygon", "vertices": verts.tolist()}

    tol = 1e-9
    fixels = []
    placed = []  # (index, r, disc angle or (edge, param)) of touching fixels
    twin = degenerate and n_contact > 0
    for idx in range(n_fixels + twin):
        if idx < n_fixels:
            touching, r = contact_flags[idx], radii[idx]
            for _attempt in range(200):
                if touching:
                    gap = rng.uniform(-0.5, 0.5) * tol if degenerate else 0.0
                elif degenerate and rng.integers(2):
                    gap = rng.uniform(2.0, 10.0) * tol
                else:
                    gap = _log_uniform(rng, 0.01, 0.5) * size
                if shape == "disc":
                    phi = rng.uniform(-math.pi, math.pi)
                    f_local = (size + r + gap) * np.array([math.cos(phi), math.sin(phi)])
                    where = phi
                else:
                    got = _polygon_fixel(rng, verts, r, gap, size, touching=touching)
                    if got is None:
                        continue
                    f_local, where = got[0], got[1:]
                break
            else:  # pragma: no cover - practically unreachable
                raise RuntimeError("could not place a fixel")
            if touching:
                placed.append((idx, r, where))
        else:  # the near-coincident twin of a touching fixel
            for _attempt in range(200):
                _, r, where = placed[int(rng.integers(len(placed)))]
                delta = _log_uniform(rng, 1e-7, 1e-3) * size * (1 if rng.integers(2) else -1)
                if shape == "disc":
                    phi = where + delta / size
                    f_local = (size + r) * np.array([math.cos(phi), math.sin(phi)])
                    break
                j, tpar = where
                elen = float(np.linalg.norm(verts[(j + 1) % len(verts)] - verts[j]))
                got = _polygon_fixel(rng, verts, r, 0.0, size, edge=j, param=tpar + delta / elen)
                if got is not None:
                    f_local = got[0]
                    break
            else:  # pragma: no cover
                raise RuntimeError("could not place a twin fixel")
            contact_flags.append(True)
            radii.append(r)
        pos = (R @ f_local + trans).tolist()
        own_mu = None
        if per_fixel_friction and rng.uniform() < 0.25:
            own_mu = 0.0 if rng.integers(3) == 0 else _log_uniform(rng, 0.02, 3.0)
        if own_mu is not None:
            fixels.append({"position": pos, "radius": float(r), "friction": own_mu})
        elif r > 0 or rng.integers(2):
            fixels.append({"position": pos, "radius": float(r)})
        else:
            fixels.append(pos)

    data = {
        "workpiece": {
            "mass": mass,
            "inertia": inertia,
            "com": com_local.tolist(),
            "shape": shape_d,
            "pose": [float(trans[0]), float(trans[1]), theta],
        },
        "friction": float(mu),
        "contact_tolerance": tol,
        "fixels": fixels,
    }
    return GeneratedScene(data, tuple(contact_flags), shape, tuple(radii), size,
                          {"mu": mu, "extreme": extreme, "degenerate": degenerate})


def shared_edge_scene(rng: np.random.Generator, *, n_shared: int | None = None,
                      convex: bool | None = None, pins: bool | None = None,
                      n_extra: int | None = None, mu: float | None = None) -> GeneratedScene:
    """2-4 touching fixels (points and pins) on one straight edge of a random convex or
    non-convex polygon, at a random pose angle (so the edge is at a random angle in the
    world), plus 0-2 other fixels (touching another edge or free).

    A fixture layout whose contacts lie on one edge: they share their normal, so their
    tangential acceleration rows are parallel by construction. The shared fixels are at
    least 5 % of the edge apart (nearly coincident fixels are family_coincident's case).
    """
    convex = bool(rng.integers(2)) if convex is None else convex
    n_shared = int(rng.integers(2, 5)) if n_shared is None else int(n_shared)
    n_extra = int(rng.integers(0, 3)) if n_extra is None else int(n_extra)
    pins = bool(rng.integers(2)) if pins is None else pins
    if mu is None:
        mu = 0.0 if rng.uniform() < 0.125 else _log_uniform(rng, 0.02, 1.5)
    size = _log_uniform(rng, 0.05, 5.0)
    mass = _log_uniform(rng, 0.05, 20.0)
    inertia = mass * _log_uniform(rng, 0.05, 1.0) * size * size
    theta = float(rng.uniform(-math.pi, math.pi))
    trans = rng.uniform(-10.0 * size, 10.0 * size, 2)
    R = _rot(theta)
    for _attempt in range(1000):
        verts = random_polygon(rng, convex=convex, size=size)
        j = int(rng.integers(len(verts)))
        params = np.sort(rng.uniform(0.1, 0.9, n_shared))
        if n_shared > 1 and np.diff(params).min() < 0.05:
            continue
        radii = [(_log_uniform(rng, 0.005, 0.1) * size if (pins and rng.integers(2)) else 0.0)
                 for _ in range(n_shared)]
        got = [_polygon_fixel(rng, verts, r, 0.0, size, edge=j, param=float(t))
               for r, t in zip(radii, params)]
        if any(g is None for g in got):
            continue
        local = [g[0] for g in got]
        flags = [True] * n_shared
        for _ in range(n_extra):
            touching = bool(rng.integers(2))
            r = _log_uniform(rng, 0.005, 0.1) * size if (pins and rng.integers(2)) else 0.0
            gap = 0.0 if touching else _log_uniform(rng, 0.01, 0.5) * size
            for _try in range(200):
                g = _polygon_fixel(rng, verts, r, gap, size, touching=touching)
                if g is not None and (not touching or g[1] != j):
                    break
            else:
                break
            local.append(g[0])
            radii.append(r)
            flags.append(touching)
        if len(local) == n_shared + n_extra:
            break
    else:  # pragma: no cover - practically unreachable
        raise RuntimeError("could not place fixels on one edge")
    order = rng.permutation(len(local))
    fixels = [{"position": (R @ local[k] + trans).tolist(), "radius": float(radii[k])}
              for k in order]
    data = {
        "workpiece": {"mass": mass, "inertia": inertia,
                      "com": (rng.uniform(-0.3, 0.3, 2) * size).tolist(),
                      "shape": {"type": "polygon", "vertices": verts.tolist()},
                      "pose": [float(trans[0]), float(trans[1]), theta]},
        "friction": float(mu), "contact_tolerance": 1e-9, "fixels": fixels,
    }
    return GeneratedScene(data, tuple(flags[k] for k in order),
                          "convex" if convex else "nonconvex",
                          tuple(radii[k] for k in order), size,
                          {"mu": mu, "shared_edge": j, "n_shared": n_shared})


# --------------------------------------------------------------------------- modes, wrenches


def random_mode(rng: np.random.Generator, in_contact) -> str:
    """A random valid mode string for the contact state (one allowed letter per fixel)."""
    return "".join(
        (CONTACT_LETTERS if t else FREE_LETTERS)[
            int(rng.integers(len(CONTACT_LETTERS if t else FREE_LETTERS)))]
        for t in in_contact)


def random_wrench(rng: np.random.Generator, length_scale: float, scale: float | None = None
                  ) -> np.ndarray:
    """A wrench (f_x, f_y, tau) whose nondimensional direction (f_x, f_y, tau/L) is uniform
    on the unit sphere; magnitude ``scale`` (log-uniform in [1e-3, 1e3] when None)."""
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    if scale is None:
        scale = _log_uniform(rng, 1e-3, 1e3)
    return scale * np.array([u[0], u[1], u[2] * length_scale])


def wrench_from_cone(rng: np.random.Generator, cone, length_scale: float) -> np.ndarray | None:
    """A random positive combination of the cone's generators plus a random lineality
    component (None when the cone has neither), to sample wrenches inside the cone.

    Uses ``cone.G`` and ``cone.lineality`` only to propose samples; the tests decide
    consistency independently.
    """
    G = np.asarray(getattr(cone, "G", np.zeros((0, 3))), dtype=float).reshape(-1, 3)
    Lin = np.asarray(getattr(cone, "lineality", np.zeros((0, 3))), dtype=float).reshape(-1, 3)
    if len(G) == 0 and len(Lin) == 0:
        return None
    g = np.zeros(3)
    if len(G):
        # normalise rows in the nondimensional metric so the weights mean something
        Gh = G / np.maximum(_nd_norm(G, length_scale), 1e-300)[:, None]
        g += rng.exponential(size=len(Gh)) @ Gh
    if len(Lin):
        Lh = Lin / np.maximum(_nd_norm(Lin, length_scale), 1e-300)[:, None]
        g += rng.normal(size=len(Lh)) @ Lh
    return g * _log_uniform(rng, 1e-3, 1e3)


#: Force rules of Table 2, literal: signs s of the friction-cone edges c_n (n + s mu t)
#: a loaded fixel may use ("a" and "s" carry no force).
FORCE_EDGES = {"a": (), "s": (), "l": (-1,), "r": (1,), "n": (-1, 1)}


def wrench_from_witness(rng: np.random.Generator, scene, mode: str, witness) -> np.ndarray | None:
    """A wrench built from Newton-Euler, without any cone: ``g = lam M xdd - J c``.

    ``witness``: an acceleration meeting the mode's acceleration conditions (strictly, for
    a possible mode; e.g. ``lp_mode_feasible(..., witness=True).witness``), or None.
    ``c`` is drawn from the mode's force rules (every loadable fixel loaded). With a strict
    witness and ``lam > 0`` the wrench is consistent with the mode by construction; with
    ``witness=None`` it is a static equilibrium wrench, a member of the mode's closure.
    Returns None when both parts vanish. J is built by the LP module from the contact
    frames (no paper matrices).
    """
    from wrenchcone_ros.core.lp_check import contact_jacobian

    L = float(scene.length_scale)
    J = contact_jacobian(scene)
    n = len(mode)
    cn, ct = np.zeros(n), np.zeros(n)
    for i, ch in enumerate(mode):
        edges = FORCE_EDGES[ch]
        if not edges:
            continue
        w = rng.exponential(size=len(edges))
        cn[i] = w.sum()
        ct[i] = float(scene.mu(i)) * float(np.dot(w, edges))
    parts = []
    f = -(J @ np.concatenate([cn, ct]))
    if np.linalg.norm(f) > 0:
        parts.append(f / _nd_norm(f, L)[0] * rng.uniform(0.0, 1.0))
    if witness is not None and np.any(np.asarray(witness) != 0):
        m, inertia = float(scene.workpiece.mass), float(scene.workpiece.inertia)
        a = np.array([m, m, inertia]) * np.asarray(witness, dtype=float)
        parts.append(a / _nd_norm(a, L)[0] * rng.uniform(0.05, 1.0))
    if not parts:
        return None
    g = np.sum(parts, axis=0)
    if _nd_norm(g, L)[0] == 0:
        return None
    return g * _log_uniform(rng, 1e-3, 1e3)


def _nd_norm(rows: np.ndarray, length_scale: float) -> np.ndarray:
    r = np.asarray(rows, dtype=float).reshape(-1, 3)
    return np.sqrt(r[:, 0] ** 2 + r[:, 1] ** 2 + (r[:, 2] / length_scale) ** 2)


def nondimensional_direction(g, length_scale: float) -> np.ndarray:
    """The unit vector of (f_x, f_y, tau / L)."""
    g = np.asarray(g, dtype=float)
    h = np.array([g[0], g[1], g[2] / length_scale])
    return h / np.linalg.norm(h)


# --------------------------------------------------------------------------- hypothesis

if st is not None:

    @st.composite
    def scenes(draw, shape=None, max_fixels: int = 5, extreme: bool = False,
               degenerate: bool = False):
        """Hypothesis strategy: a :class:`GeneratedScene` (structure drawn by hypothesis,
        details by a drawn seed)."""
        shp = shape or draw(st.sampled_from(SHAPES))
        n = draw(st.integers(1, max_fixels))
        nc = draw(st.integers(0, n))
        pins = draw(st.booleans())
        mu = draw(st.one_of(st.just(0.0), st.floats(0.01, 5.0), st.none()))
        seed = draw(st.integers(0, 2**32 - 1))
        return random_scene(np.random.default_rng(seed), shape=shp, n_fixels=n,
                            n_contact=nc, pins=pins, mu=mu, extreme=extreme,
                            degenerate=degenerate)

    @st.composite
    def modes_for(draw, in_contact):
        """Hypothesis strategy: a valid mode string for a contact state."""
        return "".join(draw(st.sampled_from(CONTACT_LETTERS if t else FREE_LETTERS))
                       for t in in_contact)

    @st.composite
    def scenes_and_modes(draw, **kw):
        """Hypothesis strategy: (GeneratedScene, valid mode string)."""
        gs = draw(scenes(**kw))
        return gs, draw(modes_for(gs.in_contact))

    @st.composite
    def shared_edge_scenes(draw):
        """Hypothesis strategy: a :func:`shared_edge_scene` (structure drawn by hypothesis)."""
        seed = draw(st.integers(0, 2**32 - 1))
        return shared_edge_scene(np.random.default_rng(seed),
                                 n_shared=draw(st.integers(2, 4)), convex=draw(st.booleans()),
                                 pins=draw(st.booleans()), n_extra=draw(st.integers(0, 2)))

    def wrenches(length_scale: float = 1.0):
        """Hypothesis strategy: a wrench with a uniform-ish nondimensional direction."""
        comp = st.floats(-1.0, 1.0, allow_nan=False)
        return (st.tuples(comp, comp, comp)
                .filter(lambda v: math.hypot(*v) > 1e-3)
                .map(lambda v: np.array([v[0], v[1], v[2] * length_scale])))
