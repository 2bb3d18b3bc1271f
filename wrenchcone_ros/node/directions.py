"""The ``~/force_directions`` service (srv/ForceDirections): which way to push.

A thin adapter over :func:`wrenchcone_ros.core.directions.force_directions`: the request
is validated, the answer computed from the ONE snapshot of the reply (its scene and its
mode classifier, whose cones the other services share) and cached in that snapshot per
(mode, point, exclusive), so repeated questions about the same inputs cost a dict lookup.
No maths here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from wrenchcone_ros import conversions  # noqa: F401 - makes wrenchcone_ros.srv importable
from wrenchcone_ros.core import ModeError, ModeSyntaxError, wrench_cone
from wrenchcone_ros.core.directions import DirectionInterval, force_directions
from wrenchcone_ros.node.services import ServiceSpec
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    INVALID_WRENCH,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    OK,
)
from wrenchcone_ros.node.store import CACHE_LIMIT, Snapshot, classifier
from wrenchcone_ros.srv import ForceDirections


@dataclass(frozen=True)
class DirectionsAnswer:
    """The outcome of one (snapshot, mode, point, exclusive)."""

    status: int
    message: str
    intervals: tuple[DirectionInterval, ...] = ()


def _point(req: ForceDirections.Request) -> tuple[float, float] | None:
    if req.at_com:
        return None
    x, y = float(req.point.x), float(req.point.y)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"point must be finite (m, workpiece frame), got ({x}, {y})")
    return (x, y)


def compute_directions(snap: Snapshot, mode: str, point: tuple[float, float] | None,
                       exclusive: bool) -> DirectionsAnswer:
    """The answer without caching. Never raises."""
    if snap.scene is None:
        return DirectionsAnswer(snap.status, snap.message)
    try:
        ivs = force_directions(snap.scene, mode, point=point, exclusive=exclusive,
                               classifier=classifier(snap))
    except ModeSyntaxError as exc:
        return DirectionsAnswer(INVALID_MODE, str(exc))
    except ModeError as exc:
        return DirectionsAnswer(MODE_NOT_ALLOWED, str(exc))
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return DirectionsAnswer(INTERNAL_ERROR, f"force_directions failed: "
                                                f"{type(exc).__name__}: {exc}")
    if not ivs:
        if not wrench_cone(snap.scene, mode).feasible:
            return DirectionsAnswer(MODE_INFEASIBLE, f"mode {mode!r} is infeasible: no "
                                                     "wrench at all realises it")
        return DirectionsAnswer(OK, "no force direction at this point is consistent with "
                                    f"mode {mode!r}" + (" alone" if exclusive else ""))
    return DirectionsAnswer(OK, "", tuple(ivs))


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
    ans = cached_directions(snap, req.mode, point, req.exclusive)
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


#: The service, registered with the others by the node (wrenchcone_node.py).
SPEC = ServiceSpec("force_directions", ForceDirections, handle, _failed)
