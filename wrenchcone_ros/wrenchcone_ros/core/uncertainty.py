# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""What is not known exactly about a scene: the uncertainty model of robust answers.

An :class:`Uncertainty` describes a *set of models* around a nominal scene:

* ``friction``: an interval [mu_lo, mu_hi] for every fixel (one pair), or one pair (or
  None: the scene's value) per fixel. Each fixel's mu varies independently in its own
  interval. Zero-width intervals are allowed (a pair (mu, mu) replaces the scene's mu).
* ``mass`` (kg) and ``inertia`` (kg m^2, about the centre of mass): intervals.
* ``com_radius`` (m): the centre of mass lies in a disc of that radius around the
  nominal one (workpiece frame); or ``com_box`` (m): half-widths (hx, hy) of a box
  around it. At most one of the two.
* ``normal_error`` (rad): each fixel's contact normal (and tangent) may be turned by any
  angle in [-delta, delta] (pose and shape errors, burrs, pin wear): one delta for every
  fixel or one per fixel.

Friction intervals are handled exactly (docs/theory.md, "Uncertain models"). The other
parameters are handled by the scenario approach: ``epsilon`` (violation probability) and
``beta`` (confidence parameter) fix the number of sampled models :meth:`scenario_size`;
models are drawn by :meth:`Uncertainty.sample` from the distribution stated there, with
the reproducible ``seed``. Every robust answer says which guarantee it carries.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .scene import Scene
from .scene_yaml import check_keys, read_yaml
from .tolerances import MAX_FRICTION

Interval = tuple[float, float]


class UncertaintyError(ValueError):
    """An invalid uncertainty model: says what was wrong and what is allowed."""


def _number(x: Any, what: str) -> float:
    if isinstance(x, bool):
        raise UncertaintyError(f"{what} must be a number, got {x!r}")
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise UncertaintyError(f"{what} must be a number, got {x!r}") from None
    if not math.isfinite(v):
        raise UncertaintyError(f"{what} must be finite, got {x!r}")
    return v


def _interval(pair: Any, what: str, low: float = 0.0, high: float = math.inf,
              positive: bool = False) -> Interval:
    """A pair (lo, hi) with low <= lo <= hi <= high (lo > 0 when ``positive``)."""
    if isinstance(pair, (str, bytes, Mapping)) or not isinstance(pair, Sequence) \
            or len(pair) != 2:
        raise UncertaintyError(f"{what} must be an interval [lo, hi], got {pair!r}")
    lo, hi = _number(pair[0], f"{what} lo"), _number(pair[1], f"{what} hi")
    if lo > hi:
        raise UncertaintyError(f"{what}: lo must be <= hi, got [{lo!r}, {hi!r}]")
    if lo < low or (positive and lo <= 0):
        bound = "> 0" if positive else f">= {low:g}"
        raise UncertaintyError(f"{what}: lo must be {bound}, got {lo!r}")
    if hi > high:
        raise UncertaintyError(f"{what}: hi must be <= {high:g}, got {hi!r}")
    return (lo, hi)


def _friction(value: Any) -> Interval | tuple[Interval | None, ...] | None:
    if value is None:
        return None
    what = "friction interval"
    if isinstance(value, Sequence) and len(value) == 2 and not any(
            isinstance(v, Sequence) or v is None for v in value):
        return _interval(value, what, 0.0, MAX_FRICTION)
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence) \
            or not value:
        raise UncertaintyError(
            f"friction must be an interval [lo, hi] or a list with one interval (or null) "
            f"per fixel, got {value!r}")
    return tuple(None if v is None else _interval(v, f"{what} of fixel {k + 1}", 0.0,
                                                   MAX_FRICTION)
                 for k, v in enumerate(value))


def _angles(value: Any) -> float | tuple[float, ...] | None:
    if value is None:
        return None
    if isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        return tuple(_angle(v, f"normal_error of fixel {k + 1}") for k, v in enumerate(value))
    return _angle(value, "normal_error")


def _angle(x: Any, what: str) -> float:
    v = _number(x, what)
    if not 0 <= v < math.pi / 2:
        raise UncertaintyError(f"{what} must be in [0, pi/2) rad, got {x!r}")
    return v


def _binomial_tail(n: int, d: int, eps: float) -> float:
    """sum_{i=0}^{d-1} C(n, i) eps^i (1 - eps)^(n - i), in logarithms (no underflow)."""
    total = 0.0
    for i in range(d):
        total += math.exp(math.lgamma(n + 1) - math.lgamma(i + 1) - math.lgamma(n - i + 1)
                          + i * math.log(eps) + (n - i) * math.log1p(-eps))
    return total


@dataclass(frozen=True)
class Model:
    """One model of the set: per-fixel friction (None: the friction box is handled
    exactly), mass (kg), inertia (kg m^2), com (workpiece frame, m), normal turns (rad).

    Parameters
    ----------
    friction : tuple of float or None
        mu of every fixel; None: the friction box is handled exactly.
    mass : float
        kg.
    inertia : float
        kg m^2, about the centre of mass.
    com : tuple of 2 float
        The centre of mass (m, workpiece frame).
    normal_error : tuple of float
        The turn of every fixel's contact normal (rad).
    """

    friction: tuple[float, ...] | None
    mass: float
    inertia: float
    com: tuple[float, float]
    normal_error: tuple[float, ...]


@dataclass(frozen=True)
class Uncertainty:
    """A set of models around a nominal scene (SI units, radians).

    Parameters
    ----------
    friction : (lo, hi), tuple of (lo, hi) or None, or None
        An interval of mu for every fixel, or one per fixel (None: the scene's value);
        each fixel's mu varies independently. Handled exactly.
    mass : (lo, hi) or None
        kg.
    inertia : (lo, hi) or None
        kg m^2, about the centre of mass.
    com_radius : float or None
        m: the com lies in a disc of this radius around the nominal one.
    com_box : (hx, hy) or None
        m: half-widths of a box around the nominal com (not with ``com_radius``).
    normal_error : float, tuple of float or None
        rad: each contact normal may turn by up to this angle (one for every fixel or
        one per fixel).
    epsilon, beta : float, optional
        In (0, 1): the scenario approach's violation probability and confidence
        parameter, which fix the number of sampled models (:meth:`scenario_size`) for
        every parameter but friction.
    seed : int, optional
        Seed of the sampled models.

    Raises
    ------
    UncertaintyError
        An invalid interval (not two finite numbers lo <= hi; negative friction, a
        mass or inertia not positive), both com regions, a negative radius or
        half-width, a normal error outside [0, pi/2) rad, epsilon or beta outside
        (0, 1), or a seed that is not an integer; the message says what is allowed.
    """

    friction: Interval | tuple[Interval | None, ...] | None = None
    mass: Interval | None = None
    inertia: Interval | None = None
    com_radius: float | None = None
    com_box: tuple[float, float] | None = None
    normal_error: float | tuple[float, ...] | None = None
    epsilon: float = 0.05
    beta: float = 1e-3
    seed: int = 0

    def __post_init__(self) -> None:
        setattr_ = object.__setattr__
        setattr_(self, "friction", _friction(self.friction))
        if self.mass is not None:
            setattr_(self, "mass", _interval(self.mass, "mass interval (kg)", positive=True))
        if self.inertia is not None:
            setattr_(self, "inertia", _interval(self.inertia, "inertia interval (kg m^2)",
                                                positive=True))
        if self.com_radius is not None and self.com_box is not None:
            raise UncertaintyError("give the com region as com_radius (a disc) or com_box "
                                   "(a box), not both")
        if self.com_radius is not None:
            r = _number(self.com_radius, "com_radius (m)")
            if r < 0:
                raise UncertaintyError(f"com_radius must be >= 0 m, got {self.com_radius!r}")
            setattr_(self, "com_radius", r)
        if self.com_box is not None:
            b = self.com_box
            if isinstance(b, (str, bytes)) or not isinstance(b, Sequence) or len(b) != 2:
                raise UncertaintyError(f"com_box must be half-widths [hx, hy] in m, got {b!r}")
            hx, hy = _number(b[0], "com_box hx (m)"), _number(b[1], "com_box hy (m)")
            if hx < 0 or hy < 0:
                raise UncertaintyError(f"com_box half-widths must be >= 0 m, got {list(b)}")
            setattr_(self, "com_box", (hx, hy))
        setattr_(self, "normal_error", _angles(self.normal_error))
        eps, beta = _number(self.epsilon, "epsilon"), _number(self.beta, "beta")
        if not 0 < eps < 1 or not 0 < beta < 1:
            raise UncertaintyError(f"epsilon and beta must be in (0, 1), got {eps!r}, {beta!r}")
        setattr_(self, "epsilon", eps)
        setattr_(self, "beta", beta)
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)):
            raise UncertaintyError(f"seed must be an integer, got {self.seed!r}")

    # --- per scene ------------------------------------------------------------------
    def friction_intervals(self, scene: Scene) -> list[Interval]:
        """[mu_lo, mu_hi] of every fixel of ``scene`` (the scene's mu where not given).

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        list of (float, float)
            One interval per fixel.

        Raises
        ------
        UncertaintyError
            The uncertainty gives a number of intervals other than the scene's fixels.
        """
        n = scene.n_fixels
        f = self.friction
        if f is None:
            return [(scene.mu(i), scene.mu(i)) for i in range(n)]
        if isinstance(f[0], (int, float)):
            return [f] * n
        if len(f) != n:
            raise UncertaintyError(f"friction has {len(f)} interval(s) but the scene has "
                                   f"{n} fixel(s); give one interval (or null) per fixel")
        return [(scene.mu(i), scene.mu(i)) if iv is None else iv for i, iv in enumerate(f)]

    def normal_errors(self, scene: Scene) -> tuple[float, ...]:
        """delta (rad) of every fixel of ``scene``.

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        tuple of float
            One angle per fixel (rad).

        Raises
        ------
        UncertaintyError
            The uncertainty gives a number of angles other than the scene's fixels.
        """
        d, n = self.normal_error, scene.n_fixels
        if d is None:
            return (0.0,) * n
        if isinstance(d, float):
            return (d,) * n
        if len(d) != n:
            raise UncertaintyError(f"normal_error has {len(d)} value(s) but the scene has "
                                   f"{n} fixel(s); give one delta or one per fixel")
        return d

    def mass_interval(self, scene: Scene) -> Interval:
        """The mass interval (kg): the scene's mass where none is given.

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        (float, float)
            [m_lo, m_hi].
        """
        m = scene.workpiece.mass
        return (m, m) if self.mass is None else self.mass

    def inertia_interval(self, scene: Scene) -> Interval:
        """The inertia interval (kg m^2): the scene's inertia where none is given.

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        (float, float)
            [I_lo, I_hi].
        """
        i = scene.workpiece.inertia
        return (i, i) if self.inertia is None else self.inertia

    def is_nominal(self, scene: Scene) -> bool:
        """Whether this is the zero-width uncertainty of ``scene``: every parameter at
        its nominal value (no friction interval wider than a point, each at the scene's
        mu; no mass, inertia, com or normal variation), so that every robust set is the
        nominal cone.

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        bool
        """
        if (self.friction is None and self.mass is None and self.inertia is None
                and self.com_radius is None and self.com_box is None
                and self.normal_error is None):
            return True  # nothing given (NOMINAL): the scene's own values, at no cost
        intervals = self.friction_intervals(scene)
        return at_scene_friction(scene, intervals) and not self.nonlinear(scene)

    def nonlinear(self, scene: Scene) -> bool:
        """Whether a parameter other than friction varies (then: the scenario approach).

        Parameters
        ----------
        scene : Scene
            The nominal scene.

        Returns
        -------
        bool
            True when mass, inertia, com or a contact normal varies.
        """
        m, i = self.mass_interval(scene), self.inertia_interval(scene)
        return (m[0] < m[1] or i[0] < i[1] or bool(self.com_radius)
                or (self.com_box is not None and any(self.com_box))
                or any(d > 0 for d in self.normal_errors(scene)))

    def scenario_size(self, d: int = 3) -> int:
        """The number N of sampled models: the smallest N with
        sum_{i<d} C(N, i) eps^i (1 - eps)^(N - i) <= beta (Campi and Garatti's bound for a
        convex scenario programme with d decision variables; d = 3 for a wrench, d = 1
        gives N >= ln beta / ln(1 - eps), the bound for one wrench chosen independently
        of the draw). docs/theory.md, "Uncertain models".

        Parameters
        ----------
        d : int, optional
            The number of decision variables.

        Returns
        -------
        int
            N.

        Raises
        ------
        UncertaintyError
            ``d`` is not a positive integer.
        """
        if isinstance(d, bool) or not isinstance(d, int) or d < 1:
            raise UncertaintyError(f"d must be a positive integer, got {d!r}")
        eps, beta = self.epsilon, self.beta
        n = max(d, int(math.ceil(math.log(beta) / math.log1p(-eps))))
        while _binomial_tail(n, d, eps) > beta:
            n += 1
        return n

    def sample(self, scene: Scene, count: int, seed: int | None = None,
               friction: bool = False) -> list[Model]:
        """``count`` models drawn independently: mass, inertia, every fixel's normal turn
        and (with ``friction=True``) every fixel's mu uniform in their intervals, the com
        uniform in its disc or box (nominal values where nothing is uncertain).
        ``seed`` (default: the model's seed) makes the draw reproducible.

        Parameters
        ----------
        scene : Scene
            The nominal scene.
        count : int
            The number of models.
        seed : int or None, optional
            The seed of the draw; None: the uncertainty's ``seed``.
        friction : bool, optional
            Draw every fixel's mu too (else the models' friction is None).

        Returns
        -------
        list of Model
            ``count`` models.
        """
        rng = np.random.default_rng(self.seed if seed is None else seed)
        n = scene.n_fixels
        (m0, m1), (i0, i1) = self.mass_interval(scene), self.inertia_interval(scene)
        delta = np.array(self.normal_errors(scene))
        mu = np.array(self.friction_intervals(scene), dtype=float).reshape(n, 2)
        cx, cy = scene.workpiece.com
        out = []
        for _ in range(count):
            m = rng.uniform(m0, m1) if m1 > m0 else m0
            inertia = rng.uniform(i0, i1) if i1 > i0 else i0
            if self.com_radius:
                r = self.com_radius * math.sqrt(rng.uniform())
                a = rng.uniform(-math.pi, math.pi)
                com = (cx + r * math.cos(a), cy + r * math.sin(a))
            elif self.com_box is not None:
                com = (cx + rng.uniform(-1, 1) * self.com_box[0],
                       cy + rng.uniform(-1, 1) * self.com_box[1])
            else:
                com = (cx, cy)
            turns = tuple((rng.uniform(-1, 1, n) * delta).tolist())
            fr = tuple(rng.uniform(mu[:, 0], mu[:, 1]).tolist()) if friction else None
            out.append(Model(fr, float(m), float(inertia), com, turns))
        return out

    def describe(self) -> str:
        """A one-line summary for tables and topics.

        Returns
        -------
        str
            The parameters that vary, with their intervals; ``none`` for the nominal model.
        """
        parts = []
        if self.friction is not None:
            parts.append(f"friction {list(self.friction)}")
        for name in ("mass", "inertia", "com_radius", "com_box", "normal_error"):
            v = getattr(self, name)
            if v is not None:
                parts.append(f"{name} {list(v) if isinstance(v, tuple) else v}")
        return ", ".join(parts) if parts else "none"

    def to_dict(self) -> dict:
        """The YAML/dict form accepted by :func:`uncertainty_from_dict`.

        Returns
        -------
        dict
            The given parameters, ``epsilon``, ``beta`` and ``seed``.
        """
        out: dict = {}
        f = self.friction
        if f is not None:
            out["friction"] = list(f) if isinstance(f[0], float) else [
                None if iv is None else list(iv) for iv in f]
        for name in ("mass", "inertia", "com_box"):
            if getattr(self, name) is not None:
                out[name] = list(getattr(self, name))
        if self.com_radius is not None:
            out["com_radius"] = self.com_radius
        if self.normal_error is not None:
            d = self.normal_error
            out["normal_error"] = list(d) if isinstance(d, tuple) else d
        out.update(epsilon=self.epsilon, beta=self.beta, seed=int(self.seed))
        return out


