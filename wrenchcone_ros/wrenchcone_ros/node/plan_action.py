# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``~/plan_seating``: the ROS 2 action over :func:`wrenchcone_ros.core.plan.plan_seating`.

The action server is the node's own (remappable, listed under the node), in a callback
group of its own: on a multi-threaded executor a plan, which takes seconds, never holds
up the services. A goal is answered from the node's current inputs (the snapshot a
service request would use); its Monte Carlo runs go to worker processes started once
(the first goal with runs or a start region starts them, later goals reuse them) with
"spawn" (a ROS process must not fork its DDS threads; the installed launcher is safe to
import in them). Goal policy (:class:`PlanAction`): validated in the goal callback
against the node's current fixture (every target fixel exists, numbered 1..n), rejected
when malformed, while inactive or without inputs, or while another plan runs. A rejected goal
has no result (the action protocol answers only "not accepted"), so the reason is
published on ``~/plan_seating/rejections`` (diagnostic_msgs/DiagnosticStatus, latched,
the goal's id among its values; the action's definition says so) and logged. The tilt is
the goal's only with ``use_tilt`` (:func:`goal_tilt`): 0 rad is a level tray, rejected.
A start region is the goal's only with ``use_start_region`` (:func:`goal_start_region`);
its certification's runs go to the same worker processes (up to REGION_CANDIDATES of the
search's plans are certified, the largest box kept: core/plan/search.py), and the result
carries the certified box, its fraction of the asked one, the claim (followed by each
later segment's entry box checked as a funnel of the plan's rest) and the last box that
failed.
Stale inputs abort with STALE_INPUTS and no plan (fail-safe).
Feedback: segments planned, simulations run of the total. A cancel stops the planner at
its next check (between candidate modes, between runs) and the goal ends CANCELED. The
node's deactivation stops a running plan the same way, and waits for it to end (at most
:data:`STOP_WAIT_S`): its goal ends ABORTED with status CANCELED and a message saying the
node was deactivated (nav2's action servers end their goals on deactivation too). The
maths is the core's; this module only converts.
"""

from __future__ import annotations

import math
import multiprocessing
import threading
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from wrenchcone_msgs.action import PlanSeating
from wrenchcone_msgs.msg import PlanarPose, PlanSegment, Status
from wrenchcone_ros.core.plan import (
    DEFAULT_MAX_CANDIDATES,
    DEFAULT_MAX_TRIALS,
    DEFAULT_WORKERS,
    Plan,
    PlanCancelled,
    PlanError,
    StartRegion,
    plan_seating,
)
from wrenchcone_ros.core.simulate import DEFAULT_TILT, Actuator, SimulationUnavailable
from wrenchcone_ros.node import rclpy_boundary
from wrenchcone_ros.node.status import OK

R = PlanSeating.Result
NAME = "plan_seating"
#: Most Monte Carlo runs one goal may ask for (about 0.1 s each on the pawl).
MAX_RUNS = 10_000
#: Longest wait (s) of a deactivation for a running plan to stop (the planner checks
#: between candidate modes and between runs; a check is far more frequent than this).
STOP_WAIT_S = 30.0
#: ``~/plan_seating/rejections``: reliable, transient local, the last REJECTIONS_KEPT
#: rejections kept for a caller that subscribes after sending its goal.
REJECTIONS_KEPT = 10
REJECTIONS_QOS = QoSProfile(depth=REJECTIONS_KEPT, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: The result's message of a plan stopped by the node's deactivation.
DEACTIVATED = "the node was deactivated: the plan was stopped, nothing is returned"


def goal_tilt(goal: PlanSeating.Goal) -> float:
    """The tray tilt a goal asks for.

    Parameters
    ----------
    goal : PlanSeating.Goal
        The goal.

    Returns
    -------
    float
        ``tilt`` (rad) with ``use_tilt``, else the planner's DEFAULT_TILT (10 degrees).

    Raises
    ------
    ValueError
        With ``use_tilt``: a tilt outside (0, pi/2] (0 is a level tray); without: a tilt
        other than 0 (given but not used: refused, never silently ignored).
    """
    tilt = float(goal.tilt)
    if not goal.use_tilt:
        if tilt != 0.0:
            raise ValueError(f"tilt {tilt!r} is given but use_tilt is false: set use_tilt "
                             f"true to use it, or leave tilt 0 for the default "
                             f"({math.degrees(DEFAULT_TILT):g} degrees)")
        return DEFAULT_TILT
    if not (math.isfinite(tilt) and 0.0 < tilt <= math.pi / 2):
        raise ValueError(f"tilt must be in (0, pi/2] rad with use_tilt, got {tilt!r} (0 is "
                         "a level tray: nothing pulls the part)")
    return tilt


def goal_start_region(goal: PlanSeating.Goal) -> StartRegion | None:
    """The region of start poses a goal asks for.

    Parameters
    ----------
    goal : PlanSeating.Goal
        The goal.

    Returns
    -------
    StartRegion or None
        With ``use_start_region``: the box of half-widths (start_region_dx m,
        start_region_dy m, start_region_dtheta rad) around the pose; without: None (the
        pose alone).

    Raises
    ------
    ValueError
        With ``use_start_region``: a half-width that is not a finite number >= 0, or a
        dtheta above pi (the core's :class:`~wrenchcone_ros.core.plan.StartRegion` says
        which); without: a half-width other than 0 (given but not used: refused, never
        silently ignored).
    """
    half = (float(goal.start_region_dx), float(goal.start_region_dy),
            float(goal.start_region_dtheta))
    if not goal.use_start_region:
        if any(v != 0.0 for v in half):
            raise ValueError(
                f"start region ({half[0]!r}, {half[1]!r}, {half[2]!r}) is given but "
                "use_start_region is false: set use_start_region true to use it, or "
                "leave start_region_dx, _dy, _dtheta 0 for the pose alone")
        return None
    try:
        return StartRegion(*half)
    except PlanError as exc:
        raise ValueError(f"{exc} (start_region_dx, _dy in m, start_region_dtheta in "
                         "rad)") from None


def goal_arguments(goal: PlanSeating.Goal, n_fixels: int) -> dict[str, Any]:
    """plan_seating's arguments from a goal; ValueError says what is wrong."""
    target = [int(t) for t in goal.target]
    if not target:
        raise ValueError("target is empty: give the fixels (1-based) that must touch")
    missing = [t for t in target if not 1 <= t <= n_fixels]
    if missing:
        raise ValueError(f"target fixel(s) {missing} not in the fixture: it has {n_fixels} "
                         f"fixels, numbered 1..{n_fixels}")
    tilt = goal_tilt(goal)
    kind = goal.actuator or "tilt"
    if kind == "tilt":
        act = Actuator("tilt", tilt=tilt)
    elif kind == "spring":
        x, y = float(goal.point.x), float(goal.point.y)
        act = Actuator("spring", tilt=tilt, point=(x, y))
    else:
        raise ValueError(f"actuator must be 'tilt' or 'spring', got {goal.actuator!r}")
    fr = [float(v) for v in goal.friction]
    if not all(math.isfinite(v) for v in fr):
        raise ValueError(f"friction must be finite, got {fr}")
    if not fr:
        unc = None
    elif len(fr) == 2:
        unc = (fr[0], fr[1])
    elif len(fr) == 2 * n_fixels:
        unc = [(fr[2 * i], fr[2 * i + 1]) for i in range(n_fixels)]
    else:
        raise ValueError(f"friction takes [lo, hi] or one [lo, hi] per fixel "
                         f"({2 * n_fixels} numbers), got {len(fr)}")
    if int(goal.runs) > MAX_RUNS:
        raise ValueError(f"runs must be at most {MAX_RUNS}, got {goal.runs}")
    budget = float(goal.budget)
    if not math.isfinite(budget) or budget < 0:
        raise ValueError(f"budget must be 0 (no time cap) or a positive number of CPU "
                         f"seconds, got {budget}")
    region = goal_start_region(goal)
    return {"target": target, "actuator": act, "uncertainty": unc, "start_region": region,
            "runs": int(goal.runs) if unc is not None else 0, "seed": int(goal.seed),
            "max_candidates": int(goal.max_candidates) or DEFAULT_MAX_CANDIDATES,
            "max_trials": int(goal.max_trials) or DEFAULT_MAX_TRIALS,
            "budget": budget or None}


def planar_pose_message(pose: Any) -> PlanarPose:
    """A core pose as a message.

    Parameters
    ----------
    pose : sequence of float
        (x m, y m, theta rad) of the workpiece frame in the fixture frame.

    Returns
    -------
    wrenchcone_msgs.msg.PlanarPose
        The same three numbers (REP-103).
    """
    return PlanarPose(x=float(pose[0]), y=float(pose[1]), theta=float(pose[2]))


def segment_message(plan: Plan, seg: Any) -> PlanSegment:
    """One planned segment as a wrenchcone_msgs/PlanSegment, with the force scale and
    tilt it must be executed at (a guaranteed plan may ease off before a contact)."""
    tilt = plan.tilt_deg(seg)
    return PlanSegment(
        mode=seg.mode, interval_lo=float(seg.interval.lo), interval_hi=float(seg.interval.hi),
        direction=float(seg.direction), margin=float(seg.margin),
        accuracy=float(seg.accuracy), scale=float(seg.scale),
        tilt=0.0 if tilt is None else math.radians(tilt),
        start=planar_pose_message(seg.start_pose), end=planar_pose_message(seg.end_pose),
        event=seg.event)


def fill_plan(result: R, plan: Plan) -> None:
    """The plan's segments and evidence into the result message."""
    result.feasible = plan.feasible
    result.guaranteed = plan.guaranteed
    result.segments = [segment_message(plan, s) for s in plan.segments]
    result.missing = list(plan.missing)
    cert = plan.region
    result.start_region_fraction = -1.0 if cert is None else float(cert.fraction)
    if cert is not None:
        box = cert.certified
        result.start_region_certified = box is not None
        if box is not None:
            (result.certified_region_dx, result.certified_region_dy,
             result.certified_region_dtheta) = box.half_widths
        # the claim, each later segment's entry box checked as a funnel, then what the
        # cones decide where the part rests on a segment's contacts
        result.start_region_claim = "; ".join(
            [cert.claim] + [f"funnel: {f.verdict()}" for f in cert.segment_funnels]
            + [f"cones: {c.verdict()}" for c in cert.cone_slices])
        result.start_region_failure = cert.failure
    rate = plan.success_rate
    result.success_rate = -1.0 if rate is None else float(rate)
    result.runs = len(plan.runs)
    result.successes = sum(r.success for r in plan.runs)
    result.contradicted = plan.contradicted
    result.nominal_success = bool(plan.nominal and plan.nominal.success)
    result.candidates, result.trials = plan.candidates, plan.trials
    result.out_of_time = plan.out_of_time
    result.status = Status.OK if plan.feasible else Status.NO_PLAN
    result.message = plan.reason


class PlanAction:
    """The node's ``~/plan_seating`` action server (module docstring).

    Goal policy: one plan at a time. A goal is validated in the goal callback and
    REJECTED (the reason logged) when it is malformed, when the node is not active or has
    no valid inputs, or while another plan runs. An accepted goal ends SUCCEEDED with a
    plan (status OK), CANCELED after a cancel request, ABORTED otherwise (NO_PLAN: the
    planner found none; STALE_INPUTS, UNAVAILABLE, INTERNAL_ERROR), the result's status
    and message saying why."""

    def __init__(self, node: Any) -> None:
        self.node = node
        self._lock = threading.Lock()
        self._busy = False
        self._stop = threading.Event()
        #: set while an execute callback runs (cleared when it has ended)
        self._running = threading.Event()
        self._ended = threading.Condition(self._lock)
        self._pool: ProcessPoolExecutor | None = None
        # the name resolved by the node (its namespace, name and remaps): rcl_action
        # expands an action's name but applies no remap rule to it
        self.name = node.resolve_topic_name(f"~/{NAME}")
        self.rejections = node.create_publisher(DiagnosticStatus, f"{self.name}/rejections",
                                                REJECTIONS_QOS)
        self.server = rclpy_boundary.goal_id_server(ActionServer)(
            node, PlanSeating, self.name,
            execute_callback=self._execute,
            goal_callback=self._on_goal, cancel_callback=lambda handle: CancelResponse.ACCEPT,
            callback_group=ReentrantCallbackGroup())

    def workers(self) -> ProcessPoolExecutor:
        """The Monte Carlo worker processes: one pool, made at the first goal that runs
        models and kept for the next goals (its processes start with the first runs and
        stay; a pool broken by a dead worker is replaced)."""
        with self._lock:
            if self._pool is None:
                self._pool = ProcessPoolExecutor(
                    max_workers=DEFAULT_WORKERS,
                    mp_context=multiprocessing.get_context("spawn"))
            return self._pool

    def drop_workers(self) -> None:
        """Shut the worker pool down (the next goal with runs starts a new one)."""
        with self._lock:
            pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=False, cancel_futures=True)

    def running(self) -> bool:
        """Whether a plan is being computed now.

        Returns
        -------
        bool
            True between the start and the end of a goal's execution.
        """
        return self._running.is_set()

    def activate(self) -> None:
        """Plans run again (after :meth:`deactivate`): goals from now on are not stopped."""
        self._stop = threading.Event()

    def deactivate(self, wait_s: float = STOP_WAIT_S) -> bool:
        """Stop a running plan (its goal ends ABORTED, status CANCELED, message
        :data:`DEACTIVATED`) and wait for it to end, at most ``wait_s``.

        Parameters
        ----------
        wait_s : float, optional
            Longest wait (s).

        Returns
        -------
        bool
            True when no plan runs any more.
        """
        self._stop.set()
        with self._ended:
            return self._ended.wait_for(lambda: not self._running.is_set(), wait_s)

    def destroy(self) -> None:
        self.deactivate(wait_s=0.0)
        self.server.destroy()
        self.node.destroy_publisher(self.rejections)
        self.drop_workers()

    def _reject(self, why: str, goal: PlanSeating.Goal) -> GoalResponse:
        """Reject a goal: the reason logged and published on the rejections topic."""
        self.node.get_logger().warning(f"{NAME} goal rejected: {why}")
        goal_id = rclpy_boundary.current_goal_id()
        try:
            self.rejections.publish(DiagnosticStatus(
                level=DiagnosticStatus.ERROR, name=self.name, message=why,
                hardware_id=self.node.get_fully_qualified_name(),
                values=[KeyValue(key="goal_id", value="" if goal_id is None
                                 else goal_id.hex()),
                        KeyValue(key="target", value=str([int(t) for t in goal.target])),
                        KeyValue(key="stamp_ns",
                                 value=str(self.node.get_clock().now().nanoseconds))]))
        except Exception as exc:  # noqa: BLE001 - the goal is rejected regardless
            self.node.get_logger().error(f"publishing the rejection failed: {exc!r}")
        return GoalResponse.REJECT

    def _on_goal(self, goal: PlanSeating.Goal) -> GoalResponse:
        node = self.node
        if not node.active:
            return self._reject(
                f"the node is not active (lifecycle state {node.state_label})", goal)
        snap = node.request_snapshot()
        if snap.status != OK or snap.scene is None:
            return self._reject(f"no valid inputs: {snap.message}", goal)
        try:
            goal_arguments(goal, snap.scene.n_fixels)
        except ValueError as exc:
            return self._reject(str(exc), goal)
        with self._lock:
            if self._busy:
                return self._reject("another plan is being computed (one at a time); "
                                    "send the goal again when it has ended", goal)
            self._busy = True
        return GoalResponse.ACCEPT

    def _execute(self, handle: Any) -> R:
        stop = self._stop  # a later activate makes a new one: this goal keeps its own
        self._running.set()
        try:
            if stop.is_set():  # accepted, then deactivated before it started
                result = R()
                result.status, result.message = Status.CANCELED, DEACTIVATED
                handle.abort()
                return result
            return self._plan(handle, R(), stop)
        finally:
            with self._lock:
                self._busy = False
                self._running.clear()
                self._ended.notify_all()

    def _plan(self, handle: Any, result: R, stop: threading.Event) -> R:
        node = self.node
        snap = node.request_snapshot()
        result.frame_id, result.inputs_version = snap.frame_id, snap.version
        result.pose_source, result.fixels_source = snap.pose_source, snap.fixels_source
        if snap.pose_stamp is not None:
            result.pose_stamp.sec, result.pose_stamp.nanosec = snap.pose_stamp
        if snap.fixels_stamp is not None:
            result.fixels_stamp.sec, result.fixels_stamp.nanosec = snap.fixels_stamp
        if snap.status != OK or snap.scene is None:
            result.status, result.message = snap.status, snap.message
            handle.abort()
            return result
        fresh = node.freshness(snap)
        if fresh.stale:
            result.status = Status.STALE_INPUTS
            result.message = f"{fresh.stale}; no plan is made from stale inputs"
            handle.abort()
            return result
        feedback = PlanSeating.Feedback()

        def on_segment(k: int) -> None:
            feedback.segments_planned = k
            handle.publish_feedback(feedback)

        def progress(done: int, total: int) -> None:
            feedback.simulations_run, feedback.simulations_total = done, total
            handle.publish_feedback(feedback)

        try:
            args = goal_arguments(handle.request, snap.scene.n_fixels)
            plan = plan_seating(
                snap.scene, args["target"], args["actuator"], args["uncertainty"],
                runs=args["runs"], seed=args["seed"], workers=DEFAULT_WORKERS,
                progress=progress, on_segment=on_segment,
                pool=(self.workers() if args["runs"] or args["start_region"] is not None
                      else None),
                start_method="spawn", start_region=args["start_region"],
                max_candidates=args["max_candidates"], max_trials=args["max_trials"],
                budget=args["budget"],
                should_stop=lambda: handle.is_cancel_requested or stop.is_set())
        except PlanCancelled:
            result.status, result.message = Status.CANCELED, "cancelled: nothing is returned"
            if stop.is_set() and not handle.is_cancel_requested:
                result.message = DEACTIVATED
            if handle.is_cancel_requested:
                handle.canceled()
            else:
                handle.abort()
            return result
        except SimulationUnavailable as exc:
            result.status, result.message = Status.UNAVAILABLE, str(exc)
            handle.abort()
            return result
        except BrokenProcessPool as exc:
            self.drop_workers()
            result.status = Status.UNAVAILABLE
            result.message = (f"a Monte Carlo worker process ended ({exc}); the workers "
                              "are restarted with the next goal")
            node.get_logger().error(result.message)
            handle.abort()
            return result
        except (PlanError, ValueError) as exc:
            result.status, result.message = Status.INVALID_GOAL, str(exc)
            handle.abort()
            return result
        except Exception as exc:  # noqa: BLE001 - a goal must end, the node must live
            node.get_logger().error(f"plan_seating failed: {exc!r}")
            result.status = Status.INTERNAL_ERROR
            result.message = f"plan_seating failed: {type(exc).__name__}: {exc}"
            handle.abort()
            return result
        fill_plan(result, plan)
        if plan.feasible:
            handle.succeed()
        else:
            handle.abort()
        return result
