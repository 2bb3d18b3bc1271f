"""Service handlers: one snapshot in, one stamped reply out, never an exception.

Every service is a :class:`ServiceSpec` in :data:`SERVICES`; :func:`register_services`
creates each in its lane (``slow=True``: the slow lane of executors.py, whose thread
keeps a long classification from holding up a check_wrench; else the node's fast lane)
and wraps its handler in :func:`_serve`, which takes ONE snapshot for the whole reply (the
newest inputs, built now if they changed), stamps the reply (:func:`stamp_response`:
frame, input stamps, inputs version, inputs age) and turns any unexpected exception into
INTERNAL_ERROR with one log line. Then, if the inputs are older than their timeout, an OK
or MODE_INFEASIBLE reply becomes STALE_INPUTS (the message says how old and what the old
inputs give; ``on_stale`` makes the reply fail-safe). A handler only fills the answer:
``handler(node, snap, req, resp) -> resp``. To add a service: write its handler here (or
in its own module) and add a ServiceSpec.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rclpy.callback_groups import CallbackGroup, ReentrantCallbackGroup

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.conversions import CheckWrench, ClassifyWrench, GetCone
from wrenchcone_ros.node import fastcheck
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    INVALID_WRENCH,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    OK,
    STALE_INPUTS,
    STATUS_NAMES,
)
from wrenchcone_ros.core.budget import TimeBudgetExceeded, time_budget
from wrenchcone_ros.core.classify import SearchBudgetError
from wrenchcone_ros.node.store import Freshness, Snapshot, classifier

Handler = Callable[[Any, Snapshot, Any, Any], Any]


@dataclass(frozen=True)
class ServiceSpec:
    """One service of the node: ``~/<name>`` of type ``srv_type`` answered by ``handler``."""

    name: str
    srv_type: Any
    handler: Handler
    #: Puts a reply into its "no answer" state before INTERNAL_ERROR is reported.
    on_failure: Callable[[Any], None] = lambda resp: None
    #: Makes a reply computed from stale inputs fail-safe (e.g. consistent = False).
    on_stale: Callable[[Any], None] = lambda resp: None
    #: Served in the slow lane (its work can be long even within the limits).
    slow: bool = False
    #: Served by the compiled lane (fastcheck.py): it answers what it can from the
    #: monitored cones and forwards the rest to this handler, in its own thread.
    compiled: bool = False


def stamp_response(resp: Any, snap: Snapshot, freshness: Freshness | None = None) -> None:
    """Say which inputs the reply was computed from (every service reply carries these)."""
    resp.frame_id = snap.frame_id
    resp.inputs_version = snap.version
    if snap.pose_stamp is not None:
        resp.pose_stamp.sec, resp.pose_stamp.nanosec = snap.pose_stamp
    if snap.fixels_stamp is not None:
        resp.fixels_stamp.sec, resp.fixels_stamp.nanosec = snap.fixels_stamp
    if freshness is not None and hasattr(resp, "inputs_age"):
        resp.inputs_age = float(freshness.age_s)


def mark_stale(spec: ServiceSpec, resp: Any, freshness: Freshness) -> None:
    """An OK / MODE_INFEASIBLE reply from stale inputs becomes STALE_INPUTS."""
    if freshness.stale and resp.status in (OK, MODE_INFEASIBLE):
        was = STATUS_NAMES[resp.status]
        detail = f": {resp.message}" if resp.message else ""
        resp.message = f"{freshness.stale}; from those inputs the answer is {was}{detail}"
        resp.status = STALE_INPUTS
        spec.on_stale(resp)


def _wrench(node: Any, snap: Snapshot, req: Any, resp: Any
            ) -> tuple[float, float, float] | None:
    """The request's wrench in the plane, or None with the reply set to INVALID_WRENCH."""
    try:
        return conv.wrench_to_planar(req.wrench, snap.scene.length_scale,
                                     node.out_of_plane_tolerance)
    except conv.ConversionError as exc:
        resp.status, resp.message = INVALID_WRENCH, str(exc)
        return None