_KEYS = {"friction", "mass", "inertia", "com_radius", "com_box", "normal_error", "epsilon",
         "beta", "seed"}


def uncertainty_from_dict(d: Any) -> Uncertainty:
    """An :class:`Uncertainty` from the YAML schema (the keys of :meth:`Uncertainty.to_dict`).

    Parameters
    ----------
    d : Mapping
        The ``uncertainty`` mapping of a file.

    Returns
    -------
    Uncertainty
        The model set.

    Raises
    ------
    UncertaintyError
        ``d`` is not a mapping, has an unknown key or an invalid value.
    """
    check_keys(d, _KEYS, "uncertainty", UncertaintyError)
    return Uncertainty(**{k: d[k] for k in d})


def load_uncertainty(source: str | Path | Mapping) -> Uncertainty | None:
    """The uncertainty of a YAML file or mapping.

    Parameters
    ----------
    source : str, Path, Mapping or Uncertainty
        A YAML file whose top-level ``uncertainty:`` mapping is read (a scene file may
        carry one) or, without scene keys, the whole file; a mapping of the same schema;
        an Uncertainty (returned as is).

    Returns
    -------
    Uncertainty or None
        None when a scene file has no ``uncertainty`` key.

    Raises
    ------
    UncertaintyError
        The file cannot be read or parsed, or a key or value is invalid (the message says
        what was wrong and what is allowed).
    """
    if isinstance(source, Uncertainty):
        return source
    if isinstance(source, Mapping):
        data = source
    else:
        data = read_yaml(source, UncertaintyError)
    if isinstance(data, Mapping) and "workpiece" in data:
        data = data.get("uncertainty")
        if data is None:
            return None
    elif isinstance(data, Mapping) and "uncertainty" in data:
        data = data["uncertainty"]
    return uncertainty_from_dict(data)


