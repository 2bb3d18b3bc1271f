# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Seating tasks that look like users' fixtures: unequal pins, turned and mirrored frames.

Three transforms of a scene dict (the scene-file schema) that keep the physics the same:

* :func:`resize_pins`: pin i gets radius r_i' and its centre moves by (r_i' - r_i) away
  from the part, along the line from the part's closest point to the pin's centre (for
  a pin in contact: minus the contact normal), so that every gap, every contact point
  and every in-contact normal at the scene's pose are unchanged; checked with the core's
  Scene (a pin whose closest point would change, as growing it near a concave corner may
  do, is refused);
* :func:`turn`: the whole fixture frame turned by alpha about the origin (fixel
  positions, the pose's x, y; theta + alpha); the part's own frame, shape and com
  unchanged. A force direction phi becomes phi + alpha, a wrench (f, tz) becomes
  (R f, tz), a mode is unchanged;
* :func:`mirror`: the reflection x -> -x (fixel positions; the polygon's vertices
  (vx, vy) -> (-vx, vy) in reversed order, to stay counter-clockwise; the com (cx, cy) ->
  (-cx, cy); the pose (x, y, theta) -> (-x, y, -theta)). A direction phi becomes
  pi - phi, a wrench (fx, fy, tz) becomes (-fx, fy, -tz), and a mode has l and r
  swapped at every fixel (the tangent t = n turned by +90 degrees flips).

:func:`user_family` makes seeded tasks from the seating family, the arrival family, the
examples and two shapes of its own (a flat rectangular plate and a tall rectangle, each
on two pins against a stop), each with unequal pins (every pin's radius drawn in
[1.5, 5] mm), turned by a uniform angle and mirrored in half of them. Nothing is tuned:
the seed picks everything. Each task carries its target and a friction interval (the
scene's mu +- 0.1), for the planner, the engine and the closed loop.

Not a test module (pytest does not collect it); importable as ``user_fixtures`` once
``test/`` is on ``sys.path`` (``test/conftest.py``, ``benchmarks/harness``).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from wrenchcone_ros.core.geometry import SceneError
from wrenchcone_ros.core.scene_yaml import scene_from_dict

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = (("pawl_seating", (1, 2, 3)), ("disc_nest", (1, 2)), ("tbar_swing", (1, 2)))

#: m: the range each pin's radius is drawn from.
PIN_RADII = (0.0015, 0.005)

#: m: how far a transform may move a gap (the tests' bound; the transforms' rounding is
#: about 1e-17 m on the families' coordinates of 0.1 to 0.3 m).
GAP_TOLERANCE_M = 1e-12

#: The kinds of :func:`user_family`, in turn.
KINDS = ("seating", "disc", "plate", "pivot", "example", "tall", "bounce")


# --- the transforms ---------------------------------------------------------------------
def resize_pins(scene: dict, radii) -> dict:
    """``scene`` with pin i of radius ``radii[i]`` (m), its centre moved by
    (radii[i] - r_i) along the unit vector from the part's closest point to the pin's
    centre (module docstring): every gap and contact point unchanged.

    Raises
    ------
    ValueError
        A radius count that is not the fixel count, a pin whose centre lies on the part
        (no direction), or a new scene whose gaps or contact set differ from the
        original's by more than GAP_TOLERANCE_M (the closest point changed).
    """
    s = scene_from_dict(scene)
    radii = [float(r) for r in radii]
    if len(radii) != s.n_fixels:
        raise ValueError(f"{len(radii)} radii for {s.n_fixels} fixels")
    out = copy.deepcopy(scene)
    fixels = []
    for i, (fx, frame, r) in enumerate(zip(s.fixels, s.contacts, radii)):
        f = np.array(fx.position)
        d = f - np.asarray(frame.p, dtype=float)
        dist = math.hypot(*d)
        if dist == 0.0:
            raise ValueError(f"fixel {i + 1}: its centre lies on the part (no direction)")
        u = -np.asarray(frame.n, dtype=float) if frame.in_contact else d / dist
        new = f + (r - fx.radius) * u
        entry = copy.deepcopy(scene["fixels"][i])
        if not isinstance(entry, dict):
            entry = {"position": list(entry)}
        entry["position"] = [float(new[0]), float(new[1])]
        entry["radius"] = r
        fixels.append(entry)
    out["fixels"] = fixels
    try:
        t = scene_from_dict(out)
    except SceneError as exc:
        raise ValueError(f"resized pins {radii}: {exc}") from None
    gaps = np.abs(np.array(t.gaps) - np.array(s.gaps))
    if gaps.max() > GAP_TOLERANCE_M or t.in_contact != s.in_contact:
        raise ValueError(f"resized pins {radii}: a gap moved by {gaps.max():.3g} m (the "
                         "part's closest point to a pin changed)")
    return out


def _rot(alpha: float, v) -> list[float]:
    c, s = math.cos(alpha), math.sin(alpha)
    return [c * v[0] - s * v[1], s * v[0] + c * v[1]]


def turn(scene: dict, alpha: float) -> dict:
    """``scene`` with the fixture frame turned by ``alpha`` (rad) about its origin
    (module docstring)."""
    out = copy.deepcopy(scene)
    for f in out["fixels"]:
        f["position"] = _rot(alpha, f["position"])
    x, y, th = out["workpiece"]["pose"]
    out["workpiece"]["pose"] = _rot(alpha, (x, y)) + [th + alpha]
    return out


def mirror_mode(mode: str) -> str:
    """A mode of the mirrored scene: l and r swapped at every fixel."""
    return mode.translate(str.maketrans("lr", "rl"))


def mirror(scene: dict) -> dict:
    """``scene`` reflected x -> -x (module docstring)."""
    out = copy.deepcopy(scene)
    for f in out["fixels"]:
        f["position"] = [-f["position"][0], f["position"][1]]
    wp = out["workpiece"]
    shape = wp["shape"]
    if shape["type"] == "polygon":
        shape["vertices"] = [[-vx, vy] for vx, vy in reversed(shape["vertices"])]
    wp["com"] = [-wp["com"][0], wp["com"][1]]
    x, y, th = wp["pose"]
    wp["pose"] = [-x, y, -th]
    if out.get("modes"):
        modes = [out["modes"]] if isinstance(out["modes"], str) else out["modes"]
        out["modes"] = [mirror_mode(m) for m in modes]
    return out


def map_direction(phi: float, alpha: float, mirrored: bool) -> float:
    """A force direction of the original task in the transformed one (turn by alpha,
    then mirror), in (-pi, pi]."""
    phi = phi + alpha
    if mirrored:
        phi = math.pi - phi
    return math.remainder(phi, 2 * math.pi)


def map_wrench(g, alpha: float, mirrored: bool) -> np.ndarray:
    """A wrench (fx N, fy N, tz N m) of the original task in the transformed one."""
    f = _rot(alpha, (g[0], g[1]))
    if mirrored:
        return np.array([-f[0], f[1], -g[2]])
    return np.array([f[0], f[1], g[2]])


def map_mode(mode: str, mirrored: bool) -> str:
    """A mode of the original task in the transformed one."""
    return mirror_mode(mode) if mirrored else mode


def map_pose(pose, alpha: float, mirrored: bool) -> list[float]:
    """A pose (x, y, theta) of the original task in the transformed one."""
    x, y, th = pose
    p = _rot(alpha, (x, y)) + [th + alpha]
    return [-p[0], p[1], -p[2]] if mirrored else p


# --- two shapes of its own --------------------------------------------------------------
def rectangle_scene(width: float, height: float, pin2_x: float, pin3_x: float,
                    stop_y: float, offset: float, mu: float, mass: float = 0.05,
                    pin: float = 0.003) -> dict:
    """A uniform rectangle (``width`` x ``height`` m, its lower left corner at the
    workpiece frame's origin) lying on pins 2 and 3 under its bottom edge (y = 0.2 m)
    and slid ``offset`` m left of its seat against the stop, fixel 1, a pin touching its
    right edge at height ``stop_y`` (m, above the bottom) when seated at x = 0.1 m."""
    seat_x = 0.1
    y0 = 0.2
    return {"workpiece": {"mass": mass, "inertia": mass * (width ** 2 + height ** 2) / 12,
                          "com": [width / 2, height / 2],
                          "shape": {"type": "polygon",
                                    "vertices": [[0.0, 0.0], [width, 0.0], [width, height],
                                                 [0.0, height]]},
                          "pose": [seat_x - offset, y0, 0.0]},
            "friction": mu, "contact_tolerance": 1e-9,
            "fixels": [{"position": [seat_x + width + pin, y0 + stop_y], "radius": pin},
                       {"position": [pin2_x, y0 - pin], "radius": pin},
                       {"position": [pin3_x, y0 - pin], "radius": pin}]}


def _rectangle(rng, kind: str) -> tuple[dict, dict]:
    """A plate (60 to 100 mm wide, 12 to 25 mm high) or a tall part (15 to 25 mm wide,
    40 to 70 mm high), 2 mm to min(10 mm, w / 5) left of its seat; the pins under the
    bottom edge all along the slide, one on each side of the com; the stop's contact at
    20 to 50 % of the right edge's height."""
    if kind == "plate":
        w, h = float(rng.uniform(0.06, 0.1)), float(rng.uniform(0.012, 0.025))
    else:
        w, h = float(rng.uniform(0.015, 0.025)), float(rng.uniform(0.04, 0.07))
    offset = float(rng.uniform(0.002, min(0.01, 0.2 * w)))
    x0 = 0.1 - offset
    # both pins under the bottom edge at the start (x0 .. x0 + w) and at the seat (0.1 ..
    # 0.1 + w), at least 0.1 w from its ends; pin 2 left of the com at the start (x0 +
    # w / 2), pin 3 right of it at the seat (0.1 + w / 2), by 0.15 w
    p2 = float(rng.uniform(0.1 + 0.1 * w, x0 + 0.35 * w))
    p3 = float(rng.uniform(0.1 + 0.65 * w, x0 + 0.9 * w))
    stop_y = float(rng.uniform(0.2, 0.5)) * h
    mu = float(rng.uniform(0.2, 0.5))
    d = rectangle_scene(w, h, p2, p3, stop_y, offset, mu)
    return d, {"width": w, "height": h, "pin2_x": p2, "pin3_x": p3, "stop_y": stop_y,
               "offset": offset, "mu": mu}


# --- the family -------------------------------------------------------------------------
@dataclass(frozen=True)
class UserTask:
    """One task: its name and kind, the scene (the scene-file schema, transformed), the
    target fixels (1-based), the friction interval (every fixel), the base scene before
    the transforms and the transforms' parameters (``radii`` m, ``alpha`` rad,
    ``mirrored``) and the base's own parameters."""

    name: str
    kind: str
    scene: dict
    target: tuple[int, ...]
    friction: tuple[float, float]
    base: dict
    radii: tuple[float, ...]
    alpha: float
    mirrored: bool
    params: dict = field(default_factory=dict)

    @property
    def resized(self) -> dict:
        """The base scene with the task's pins, neither turned nor mirrored."""
        return resize_pins(self.base, self.radii)


def transform(base: dict, radii, alpha: float, mirrored: bool) -> dict:
    """``base`` resized (:func:`resize_pins`), turned, then mirrored when asked."""
    d = turn(resize_pins(base, radii), alpha)
    return mirror(d) if mirrored else d


def user_family(n: int, seed: int = 0) -> list[UserTask]:
    """``n`` seeded tasks, the kinds of KINDS in turn (module docstring): ``seating``
    (test/helpers/seating_family.py), ``disc``, ``pivot``, ``bounce``
    (test/helpers/arrival_family.py), ``example`` (examples/pawl_seating.yaml,
    disc_nest.yaml, tbar_swing.yaml in turn), ``plate`` and ``tall``
    (:func:`rectangle_scene`); each with pin radii drawn in PIN_RADII (redrawn, seeded,
    when growing a pin would change the part's closest point to it), a turn uniform in
    [-pi, pi) and a mirror with probability 1/2. Friction interval: the scene's mu
    +- 0.1 (at least 0)."""
    from helpers.arrival_family import arrival_family
    from helpers.seating_family import seating_family

    rng = np.random.default_rng((seed, 40))
    per = -(-n // len(KINDS)) + 1
    pools: dict[str, list] = {"seating": [(t.name, t.scene, (1, 2, 3), t.params)
                                          for t in seating_family(per, seed)]}
    for t in arrival_family(3 * per + 3, seed):
        pools.setdefault(t.kind, []).append((t.name, t.scene, t.target, t.params))
    pools["example"] = [(name, yaml.safe_load((ROOT / "examples" / f"{name}.yaml")
                                              .read_text()), target, {})
                        for name, target in EXAMPLES]
    used = dict.fromkeys(KINDS, 0)
    out: list[UserTask] = []
    for k in range(n):
        kind = KINDS[k % len(KINDS)]
        j = used[kind]
        used[kind] += 1
        if kind in ("plate", "tall"):
            base, params = _rectangle(rng, kind)
            base_name, target = f"{kind}_{seed}_{j}", (1, 2, 3)
        else:
            pool = pools[kind]
            base_name, base, target, params = pool[j % len(pool)]
        nf = len(base["fixels"])
        for _attempt in range(50):
            radii = tuple(float(r) for r in rng.uniform(*PIN_RADII, size=nf))
            try:
                resize_pins(base, radii)
                break
            except ValueError:
                continue
        else:  # pragma: no cover - never met by the families' shapes
            raise ValueError(f"{base_name}: no pin radii keep the gaps")
        alpha = float(rng.uniform(-math.pi, math.pi))
        mirrored = bool(rng.random() < 0.5)
        mu = float(base["friction"])
        out.append(UserTask(
            name=f"user_{seed}_{k}_{base_name}", kind=kind,
            scene=transform(base, radii, alpha, mirrored), target=tuple(target),
            friction=(round(max(0.0, mu - 0.1), 12), round(mu + 0.1, 12)), base=copy.deepcopy(base),
            radii=radii, alpha=alpha, mirrored=mirrored, params=dict(params)))
    return out
