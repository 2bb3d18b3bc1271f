"""The ``~/force_directions`` service (srv/ForceDirections): which way to push.

A thin adapter over :func:`wrenchcone_ros.core.directions.force_directions`: the request
is validated and checked against the node's request limits (:func:`over_directions_limit`:
the mode's wildcards, and with ``exclusive`` every mode of the scene, count against
``max_concrete_modes``) before anything is computed; the answer is computed from the ONE
snapshot of the reply (its scene and its mode classifier, whose cones the other services
and the markers' force fans share) and cached in that snapshot per (mode, point,
exclusive), so repeated questions about the same inputs cost a dict lookup. Stale inputs
make the reply STALE_INPUTS with empty arrays (fail-safe, :func:`_stale`). No maths here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from wrenchcone_ros import conversions  # noqa: F401 - makes wrenchcone_ros.srv importable
from wrenchcone_ros.core import ModeError, ModeSyntaxError
from wrenchcone_ros.core.directions import DirectionInterval, force_directions
from wrenchcone_ros.core.modes import count_concrete_modes, expand_mode
from wrenchcone_ros.node.services import ServiceSpec
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    INVALID_WRENCH,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    OK,
)
from wrenchcone_ros.node.store import CACHE_LIMIT, Limits, Snapshot, classifier, over_limit
from wrenchcone_ros.srv import ForceDirections


@dataclass(frozen=True)
class DirectionsAnswer:
    """The outcome of one (snapshot, mode, point, exclusive)."""

    status: int
    message: str
    intervals: tuple[DirectionInterval, ...] = ()


def _point(req: ForceDirections.Request) -> tuple[float, float] | None:
    if not req.use_point:
        return None  # the default: a force at the centre of mass
    x, y = float(req.point.x), float(req.point.y)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"point must be finite (m, workpiece frame), got ({x}, {y})")
    return (x, y)


def compute_directions(snap: Snapshot, mode: str, point: tuple[float, float] | None,
                       exclusive: bool) -> DirectionsAnswer:
    """The answer without caching. Never raises. The mode's cones come from the
    snapshot's classifier (computed at most once per snapshot, shared with the other
    services and the markers)."""
    if snap.scene is None:
        return DirectionsAnswer(snap.status, snap.message)
    scene, clf = snap.scene, classifier(snap)
    try:
        concrete = expand_mode(mode, scene.in_contact, scene.gaps,
                               scene.effective_contact_tolerance)
        if not any(clf.cone(m).feasible for m in concrete):
            return DirectionsAnswer(MODE_INFEASIBLE, f"mode {mode!r} is infeasible: no "
                                                     "wrench at all realises it")
        ivs = force_directions(scene, mode, point=point, exclusive=exclusive,
                               classifier=clf)
    except ModeSyntaxError as exc:
        return DirectionsAnswer(INVALID_MODE, str(exc))
    except ModeError as exc:
        return DirectionsAnswer(MODE_NOT_ALLOWED, str(exc))
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return DirectionsAnswer(INTERNAL_ERROR, f"force_directions failed: "
                                                f"{type(exc).__name__}: {exc}")
    if not ivs:
        return DirectionsAnswer(OK, "no force direction at this point is consistent with "
                                    f"mode {mode!r}" + (" alone" if exclusive else ""))
    return DirectionsAnswer(OK, "", tuple(ivs))


def over_directions_limit(snap: Snapshot, mode: str, exclusive: bool,
                          limits: Limits) -> DirectionsAnswer | None:
    """LIMIT_EXCEEDED before any computation, else None. The mode itself as for the other
    services (:func:`~wrenchcone_ros.node.store.over_limit`: max_mode_length, and
    max_concrete_modes for its wildcards); ``exclusive`` compares the mode with every
    valid mode of the scene, the expansion of ``*...*``, so that count is held to
    max_concrete_modes too (the same budget: the same enumeration as a wildcard)."""
    ans = over_limit(snap, mode, limits)
    if ans is not None:
        return DirectionsAnswer(ans.status, ans.message)
    if exclusive and snap.scene is not None:
        scene = snap.scene
        n = count_concrete_modes("*" * scene.n_fixels, scene.in_contact)
        if n > limits.max_concrete_modes:
            return DirectionsAnswer(
                LIMIT_EXCEEDED,
                f"exclusive compares the mode with all {n} modes of the scene, more than "
                f"max_concrete_modes ({limits.max_concrete_modes}); ask without exclusive "
                "or raise the parameter")
    return None


def cached_directions(snap: Snapshot, mode: str, point: tuple[float, float] | None,
                      exclusive: bool) -> DirectionsAnswer:
    """Cached per (snapshot, mode, point, exclusive), in the snapshot's answer cache."""
    key = ("force_directions", mode, point, bool(exclusive))
    ans = snap.answers.get(key)
    if ans is None:
        ans = compute_directions(snap, mode, point, exclusive)
        if len(snap.answers) < CACHE_LIMIT:
            snap.answers[key] = ans
    return ans


def handle(node: Any, snap: Snapshot, req: ForceDirections.Request,
           resp: ForceDirections.Response) -> ForceDirections.Response:
    try:
        point = _point(req)
    except ValueError as exc:
        resp.status, resp.message = INVALID_WRENCH, str(exc)
        return resp
    ans = (over_directions_limit(snap, req.mode, req.exclusive, node.limits)
           or cached_directions(snap, req.mode, point, req.exclusive))
    if ans.status == INTERNAL_ERROR:
        node.get_logger().error(f"force_directions {req.mode!r}: {ans.message}")
    resp.status, resp.message = ans.status, ans.message
    resp.lo = [iv.lo for iv in ans.intervals]
    resp.hi = [iv.hi for iv in ans.intervals]
    resp.best = [iv.best for iv in ans.intervals]
    resp.margin = [iv.margin for iv in ans.intervals]
    return resp


def _failed(resp: ForceDirections.Response) -> None:
    resp.lo, resp.hi, resp.best, resp.margin = [], [], [], []


def _stale(resp: ForceDirections.Response) -> None:
    """Fail-safe: no direction is offered from stale inputs (the message keeps how many
    intervals they would give)."""
    if resp.lo:
        resp.message += f" ({len(resp.lo)} interval(s) from the stale inputs)"
    _failed(resp)


def monitored_directions(snap: Snapshot, mode: str) -> tuple[DirectionInterval, ...]:
    """The force directions at the com for a monitored mode (the markers' fans), from the
    same per-snapshot cache and classifier as the service."""
    return cached_directions(snap, mode, None, False).intervals


#: The service, registered with the others by the node (wrenchcone_node.py).
SPEC = ServiceSpec("force_directions", ForceDirections, handle, _failed, _stale, slow=True)
