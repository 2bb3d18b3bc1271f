# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Scene families at the edges of the model, and exact membership: for tests and benchmarks.

The seeded generators of the error-against-run-time study (``benchmarks/error_vs_runtime.py``,
docs/error_vs_runtime.md) and of the stability test (``test/core/test_stability.py``):
each family builder returns a list of :class:`FamilyCase` (a scene dict in the
scene-file schema, the value of the family's parameter, the modes to check). Beside them
the exact reference: :func:`exact_contains` (membership decided in rational arithmetic),
:func:`sample_directions` (uniform and near-boundary directions), :func:`band_for` (the
band around the exact boundary in which either answer is accepted).

Not a test module (pytest does not collect it); importable as ``families`` once ``test/``
is on ``sys.path`` (``test/conftest.py`` puts it there for the tests, ``benchmarks/harness``
for the benchmarks). Benchmarks may import it; it imports nothing from ``benchmarks/``.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np

TOL = 1e-9  # contact tolerance of the generated scenes (m), the core's default

#: Dimensionless band around the exact boundary (docs/error_vs_runtime.md): a unit
#: nondimensional wrench direction whose exact margin is below BAND in absolute value may
#: be classified either way. 10x ``Cone.contains``'s own tolerance (CONE_TOLERANCE).
BAND = 1e-8

#: Multiple of the inputs' own rounding (see :func:`band_for`).
INPUT_ROUNDING_FACTOR = 64


def band_for(scene) -> float:
    """The band for one scene: max(BAND, 64 eps C / L), C the largest world coordinate
    (pose, fixel positions, m), L the length scale. Exact arithmetic reads a float input as
    its shortest decimal, float arithmetic as the binary double; the two differ by up to
    half an ulp, i.e. eps C relative to the body after subtracting the pose. Far from the
    origin (1e7 m offsets, 6 cm bodies: 4e-8) that exceeds BAND, and float and exact may
    then legitimately disagree within a few times that of the boundary."""
    coords = [abs(scene.pose[0]), abs(scene.pose[1])]
    for f in scene.fixels:
        coords += [abs(f.position[0]), abs(f.position[1])]
    return max(BAND, INPUT_ROUNDING_FACTOR * 2.220446049250313e-16 * max(coords)
               / scene.length_scale)


@dataclass
class FamilyCase:
    family: str
    param: str  # e.g. "mass=1e-06"
    data: dict  # scene dict
    modes: list[str] = field(default_factory=list)
    rejected: str = ""  # why load_scene refused the scene (then modes is empty)


def pick_modes(scene, rng: np.random.Generator, k: int, feasible_share: float = 0.5
               ) -> list[str]:
    """k distinct valid modes: about ``feasible_share`` of them with a feasible open mode
    (per the LP oracle ``lp_mode_feasible``, used only to select), the rest uniform."""
    from .strategies import random_mode

    from wrenchcone_ros.core.lp_check import lp_mode_feasible
    from wrenchcone_ros.core.modes import enumerate_modes

    every = list(enumerate_modes(scene.in_contact))
    if len(every) <= k:
        return every
    want_feasible = int(round(k * feasible_share))
    out: list[str] = []
    for _ in range(40 * k):
        if len(out) >= want_feasible:
            break
        m = random_mode(rng, scene.in_contact)
        if m not in out and lp_mode_feasible(scene, m).consistent:
            out.append(m)
    for _ in range(40 * k):
        if len(out) >= k:
            break
        m = random_mode(rng, scene.in_contact)
        if m not in out:
            out.append(m)
    return out


def _load(case: FamilyCase, rng, k: int) -> FamilyCase:
    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.geometry import SceneError

    try:
        scene = load_scene(case.data)
    except SceneError as exc:
        case.rejected = str(exc)
        return case
    case.modes = pick_modes(scene, rng, k)
    return case


def _random_base(rng, **kw) -> dict:
    from .strategies import random_scene

    kw.setdefault("n_fixels", int(rng.integers(2, 5)))
    return random_scene(rng, **kw).data


def _scale_lengths(d: dict, s: float) -> dict:
    """The same scene with every length multiplied by s (inertia by s^2)."""
    d = copy.deepcopy(d)
    wp = d["workpiece"]
    wp["inertia"] *= s * s
    wp["com"] = [c * s for c in wp["com"]]
    wp["pose"] = [wp["pose"][0] * s, wp["pose"][1] * s, wp["pose"][2]]
    sh = wp["shape"]
    if sh["type"] == "disc":
        sh["radius"] *= s
    else:
        sh["vertices"] = [[x * s, y * s] for x, y in sh["vertices"]]
    fx = []
    for f in d["fixels"]:
        if isinstance(f, dict):
            f = dict(f, position=[f["position"][0] * s, f["position"][1] * s],
                     radius=f.get("radius", 0.0) * s)
        else:
            f = [f[0] * s, f[1] * s]
        fx.append(f)
    d["fixels"] = fx
    return d


def _offset(d: dict, dx: float, dy: float) -> dict:
    d = copy.deepcopy(d)
    wp = d["workpiece"]
    wp["pose"] = [wp["pose"][0] + dx, wp["pose"][1] + dy, wp["pose"][2]]
    fx = []
    for f in d["fixels"]:
        if isinstance(f, dict):
            f = dict(f, position=[f["position"][0] + dx, f["position"][1] + dy])
        else:
            f = [f[0] + dx, f[1] + dy]
        fx.append(f)
    d["fixels"] = fx
    return d


def _scene_dict(shape: dict, fixels: list, mu: float, mass=1.0, inertia=None, com=(0.0, 0.0),
                pose=(0.0, 0.0, 0.0), tol=TOL) -> dict:
    return {"workpiece": {"mass": mass, "inertia": mass * 0.5 if inertia is None else inertia,
                          "com": list(com), "shape": shape, "pose": list(pose)},
            "friction": mu, "contact_tolerance": tol, "fixels": fixels}


def _g(x: float) -> str:
    return f"{x:.0e}" if x not in (0.0, 1.0) else f"{x:g}"


def family_paper(rng, size: int) -> list[FamilyCase]:
    """The paper's worked example (section 4), every valid mode."""
    from wrenchcone_ros.core import PAPER_DISC, load_scene
    from wrenchcone_ros.core.modes import enumerate_modes

    d = copy.deepcopy(PAPER_DISC)
    d.pop("modes", None)
    return [FamilyCase("paper", "paper example", d,
                       list(enumerate_modes(load_scene(d).in_contact)))]


def family_random(rng, size: int) -> list[FamilyCase]:
    """Random valid scenes (test/strategies.random_scene, normal ranges)."""
    return [_load(FamilyCase("random", "random", _random_base(rng)), rng, 3)
            for _ in range(size)]


def family_mass(rng, size: int) -> list[FamilyCase]:
    """Mass 1e-6..1e6 kg, I / (m L^2) kept (so the inertia scales with the mass)."""
    out = []
    for m in 10.0 ** np.arange(-6, 7, 2):
        for _ in range(size):
            d = _random_base(rng)
            wp = d["workpiece"]
            wp["inertia"] *= m / wp["mass"]
            wp["mass"] = float(m)
            out.append(_load(FamilyCase("mass", f"m={_g(m)} kg", d), rng, 2))
    return out


def family_inertia(rng, size: int) -> list[FamilyCase]:
    """I / (m L^2) from 1e-8 to 1e6 every 2 decades (L the scene's length scale): the
    whole range load_scene accepts (ACCEPTED_INERTIA_RATIO)."""
    from wrenchcone_ros.core import load_scene

    out = []
    from wrenchcone_ros.core.tolerances import ACCEPTED_INERTIA_RATIO

    lo, hi = (round(math.log10(v)) for v in ACCEPTED_INERTIA_RATIO)
    for k in 10.0 ** np.arange(lo, hi + 1, 2):
        for _ in range(size):
            d = _random_base(rng)
            L = load_scene(d).length_scale
            d["workpiece"]["inertia"] = float(k * d["workpiece"]["mass"] * L * L)
            out.append(_load(FamilyCase("inertia", f"I/(mL^2)={_g(k)}", d), rng, 2))
    return out


def family_mu(rng, size: int) -> list[FamilyCase]:
    """mu in {0, 1e-9, 1e-3, 1, 1e3, 1e9} (one coefficient for every fixel)."""
    out = []
    for mu in (0.0, 1e-9, 1e-3, 1.0, 1e3, 1e9):
        for _ in range(size):
            d = _random_base(rng, per_fixel_friction=False, mu=mu)
            out.append(_load(FamilyCase("mu", f"mu={_g(mu)}", d), rng, 3))
    return out


def _bent_edge(delta: float) -> list:
    """A convex pentagon whose bottom edge is bent by ``delta`` rad at x = 0."""
    h = math.tan(delta / 2.0)
    return [[-1.0, -1.0], [0.0, -1.0 - h], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]


def family_parallel(rng, size: int) -> list[FamilyCase]:
    """Two contacts 1 m apart whose normals differ by delta = 1e-3..1e-12 rad (a pentagon
    with a bottom edge bent by delta), plus a side contact and a free fixel."""
    out = []
    for e in range(3, 13):
        delta = 10.0 ** -e
        for _ in range(size):
            h = math.tan(delta / 2.0)
            x1, x2 = rng.uniform(-0.9, -0.1), rng.uniform(0.1, 0.9)
            fixels = [[x1, -1.0 - h * (x1 + 1.0)], [x2, -1.0 - h * (1.0 - x2)],
                      [1.0, float(rng.uniform(-0.8, 0.8))], [-1.2, 0.5]]
            d = _scene_dict({"type": "polygon", "vertices": _bent_edge(delta)}, fixels,
                            mu=float(rng.choice([0.0, 0.3, 1.0])), mass=1.0,
                            inertia=float(rng.uniform(0.2, 1.0)),
                            com=[float(rng.uniform(-0.2, 0.2)), float(rng.uniform(-0.2, 0.2))])
            out.append(_load(FamilyCase("parallel", f"delta={_g(delta)} rad", d), rng, 4))
    return out


def family_coincident(rng, size: int) -> list[FamilyCase]:
    """Two touching fixels 1e-3..1e-12 (relative to the body size) apart: on a flat
    polygon edge (same normal) and on a disc (normals then differ by the same angle)."""
    out = []
    for e in range(3, 13):
        sep = 10.0 ** -e
        for k in range(size):
            mu = float(rng.choice([0.0, 0.25, 1.0]))
            if k % 2 == 0:  # disc of radius 1, fixels at phi and phi + sep
                phi = float(rng.uniform(-math.pi, math.pi))
                fixels = [[math.cos(phi), math.sin(phi)],
                          [math.cos(phi + sep), math.sin(phi + sep)],
                          [math.cos(phi + 2.2), math.sin(phi + 2.2)], [0.0, 1.3]]
                shape = {"type": "disc", "radius": 1.0}
            else:  # square, fixels at x and x + sep on the bottom edge
                x = float(rng.uniform(-0.8, 0.8))
                fixels = [[x, -1.0], [x + sep, -1.0], [1.0, float(rng.uniform(-0.8, 0.8))],
                          [-1.3, 0.0]]
                shape = {"type": "polygon",
                         "vertices": [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]}
            d = _scene_dict(shape, fixels, mu=mu, inertia=float(rng.uniform(0.2, 1.0)),
                            com=[float(rng.uniform(-0.2, 0.2)), float(rng.uniform(-0.2, 0.2))])
            out.append(_load(FamilyCase("coincident", f"sep={_g(sep)} L", d), rng, 4))
    return out


def family_offset(rng, size: int) -> list[FamilyCase]:
    """The whole scene translated 1e3..1e7 m from the world origin."""
    out = []
    for D in 10.0 ** np.arange(3, 8):
        for _ in range(size):
            a = float(rng.uniform(0, 2 * math.pi))
            d = _offset(_random_base(rng), D * math.cos(a), D * math.sin(a))
            out.append(_load(FamilyCase("offset", f"offset={_g(D)} m", d), rng, 2))
    return out


def family_size(rng, size: int) -> list[FamilyCase]:
    """Body sizes 1e-6..1e3 m (the whole scene scaled; contact tolerance kept at 1e-9 m)."""
    from .strategies import random_scene

    out = []
    for s in 10.0 ** np.arange(-6, 4, 1):
        for _ in range(max(1, size // 2)):
            gs = random_scene(rng, n_fixels=int(rng.integers(2, 5)))
            d = _scale_lengths(gs.data, float(s) / gs.size)
            out.append(_load(FamilyCase("size", f"size={_g(s)} m", d), rng, 2))
    return out


def family_gaps(rng, size: int) -> list[FamilyCase]:
    """Gaps at the contact tolerance: random degenerate scenes (touching gaps within
    +-0.5 tol, free gaps of 2..10 tol, a near-twin fixel), and the paper's disc with its
    free fixel at -0.99..2 tolerances."""
    from .strategies import random_scene

    out = []
    for _ in range(size):
        gs = random_scene(rng, n_fixels=int(rng.integers(2, 4)), degenerate=True)
        out.append(_load(FamilyCase("gaps", "degenerate random", gs.data), rng, 3))
    for k in (-0.99, -0.5, 0.0, 0.5, 0.99, 1.01, 2.0):
        fixels = [[0.0, -1.0 - 0.9 * TOL], [1.0 + k * TOL, 0.0], [-0.6, 0.8 + 0.99 * TOL]]
        d = _scene_dict({"type": "disc", "radius": 1.0}, fixels, mu=0.2, inertia=1.0)
        out.append(_load(FamilyCase("gaps", f"gap={k:g} tol", d), rng, 6))
    return out


def family_shared_edge(rng, size: int) -> list[FamilyCase]:
    """2-4 touching fixels (points and pins) on one straight edge of a convex or non-convex
    polygon at a random angle, plus 0-2 other fixels (test/strategies.shared_edge_scene):
    the common fixture layout whose tangential rows are parallel by construction."""
    from .strategies import shared_edge_scene

    out = []
    for n in (2, 3, 4):
        for convex in (True, False):
            for _ in range(size):
                gs = shared_edge_scene(rng, n_shared=n, convex=convex)
                kind = "convex" if convex else "non-convex"
                out.append(_load(FamilyCase("shared_edge", f"{n} on one edge, {kind}",
                                            gs.data), rng, 4))
    return out


FAMILIES = {
    "paper": family_paper,
    "random": family_random,
    "mass": family_mass,
    "inertia": family_inertia,
    "mu": family_mu,
    "parallel": family_parallel,
    "coincident": family_coincident,
    "offset": family_offset,
    "size": family_size,
    "gaps": family_gaps,
    "shared_edge": family_shared_edge,
}

FAMILY_TITLES = {
    "paper": "paper example (section 4), all 8 valid modes",
    "random": "random normal scenes",
    "mass": "mass 1e-6..1e6 kg",
    "inertia": "I/(m L^2) 1e-8..1e6",
    "mu": "mu in {0, 1e-9, 1e-3, 1, 1e3, 1e9}",
    "parallel": "nearly parallel normals, 1e-3..1e-12 rad",
    "coincident": "nearly coincident fixels, 1e-3..1e-12 L apart",
    "offset": "world offsets 1e3..1e7 m",
    "size": "body sizes 1e-6..1e3 m",
    "gaps": "gaps at the contact tolerance",
    "shared_edge": "2-4 fixels on one polygon edge at a random angle",
}


# ----------------------------------------------------------------------------- exact truth


def exact_contains(cone, u) -> bool:
    """Membership of the nondimensional vector u (floats, taken exactly) in an exact Cone,
    decided in rational arithmetic from ``cone.exact_rep`` (False for an infeasible mode)."""
    from fractions import Fraction

    if not cone.feasible:
        return False
    rep = cone.exact_rep
    q = [Fraction(float(x)) for x in u]
    for f in rep.F:
        if f[0] * q[0] + f[1] * q[1] + f[2] * q[2] > 0:
            return False
    for e in rep.E:
        if e[0] * q[0] + e[1] * q[1] + e[2] * q[2] != 0:
            return False
    return True


def sample_directions(rng: np.random.Generator, target, n_uniform: int, n_boundary: int,
                      delta_range=(1e-14, 1e-2)) -> np.ndarray:
    """Unit nondimensional directions: n_uniform uniform on the sphere, then n_boundary
    near the boundary of ``target`` (a Cone; use the closure of an infeasible one): a
    random point of a random face (positive combination of the face's extreme rays plus
    lineality), pushed off it by an angle log-uniform in delta_range, random direction."""
    u = rng.normal(size=(n_uniform, 3))
    out = list(u / np.linalg.norm(u, axis=1, keepdims=True))
    F, G, Lh = target.F_hat, target.G_hat, target.L_hat
    for _ in range(n_boundary):
        p = None
        if F.shape[0]:
            i = int(rng.integers(F.shape[0]))
            on = G[np.abs(G @ F[i]) <= 1e-9] if G.shape[0] else np.zeros((0, 3))
            p = np.zeros(3)
            if on.shape[0]:
                p += rng.exponential(size=on.shape[0]) @ on
            if Lh.shape[0]:
                p += rng.normal(size=Lh.shape[0]) @ Lh
        elif G.shape[0] or Lh.shape[0]:  # a cone without facets: a ray, a line, a plane
            p = np.zeros(3)
            if G.shape[0]:
                p += rng.exponential(size=G.shape[0]) @ G
            if Lh.shape[0]:
                p += rng.normal(size=Lh.shape[0]) @ Lh
        if p is None or np.linalg.norm(p) == 0:
            v = rng.normal(size=3)
            out.append(v / np.linalg.norm(v))
            continue
        p /= np.linalg.norm(p)
        w = rng.normal(size=3)
        w -= (w @ p) * p
        w /= np.linalg.norm(w)
        delta = math.exp(rng.uniform(math.log(delta_range[0]), math.log(delta_range[1])))
        v = p + math.tan(delta) * w
        out.append(v / np.linalg.norm(v))
    return np.array(out).reshape(-1, 3)


def si_wrench(u: np.ndarray, length_scale: float) -> np.ndarray:
    """The SI wrench (f_x, f_y, tau) whose nondimensional direction is u."""
    return np.array([u[0], u[1], u[2] * length_scale])


