# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Scalar arithmetic for the two number types of the core: float and exact Fraction.

The geometry and the algorithm are written once and run in either arithmetic. Exact
inputs are taken *as written*: a float such as 0.2 becomes Fraction(1, 5) (the shortest
decimal that round-trips, :func:`to_exact`), not the binary double nearest to 0.2.
Square roots and cos/sin are exact where the result is rational (perfect squares,
theta = 0) and otherwise rounded once to the nearest double, then carried exactly;
the cone does not depend on the length of n_i and t_i, so this only moves contact
points by about 1e-16 relative (documented in docs/numerics.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from numbers import Rational, Real
from typing import Callable
from collections.abc import Sequence

from .tolerances import WRENCH_RESCALE_ABOVE

Scalar = float | Fraction


def to_exact(x: Real) -> Fraction:
    """The rational number a user wrote: ints and Fractions as they are, floats via repr.

    Parameters
    ----------
    x : numbers.Real
        An int, a Fraction or a float.

    Returns
    -------
    fractions.Fraction
        ``x`` as written: ``to_exact(0.2) == Fraction(1, 5)``.

    Raises
    ------
    ValueError
        ``x`` is infinite or NaN.
    """
    if isinstance(x, Rational):
        return Fraction(x)
    f = float(x)
    if not math.isfinite(f):
        raise ValueError(f"{x!r} is not a finite number")
    return Fraction(repr(f))


def exact_sqrt(x: Fraction) -> Fraction:
    """sqrt(x), exact when numerator and denominator are perfect squares, else rounded.

    Parameters
    ----------
    x : fractions.Fraction
        A number >= 0.

    Returns
    -------
    fractions.Fraction
        sqrt(x), exact or rounded once to the nearest double.

    Raises
    ------
    ValueError
        ``x`` is negative.
    """
    if x < 0:
        raise ValueError(f"square root of negative number {x}")
    p, q = x.numerator, x.denominator
    rp, rq = math.isqrt(p), math.isqrt(q)
    if rp * rp == p and rq * rq == q:
        return Fraction(rp, rq)
    return Fraction(math.sqrt(float(x)))


def exact_cos_sin(theta: Fraction) -> tuple[Fraction, Fraction]:
    """cos and sin of theta (rad): exact for theta = 0, otherwise rounded once.

    Parameters
    ----------
    theta : fractions.Fraction
        An angle (rad).

    Returns
    -------
    tuple of fractions.Fraction
        (cos theta, sin theta).
    """
    if theta == 0:
        return Fraction(1), Fraction(0)
    t = float(theta)
    return Fraction(math.cos(t)), Fraction(math.sin(t))


@dataclass(frozen=True)
class Arithmetic:
    """The operations that differ between float and exact evaluation.

    Parameters
    ----------
    exact : bool
        True for exact (Fraction) arithmetic.
    convert : callable
        A real number as a scalar of this arithmetic.
    sqrt : callable
        The square root.
    cos_sin : callable
        cos and sin of an angle (rad).
    """

    exact: bool
    convert: Callable[[Real], Scalar]
    sqrt: Callable[[Scalar], Scalar]
    cos_sin: Callable[[Scalar], tuple[Scalar, Scalar]]


FLOAT = Arithmetic(False, float, math.sqrt, lambda t: (math.cos(t), math.sin(t)))
EXACT = Arithmetic(True, to_exact, exact_sqrt, exact_cos_sin)


def arithmetic(exact: bool) -> Arithmetic:
    """FLOAT or EXACT.

    Parameters
    ----------
    exact : bool
        Exact arithmetic instead of floats.

    Returns
    -------
    Arithmetic
        :data:`EXACT` when ``exact``, else :data:`FLOAT`.
    """
    return EXACT if exact else FLOAT


def rescale_wrench(values: Sequence[float]) -> tuple[float, ...]:
    """The wrench components ``values`` (N, N m; finite) multiplied by one exact power of
    two when their largest magnitude is above WRENCH_RESCALE_ABOVE or, nonzero, below its
    inverse (the largest then lies in [0.5, 1)); otherwise unchanged.

    Whether a wrench is consistent with a mode, and its margin, depend only on its
    direction (the set of consistent wrenches is a cone), so the rescaled wrench gives
    the same answers while its squares stay finite. Any number of components (3: planar
    (fx, fy, tz); 6: a full wrench) and the same power of two for all of them.

    Parameters
    ----------
    values : sequence of float
        The wrench components (N, N m), finite.

    Returns
    -------
    tuple of float
        The components, all multiplied by the same power of two (or unchanged).
    """
    out = tuple(float(v) for v in values)
    big = max((abs(v) for v in out), default=0.0)
    if big > WRENCH_RESCALE_ABOVE or 0.0 < big < 1.0 / WRENCH_RESCALE_ABOVE:
        k = -math.frexp(big)[1]
        out = tuple(math.ldexp(v, k) for v in out)
    return out