def at_scene_friction(scene: Scene, intervals: Sequence[Interval]) -> bool:
    """Whether every friction interval is the single value the scene has.

    Parameters
    ----------
    scene : Scene
        The nominal scene (its mu per fixel).
    intervals : sequence of (float, float)
        [mu_lo, mu_hi] per fixel (:meth:`Uncertainty.friction_intervals`).

    Returns
    -------
    bool
    """
    return all(lo == hi == scene.mu(i) for i, (lo, hi) in enumerate(intervals))


#: The zero-width uncertainty: the nominal model alone (every parameter as the scene has
#: it). A nominal answer is the robust answer for this uncertainty.
NOMINAL = Uncertainty()


def as_uncertainty(uncertainty: Any = None, scene: Scene | None = None) -> Uncertainty:
    """The uncertainty an entry point works with, from what its caller gave: None (no
    uncertainty given) is :data:`NOMINAL`, an :class:`Uncertainty` is itself, a friction
    interval (lo, hi) for every fixel or one (or None) per fixel is
    ``Uncertainty(friction=...)``. The one normaliser of the package: entry points take
    whatever it takes and pass an Uncertainty on.

    Parameters
    ----------
    uncertainty : Uncertainty, sequence or None, optional
        The model set given.
    scene : Scene or None, optional
        When given, the uncertainty is checked against it: as many friction intervals
        and normal errors as the scene has fixels.

    Returns
    -------
    Uncertainty

    Raises
    ------
    UncertaintyError
        An invalid friction interval, or (with ``scene``) a number of intervals or normal
        errors other than the scene's number of fixels.
    TypeError
        ``uncertainty`` is none of the above (a number, a mapping, a string, ...).
    """
    if uncertainty is None:
        return NOMINAL
    if not isinstance(uncertainty, Uncertainty):
        if isinstance(uncertainty, (str, bytes, Mapping)) or not isinstance(
                uncertainty, Sequence):
            raise TypeError(f"uncertainty must be an Uncertainty, None, or a friction "
                            f"interval (lo, hi) (or one per fixel), got "
                            f"{type(uncertainty).__name__}")
        uncertainty = Uncertainty(friction=tuple(uncertainty))
    if scene is not None:
        uncertainty.friction_intervals(scene)
        uncertainty.normal_errors(scene)
    return uncertainty


def nominal_model(scene: Scene) -> Model:
    """The scene's own model: its mu at every fixel, its mass, inertia and centre of mass,
    no normal turn. The one nominal model (what the simulation runs as "nominal" and
    every model of :data:`NOMINAL` is). Its friction is the scene's mu, not None: a
    :class:`Model` with friction None stands for the whole friction box, handled
    exactly, which is the nominal friction only when no interval is given.

    Parameters
    ----------
    scene : Scene
        The nominal scene.

    Returns
    -------
    Model
        The scene's model.
    """
    wp = scene.workpiece
    return Model(tuple(scene.mu(i) for i in range(scene.n_fixels)), wp.mass, wp.inertia,
                 tuple(wp.com), (0.0,) * scene.n_fixels)


__all__ = ["Uncertainty", "UncertaintyError", "Model", "NOMINAL", "as_uncertainty",
           "nominal_model",
           "at_scene_friction",
           "uncertainty_from_dict", "load_uncertainty"]
