# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Service handlers: one snapshot in, one stamped reply out, never an exception.

Every service is a :class:`ServiceSpec` in :data:`SERVICES`; :func:`register_services`
creates each on the node in its callback group (``slow=True``: a group of its own, so
that on a multi-threaded executor a long classification never holds up a check_wrench)
and wraps its handler in :func:`serve`, which refuses with NOT_ACTIVE while the node is
not active (lifecycle), and takes ONE snapshot for the whole reply (the
newest inputs, built now if they changed), stamps the reply (:func:`stamp_response`:
frame, input stamps, inputs version, inputs age) and turns any unexpected exception into
INTERNAL_ERROR with one log line. Then, if the inputs are older than their timeout, an OK
or MODE_INFEASIBLE reply becomes STALE_INPUTS (the message says how old and what the old
inputs give; ``on_stale`` makes the reply fail-safe). A handler only fills the answer:
``handler(node, snap, req, resp) -> resp``. To add a service: write its handler here
and add a ServiceSpec.

The handlers: ``check_wrench``, ``get_cone`` and ``classify_wrench`` answer from the
snapshot's cached answers (answers.py: with ``uncertainty.*`` set, the robust "all"
cones, the message naming the set and the guarantee) and its classifiers
(:func:`classify`: with ``uncertainty.*`` set, every mode possible for some model,
flagged certain for every model, against the snapshot's cached robust cones);
``force_directions``
(srv/ForceDirections, which way to push) is a thin adapter over
:func:`wrenchcone_ros.core.directions.force_directions`: the request is checked against
the request limits (:func:`over_directions_limit`: the mode's wildcards, and with
``exclusive`` every mode of the scene, count against ``max_concrete_modes``) before
anything is computed, and the answer is cached in the snapshot per (mode, point,
exclusive); stale inputs make its reply STALE_INPUTS with no interval (fail-safe).

Timing hook: the node's ``on_request`` attribute, when set, is called after every reply
with a :class:`RequestTiming` (in the serving thread; keep it short).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rclpy.callback_groups import ReentrantCallbackGroup

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.core import ModeError, ModeSyntaxError
from wrenchcone_ros.core.budget import TimeBudgetExceeded, time_budget
from wrenchcone_ros.core.classify import ModeMatch, SearchBudgetError
from wrenchcone_ros.core.directions import DirectionInterval, force_directions
from wrenchcone_ros.core.modes import count_concrete_modes, expand_mode
from wrenchcone_ros.core.uncertainty import NOMINAL, Uncertainty
from wrenchcone_ros.node.answers import (
    Limits,
    cacheable,
    classifier,
    over_classify_limit,
    over_limit,
    uncertainty_text,
)
from wrenchcone_ros.node.executors import LongRunningGroup
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.lane import LaneGroup
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    INVALID_WRENCH,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    NOT_ACTIVE,
    OK,
    STALE_INPUTS,
    STATUS_NAMES,
)
from wrenchcone_ros.node.store import Snapshot
from wrenchcone_msgs.msg import DirectionInterval as DirectionIntervalMsg
from wrenchcone_msgs.msg import ModeMatch as ModeMatchMsg
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, ForceDirections, GetCone

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
    #: In a callback group of its own (its work can be long even within the limits).
    slow: bool = False


@dataclass(frozen=True)
class RequestTiming:
    """One reply computed in Python, as the node's ``on_request`` hook receives it.

    ``started`` is ``time.perf_counter()`` (CLOCK_MONOTONIC on Linux: comparable across
    processes of one machine) and ``started_wall`` ``time.time()``, both in s, when the
    service callback began; ``duration_s`` how long it took until the reply was complete
    (s); ``status`` the reply's status code (status.py)."""

    service: str  # e.g. "check_wrench"
    started: float
    started_wall: float
    duration_s: float
    status: int


def stamp_response(resp: Any, snap: Snapshot, freshness: Freshness | None = None) -> None:
    """Say which inputs the reply was computed from (every service reply carries these)."""
    resp.frame_id = snap.frame_id
    resp.inputs_version = snap.version
    resp.pose_source, resp.fixels_source = snap.pose_source, snap.fixels_source
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