def classify(node: Any, snap: Snapshot, g: tuple[float, float, float]) -> list:
    """Every mode g is consistent with, within the node's classify budget."""
    return classifier(snap).consistent_modes(g, max_nodes=node.limits.max_classify_nodes)


def _budget_message(node: Any, exc: Exception) -> str:
    return (f"classification stopped: {exc} (max_classify_nodes "
            f"{node.limits.max_classify_nodes}); raise the parameter or use fewer fixels")


# --- handlers ---------------------------------------------------------------------------
def check_wrench(node: Any, snap: Snapshot, req: CheckWrench.Request,
                 resp: CheckWrench.Response) -> CheckWrench.Response:
    resp.consistent = False
    resp.margin = -1.0
    ans = node.answer(snap, req.mode)
    if ans.status not in (OK, MODE_INFEASIBLE):
        resp.status, resp.message = ans.status, ans.message
        return resp
    g = _wrench(node, snap, req, resp)
    if g is None:
        return resp
    resp.status, resp.message = ans.status, ans.message
    if ans.status == OK:
        if ans.union is not None:
            resp.consistent = bool(ans.union.contains(g))
            resp.margin = float(ans.union.margin(g))
        else:
            resp.consistent, resp.margin = ans.cone.check(g)
    if req.classify:
        mine = set(ans.union.modes) if ans.union is not None else {req.mode}
        try:
            matches = classify(node, snap, g)
        except SearchBudgetError as exc:
            _check_wrench_failed(resp)
            resp.status, resp.message = LIMIT_EXCEEDED, _budget_message(node, exc)
            return resp
        others = [m for m in matches if m.mode not in mine]
        resp.other_modes = [m.mode for m in others]
        resp.other_margins = [float(m.margin) for m in others]
        resp.only_mode = bool(resp.consistent and not others)
    return resp


def _check_wrench_failed(resp: CheckWrench.Response) -> None:
    resp.consistent, resp.margin, resp.only_mode = False, -1.0, False
    resp.other_modes, resp.other_margins = [], []


def _check_wrench_stale(resp: CheckWrench.Response) -> None:
    if resp.consistent:
        resp.message += f" (consistent, margin {resp.margin:.6g})"
    resp.consistent, resp.only_mode = False, False


def classify_wrench(node: Any, snap: Snapshot, req: ClassifyWrench.Request,
                    resp: ClassifyWrench.Response) -> ClassifyWrench.Response:
    if snap.scene is None:
        resp.status, resp.message = snap.status, snap.message
        return resp
    g = _wrench(node, snap, req, resp)
    if g is None:
        return resp
    try:
        matches = classify(node, snap, g)
    except SearchBudgetError as exc:
        resp.status, resp.message = LIMIT_EXCEEDED, _budget_message(node, exc)
        return resp
    resp.modes = [m.mode for m in matches]
    resp.margins = [float(m.margin) for m in matches]
    resp.status = OK
    if not matches:
        resp.message = "the wrench is consistent with no mode of the current scene"
    return resp


def _classify_wrench_failed(resp: ClassifyWrench.Response) -> None:
    resp.modes, resp.margins = [], []


def get_cone(node: Any, snap: Snapshot, req: GetCone.Request,
             resp: GetCone.Response) -> GetCone.Response:
    resp.feasible = False
    ans = node.answer(snap, req.mode)
    resp.status, resp.message = ans.status, ans.message
    if ans.union is not None:
        resp.status = INVALID_MODE
        resp.message = (f"mode {req.mode!r} has wildcards: it is the union of the cones "
                        f"of {list(ans.union.modes)}, not one cone; call get_cone "
                        "for each, or check_wrench with the wildcard mode")
        return resp
    if ans.cone is not None:
        resp.length_scale = float(ans.cone.length_scale)
    if ans.status == OK:
        cone = ans.cone
        resp.feasible = True
        resp.inequalities = conv.rows_flat(cone.F)
        resp.equalities = conv.rows_flat(cone.equalities)
        resp.generators = conv.rows_flat(cone.G)
        resp.lineality = conv.rows_flat(cone.lineality)
    return resp


