# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The core's process-wide counters and caches, in one place, with one reset.

Counters (read them to see how often a float computation was redone exactly; see
docs/numerics.md):

* :data:`FALLBACKS` -- float cddlib conversions (:mod:`.cones`) and how many were redone
  in exact arithmetic;
* :data:`PLANAR_FALLBACKS` -- float cones of the planar method (:mod:`.planar`; also those
  the compiled kernel made) and the exact fallbacks among them;
* :data:`PAPER_FALLBACKS` -- the same for the paper's method (:mod:`.paper`);
* :data:`KERNEL_STATS` -- cones the compiled kernel made, and modes it declined (then the
  reference computed them).

Caches (pose independent: keyed by mode strings and contact state, bounded by clearing):

* :data:`PLANS` -- Table 2 of a mode as index arrays (:func:`.constraints.plan_for`);
* :data:`PLAN_CODES` -- the same as the kernel's int64 code (:func:`.engines.plan_code`);
* :data:`BATCH_PLANS` -- packed plans of a list of modes (:func:`.engines.batch_plan`);
* :data:`VERTEX_CODES` -- codes of a mode's copies at the vertices of a friction box
  (the robust "all" batch of :class:`.engines.KernelEngine`);
* :data:`ANY_CODES` -- codes of a mode in the robust "any" layout (the same engine).

These are every cache the engines keep (:mod:`.engines`). The algorithm modules bind
these same objects under their own names (``planar.PLANAR_FALLBACKS``,
``engine.KERNEL_STATS``, ...). :func:`reset` sets every
counter to zero and empties every cache, in place, so those names stay valid.
"""

from __future__ import annotations

FALLBACKS: dict[str, int] = {"float_calls": 0, "exact_fallbacks": 0}
PLANAR_FALLBACKS: dict[str, int] = {"float_cones": 0, "exact_fallbacks": 0,
                                    "exact_ill_conditioned": 0}
PAPER_FALLBACKS: dict[str, int] = {"float_cones": 0, "exact_fallbacks": 0,
                                   "exact_ill_conditioned": 0}
KERNEL_STATS: dict[str, int] = {"kernel_cones": 0, "declined": 0}

PLANS: dict[tuple, tuple] = {}
PLAN_CODES: dict[tuple, object] = {}
BATCH_PLANS: dict[tuple, object] = {}
VERTEX_CODES: dict[tuple, tuple] = {}
ANY_CODES: dict[tuple, object] = {}

#: Largest number of entries a cache holds before it is emptied (it refills on use).
PLAN_CACHE_LIMIT = 65536
BATCH_PLAN_CACHE_LIMIT = 4096

COUNTERS = (FALLBACKS, PLANAR_FALLBACKS, PAPER_FALLBACKS, KERNEL_STATS)
CACHES = (PLANS, PLAN_CODES, BATCH_PLANS, VERTEX_CODES, ANY_CODES)


def remember(cache: dict, key, value, limit: int = PLAN_CACHE_LIMIT):
    """Store ``value`` under ``key``, emptying ``cache`` first when it holds more than
    ``limit`` entries; returns ``value``.

    Parameters
    ----------
    cache : dict
        One of the caches of ``CACHES``.
    key : hashable
        The key.
    value : object
        The value.
    limit : int, optional
        The most entries before the cache is emptied.

    Returns
    -------
    object
        ``value``.
    """
    if len(cache) > limit:
        cache.clear()
    cache[key] = value
    return value


def counters() -> dict[str, dict[str, int]]:
    """A copy of every counter, by name.

    Returns
    -------
    dict
        Counter name -> {event: count}.
    """
    return {"FALLBACKS": dict(FALLBACKS), "PLANAR_FALLBACKS": dict(PLANAR_FALLBACKS),
            "PAPER_FALLBACKS": dict(PAPER_FALLBACKS), "KERNEL_STATS": dict(KERNEL_STATS)}


def reset(counters: bool = True, caches: bool = True) -> None:
    """Zero every counter and empty every cache (in place: the objects stay the same).

    Benchmarks call it between runs that must not share warm caches; tests call it to
    count from zero. Not thread-safe against concurrent cone computations.

    Parameters
    ----------
    counters : bool, optional
        Zero every counter.
    caches : bool, optional
        Empty every cache.
    """
    if counters:
        for d in COUNTERS:
            for k in d:
                d[k] = 0
    if caches:
        for c in CACHES:
            c.clear()