# --- answers as messages ---------------------------------------------------------------
def mode_match_message(m: ModeMatch) -> ModeMatchMsg:
    """A core :class:`~wrenchcone_ros.core.classify.ModeMatch` as a message.

    Parameters
    ----------
    m : ModeMatch
        The core's match (what ``wrenchcone classify`` prints).

    Returns
    -------
    wrenchcone_msgs.msg.ModeMatch
        mode, margin, certain and margin_all (``m.margin_all`` None, the nominal model's:
        ``margin``).
    """
    margin = float(m.margin)
    return ModeMatchMsg(mode=m.mode, margin=margin, certain=bool(m.certain),
                        margin_all=margin if m.margin_all is None else float(m.margin_all))


def direction_interval_message(iv: DirectionInterval) -> DirectionIntervalMsg:
    """A core :class:`~wrenchcone_ros.core.directions.DirectionInterval` as a message.

    Parameters
    ----------
    iv : DirectionInterval
        The core's interval (what ``wrenchcone directions`` prints).

    Returns
    -------
    wrenchcone_msgs.msg.DirectionInterval
        lo, hi, best (rad, fixture frame) and margin.
    """
    return DirectionIntervalMsg(lo=float(iv.lo), hi=float(iv.hi), best=float(iv.best),
                                margin=float(iv.margin))


# --- classification -------------------------------------------------------------------
@dataclass(frozen=True)
class Classification:
    """The modes one wrench is consistent with, for one snapshot (srv/ClassifyWrench).

    ``matches``: the core's :class:`~wrenchcone_ros.core.classify.ModeMatch` of each
    mode, the very objects the ``wrenchcone classify`` command prints
    (:func:`~wrenchcone_ros.cli.render.classify_answer`), one ``ModeMatch`` message each
    (:func:`mode_match_message`). Nominal model: best margin first, each certain (one model), ``margin_all`` its
    margin. Under the snapshot's uncertainty set
    (:func:`~wrenchcone_ros.core.classify.robust_mode_matches`): every mode possible for
    some model, certain ones first, ``margin`` in the "any" sets, ``margin_all`` in the
    "all" cones; ``uncertainty`` and ``guarantee`` name the set and what the answer
    means."""

    matches: tuple[ModeMatch, ...]
    uncertainty: str = ""
    guarantee: str = ""

    @property
    def robust(self) -> bool:
        return bool(self.uncertainty)


class RobustClassifyRefused(SearchBudgetError):
    """A robust classification over max_classify_nodes, refused before any work; its
    message is the whole reply (answers.over_classify_limit)."""


def classify(node: Any, snap: Snapshot, g: tuple[float, float, float]) -> Classification:
    """Every mode g is consistent with, within the node's classify budget (raises
    SearchBudgetError when over it). Under the snapshot's uncertainty set: every mode
    possible for some model, flagged certain for every model, from the snapshot's cached
    robust cones (refused before they are computed when over max_classify_nodes)."""
    refusal = over_classify_limit(snap, node.limits)
    if refusal is not None:
        raise RobustClassifyRefused(refusal.message)
    clf = classifier(snap)
    found = clf.consistent_modes(g, max_nodes=node.limits.max_classify_nodes)
    text = uncertainty_text(snap.uncertainty)
    return Classification(tuple(found), text, str(clf.guarantee) if text else "")


def _budget_message(node: Any, exc: Exception) -> str:
    if isinstance(exc, RobustClassifyRefused):
        return str(exc)
    return (f"classification stopped: {exc} (max_classify_nodes "
            f"{node.limits.max_classify_nodes}); raise the parameter or use fewer fixels")


def _robust_note(c: Classification) -> str:
    """What a robust classification's modes mean (empty for the nominal model)."""
    if not c.robust:
        return ""
    return (f"modes: for some model of {c.uncertainty} (guarantee {c.guarantee}; margins "
            "in the 'any' sets), certain: for every model (margin_all)")


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
        consistent, margin = ans.wrenches.check(g)
        resp.consistent, resp.margin = bool(consistent), float(margin)
    if req.classify:
        mine = set(ans.wrenches.modes) | {req.mode}
        try:
            c = classify(node, snap, g)
        except SearchBudgetError as exc:
            _check_wrench_failed(resp)
            resp.status, resp.message = LIMIT_EXCEEDED, _budget_message(node, exc)
            return resp
        others = [m for m in c.matches if m.mode not in mine]
        resp.others = [mode_match_message(m) for m in others]
        # under uncertainty: consistent for every model (the "all" cone) and no other
        # mode possible for any model (robust exclusivity)
        resp.only_mode = bool(resp.consistent and not others)
        resp.classified = True
        if c.robust:
            certain = [m.mode for m in others if m.certain]
            resp.message += ("; others: for some model (margins in their 'any' sets)"
                             + (f", for every model: {', '.join(certain)}" if certain
                                else ""))
    return resp