def _get_cone_failed(resp: GetCone.Response) -> None:
    resp.feasible = False
    resp.inequalities, resp.equalities, resp.generators, resp.lineality = [], [], [], []


#: Every service of the node (name relative to the node: ``~/<name>``).
SERVICES: tuple[ServiceSpec, ...] = (
    ServiceSpec("check_wrench", CheckWrench, check_wrench, _check_wrench_failed,
                _check_wrench_stale, compiled=True),
    ServiceSpec("get_cone", GetCone, get_cone, _get_cone_failed),
    ServiceSpec("classify_wrench", ClassifyWrench, classify_wrench, _classify_wrench_failed,
                slow=True),
)


# --- registration -------------------------------------------------------------------------
def _serve(node: Any, spec: ServiceSpec) -> Callable[[Any, Any], Any]:
    def callback(req: Any, resp: Any) -> Any:
        if spec.slow:  # the publishing worker does not wait for a long request
            return _answer(req, resp)
        # the fast lane: the publishing worker waits for the request, and the request
        # gets at most max_request_time of computation (core/budget.py)
        with node.serving(), time_budget(node.limits.max_request_time):
            return _answer(req, resp)

    def _answer(req: Any, resp: Any) -> Any:
        try:
            # one snapshot for the whole reply: the newest inputs (parameter
            # pose_reuse_window: or the current snapshot, if its pose is that recent)
            snap = node.request_snapshot()
            freshness = node.freshness(snap)
            stamp_response(resp, snap, freshness)
            resp = spec.handler(node, snap, req, resp)
            mark_stale(spec, resp, freshness)
        except TimeBudgetExceeded as exc:
            spec.on_failure(resp)
            resp.status = LIMIT_EXCEEDED
            resp.message = (f"{spec.name} stopped: {exc} (max_request_time); raise the "
                            "parameter, use fewer wildcards, or classify with "
                            "classify_wrench (its own thread, no time budget)")
        except Exception as exc:  # noqa: BLE001 - a service must answer, not die
            spec.on_failure(resp)
            resp.status = INTERNAL_ERROR
            resp.message = f"{spec.name} failed: {type(exc).__name__}: {exc}"[:1000]
            node.get_logger().error(resp.message)
        node.request_counts.record(spec.name, resp.status)  # for /diagnostics
        return resp

    return callback


def register_services(node: Any, specs: tuple[ServiceSpec, ...], slow_lane: Any,
                      compiled_lane: Any) -> dict[str, CallbackGroup | None]:
    """Create every service in ``specs``: ``~/<name>`` on ``node`` (the fast lane), or
    with the same full name on ``slow_lane`` (:class:`~.executors.SlowLane`) for a
    ``slow`` one, or by ``compiled_lane`` (fastcheck.py) for a ``compiled`` one. On the
    multi-threaded fallback executor each fast service has its own reentrant callback
    group. Return name -> callback group (None outside the fast lane)."""
    groups: dict[str, CallbackGroup | None] = {}
    for spec in specs:
        if spec.compiled:
            fastcheck.serve(compiled_lane, node, f"~/{spec.name}", _serve(node, spec))
            groups[spec.name] = None
            continue
        if spec.slow:
            slow_lane.create_service(spec.srv_type, spec.name, _serve(node, spec))
            groups[spec.name] = None
            continue
        group = ReentrantCallbackGroup()
        node.create_service(spec.srv_type, f"~/{spec.name}", _serve(node, spec),
                            callback_group=group)
        groups[spec.name] = group
    return groups