def _check_wrench_failed(resp: CheckWrench.Response) -> None:
    resp.consistent, resp.margin, resp.only_mode = False, -1.0, False
    resp.others = []


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
    resp.uncertainty = uncertainty_text(snap.uncertainty)
    try:
        c = classify(node, snap, g)
    except SearchBudgetError as exc:
        resp.status, resp.message = LIMIT_EXCEEDED, _budget_message(node, exc)
        return resp
    resp.matches = [mode_match_message(m) for m in c.matches]
    resp.uncertainty, resp.guarantee = c.uncertainty, c.guarantee
    resp.status = OK
    none = ("the wrench is consistent with no mode of the current scene"
            + (f" for any model of {c.uncertainty}" if c.robust else "")) if not c.matches else ""
    resp.message = "; ".join(x for x in (none, _robust_note(c)) if x)
    return resp


def _classify_wrench_failed(resp: ClassifyWrench.Response) -> None:
    resp.matches = []


def get_cone(node: Any, snap: Snapshot, req: GetCone.Request,
             resp: GetCone.Response) -> GetCone.Response:
    resp.feasible = False
    ans = node.answer(snap, req.mode)
    resp.status, resp.message = ans.status, ans.message
    if ans.wrenches is not None and ans.cone is None:
        resp.status = INVALID_MODE
        resp.message = (f"mode {req.mode!r} has wildcards: it is the union of the cones "
                        f"of {list(ans.wrenches.modes)}, not one cone; call get_cone "
                        "for each, or check_wrench with the wildcard mode")
        return resp
    cone = ans.cone
    if cone is not None:
        resp.length_scale = float(cone.length_scale)
    if ans.status == OK:
        resp.feasible = True
        resp.inequalities = conv.rows_flat(cone.F)
        resp.equalities = conv.rows_flat(cone.equalities)
        resp.generators = conv.rows_flat(cone.G)
        resp.lineality = conv.rows_flat(cone.lineality)
    return resp


def _get_cone_failed(resp: GetCone.Response) -> None:
    resp.feasible = False
    resp.inequalities, resp.equalities, resp.generators, resp.lineality = [], [], [], []


# --- force_directions ---------------------------------------------------------------
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
                       exclusive: bool, uncertainty: Uncertainty) -> DirectionsAnswer:
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
                               classifier=clf, uncertainty=uncertainty)
    except ModeSyntaxError as exc:
        return DirectionsAnswer(INVALID_MODE, str(exc))
    except ModeError as exc:
        return DirectionsAnswer(MODE_NOT_ALLOWED, str(exc))
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return DirectionsAnswer(INTERNAL_ERROR, f"force_directions failed: "
                                                f"{type(exc).__name__}: {exc}")
    text = uncertainty_text(uncertainty)
    robust = text and (
        f"for every model of {text} (guarantee "
        f"{ivs[0].guarantee if ivs else 'as computed'}; margin and best: the worst case)")
    if not ivs:
        return DirectionsAnswer(OK, "no force direction at this point is consistent with "
                                    f"mode {mode!r}" + (" alone" if exclusive else "")
                                + (" " + robust if robust else ""))
    return DirectionsAnswer(OK, robust, tuple(ivs))


def over_directions_limit(snap: Snapshot, mode: str, exclusive: bool,
                          limits: Limits) -> DirectionsAnswer | None:
    """LIMIT_EXCEEDED before any computation, else None. The mode itself as for the other
    services (:func:`~wrenchcone_ros.node.answers.over_limit`: max_mode_length, and
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
                      exclusive: bool, uncertainty: Uncertainty) -> DirectionsAnswer:
    """Cached per (snapshot, mode, point, exclusive, uncertainty), in the snapshot's
    answer cache."""
    key = ("force_directions", mode, point, bool(exclusive), uncertainty)
    ans = snap.answers.get(key)
    if ans is None:
        ans = compute_directions(snap, mode, point, exclusive, uncertainty)
        if cacheable(snap.answers, ans.status):
            snap.answers[key] = ans
    return ans


def force_directions_handler(node: Any, snap: Snapshot, req: ForceDirections.Request,
           resp: ForceDirections.Response) -> ForceDirections.Response:
    try:
        point = _point(req)
    except ValueError as exc:
        resp.status, resp.message = INVALID_WRENCH, str(exc)
        return resp
    ans = (over_directions_limit(snap, req.mode, req.exclusive, node.limits)
           or cached_directions(snap, req.mode, point, req.exclusive, snap.uncertainty))
    if ans.status == INTERNAL_ERROR:
        node.get_logger().error(f"force_directions {req.mode!r}: {ans.message}")
    resp.status, resp.message = ans.status, ans.message
    resp.intervals = [direction_interval_message(iv) for iv in ans.intervals]
    return resp


def _force_directions_failed(resp: ForceDirections.Response) -> None:
    resp.intervals = []


def _force_directions_stale(resp: ForceDirections.Response) -> None:
    """Fail-safe: no direction is offered from stale inputs (the message keeps how many
    intervals they would give)."""
    if resp.intervals:
        resp.message += f" ({len(resp.intervals)} interval(s) from the stale inputs)"
    _force_directions_failed(resp)


def monitored_directions(snap: Snapshot, mode: str) -> tuple[DirectionInterval, ...]:
    """The force directions at the com for a monitored mode (the markers' fans), from the
    same per-snapshot cache and classifier as the service; the nominal model's."""
    return cached_directions(snap, mode, None, False, NOMINAL).intervals


#: Every service of the node (name relative to the node: ``~/<name>``).
SERVICES: tuple[ServiceSpec, ...] = (
    ServiceSpec("check_wrench", CheckWrench, check_wrench, _check_wrench_failed,
                _check_wrench_stale),
    ServiceSpec("get_cone", GetCone, get_cone, _get_cone_failed),
    ServiceSpec("classify_wrench", ClassifyWrench, classify_wrench, _classify_wrench_failed,
                slow=True),
    ServiceSpec("force_directions", ForceDirections, force_directions_handler,
                _force_directions_failed, _force_directions_stale, slow=True),
)


# --- registration -------------------------------------------------------------------------
def serve(node: Any, spec: ServiceSpec) -> Callable[[Any, Any], Any]:
    """The service callback ``callback(request, response) -> response`` of ``spec`` on
    ``node`` (what :func:`register_services` registers); it never raises."""
    def callback(req: Any, resp: Any) -> Any:
        started, started_wall = time.perf_counter(), time.time()
        if spec.slow:  # the publishing worker does not wait for a long request
            resp = _answer(req, resp)
        else:
            # the fast lane: the publishing worker waits for the request, and the
            # request gets at most max_request_time of computation (core/budget.py)
            with node.serving(), time_budget(node.limits.max_request_time):
                resp = _answer(req, resp)
        hook = node.on_request
        if hook is not None:
            try:
                hook(RequestTiming(spec.name, started, started_wall,
                                   time.perf_counter() - started, resp.status))
            except Exception as exc:  # noqa: BLE001 - a hook must never cost a reply
                node.get_logger().error(f"on_request hook failed: {exc!r}",
                                        throttle_duration_sec=5.0)
        return resp

    def _answer(req: Any, resp: Any) -> Any:
        if not node.active:  # lifecycle: configured but not active
            spec.on_failure(resp)
            resp.status = NOT_ACTIVE
            resp.message = (f"the node is not active (lifecycle state {node.state_label}): "
                            "activate it (lifecycle_msgs/srv/ChangeState) to get answers")
            node.request_counts.record(spec.name, resp.status)
            return resp
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


def register_services(node: Any, specs: tuple[ServiceSpec, ...],
                      lane: bool = False) -> dict[str, Any]:
    """Create every service in ``specs`` as ``~/<name>`` on ``node`` and return name ->
    service. Callback groups (what a multi-threaded executor may run at once): the fast
    services (check_wrench, get_cone) share one reentrant group, so concurrent checks
    run side by side, or with ``lane`` one :class:`~.lane.LaneGroup`, from which no
    executor runs them (the node's request lane serves them: lane.py); each ``slow``
    one (classify_wrench, force_directions) has a mutually exclusive group of its own (a
    :class:`~.executors.LongRunningGroup`), so a long classification never holds up a
    check. On a single-threaded executor the executor's services run in turn."""
    fast = LaneGroup() if lane else ReentrantCallbackGroup()
    services: dict[str, Any] = {}
    for spec in specs:
        group = LongRunningGroup() if spec.slow else fast
        services[spec.name] = node.create_service(
            spec.srv_type, f"~/{spec.name}", serve(node, spec), callback_group=group)
    return services


def lane_services(services: dict[str, Any]) -> list[Any]:
    """The services of ``services`` (name -> service) that the request lane serves."""
    return [srv for srv in services.values() if isinstance(srv.callback_group, LaneGroup)]
