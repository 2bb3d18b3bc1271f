"""``~/plan_seating``: the ROS 2 action over :func:`wrenchcone_ros.core.plan.plan_seating`.

A goal is answered from the node's current inputs (the snapshot a service request would
use) in a lane of its own: a hidden helper node with a multi-threaded executor spun in its
own thread (like the slow lane, executors.py), so that a plan, which takes seconds,
never holds up the other services; its Monte Carlo runs go to worker processes started
with "spawn" (a ROS process must not fork its DDS threads). One plan at a time: a goal
that arrives while another is computed gets BUSY. Stale inputs give STALE_INPUTS and no
plan (fail-safe). Feedback: segments planned, simulations run of the total. A cancel
stops the planner at its next check (between candidate modes, between runs) and the goal
ends CANCELED. The maths is the core's; this module only converts.
"""

from __future__ import annotations

import math
import threading
from typing import Any

from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node

from geometry_msgs.msg import Pose2D
from wrenchcone_msgs.action import PlanSeating
from wrenchcone_msgs.msg import PlanSegment, Status
from wrenchcone_ros.core.plan import (
    DEFAULT_WORKERS,
    Plan,
    PlanCancelled,
    PlanError,
    plan_seating,
)
from wrenchcone_ros.core.simulate import DEFAULT_TILT, Actuator, SimulationUnavailable
from wrenchcone_ros.node.executors import spin
from wrenchcone_ros.node.status import OK

R = PlanSeating.Result
NAME = "plan_seating"
#: Threads of the plan lane's executor: one runs the goal, the others take goals,
#: cancels and result requests meanwhile.
PLAN_LANE_THREADS = 3
#: Most Monte Carlo runs one goal may ask for (about 0.1 s each on the pawl).
MAX_RUNS = 10_000


def goal_arguments(goal: PlanSeating.Goal, n_fixels: int) -> dict[str, Any]:
    """plan_seating's arguments from a goal; ValueError says what is wrong."""
    target = [int(t) for t in goal.target]
    if not target:
        raise ValueError("target is empty: give the fixels (1-based) that must touch")
    tilt = float(goal.tilt) or DEFAULT_TILT
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
    return {"target": target, "actuator": act, "uncertainty": unc,
            "runs": int(goal.runs) if unc is not None else 0, "seed": int(goal.seed)}


def segment_message(seg: Any) -> PlanSegment:
    """One planned segment as a wrenchcone_msgs/PlanSegment."""
    return PlanSegment(
        mode=seg.mode, interval_lo=float(seg.interval[0]), interval_hi=float(seg.interval[1]),
        direction=float(seg.direction), margin=float(seg.margin),
        start=Pose2D(x=float(seg.start_pose[0]), y=float(seg.start_pose[1]),
                     theta=float(seg.start_pose[2])),
        end=Pose2D(x=float(seg.end_pose[0]), y=float(seg.end_pose[1]),
                   theta=float(seg.end_pose[2])),
        event=seg.event)


def fill_plan(result: R, plan: Plan) -> None:
    """The plan's segments and evidence into the result message."""
    result.feasible = plan.feasible
    result.guaranteed = plan.guaranteed
    result.segments = [segment_message(s) for s in plan.segments]
    rate = plan.success_rate
    result.success_rate = -1.0 if rate is None else float(rate)
    result.runs = len(plan.runs)
    result.successes = sum(r.success for r in plan.runs)
    result.contradicted = plan.contradicted
    result.nominal_success = bool(plan.nominal and plan.nominal.success)
    result.status = Status.OK if plan.feasible else Status.NO_PLAN
    result.message = plan.reason


def start_plan_lane(owner: Any) -> PlanLane:
    """The node's ``~/plan_seating`` action server, started (destroy() it with the node)."""
    lane = PlanLane(owner)
    lane.start()
    return lane


class PlanLane:
    """The action server in its own lane (module docstring)."""

    def __init__(self, owner: Any) -> None:
        self.owner = owner
        self.node = Node(f"_{owner.get_name()}_plan_lane", namespace=owner.get_namespace(),
                         context=owner.context, use_global_arguments=False,
                         start_parameter_services=False, enable_rosout=False)
        self._busy = threading.Lock()
        self._stop = threading.Event()
        self.server = ActionServer(
            self.node, PlanSeating, f"{owner.get_fully_qualified_name()}/{NAME}",
            execute_callback=self._execute, goal_callback=lambda goal: GoalResponse.ACCEPT,
            cancel_callback=lambda handle: CancelResponse.ACCEPT,
            callback_group=ReentrantCallbackGroup())
        self.executor = MultiThreadedExecutor(num_threads=PLAN_LANE_THREADS,
                                              context=owner.context)
        self.executor.add_node(self.node)
        self.thread = threading.Thread(target=spin, name=f"{owner.get_name()}-plan-lane",
                                       args=(self.executor, owner.get_logger(), self._stop),
                                       daemon=True)

    def start(self) -> None:
        self.thread.start()

    def destroy(self) -> None:
        self._stop.set()
        if self.thread.is_alive():
            self.thread.join()
        self.server.destroy()
        self.executor.shutdown()
        self.node.destroy_node()

    # --- one goal -----------------------------------------------------------------------
    def _execute(self, handle: Any) -> R:
        result = R()
        if not self._busy.acquire(blocking=False):
            result.status, result.message = Status.BUSY, "another plan is being computed"
            handle.abort()
            return result
        try:
            return self._plan(handle, result)
        finally:
            self._busy.release()

    def _plan(self, handle: Any, result: R) -> R:
        owner = self.owner
        snap = owner.request_snapshot()
        result.frame_id, result.inputs_version = snap.frame_id, snap.version
        if snap.pose_stamp is not None:
            result.pose_stamp.sec, result.pose_stamp.nanosec = snap.pose_stamp
        if snap.fixels_stamp is not None:
            result.fixels_stamp.sec, result.fixels_stamp.nanosec = snap.fixels_stamp
        if snap.status != OK or snap.scene is None:
            result.status, result.message = snap.status, snap.message
            handle.abort()
            return result
        fresh = owner.freshness(snap)
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
                progress=progress, on_segment=on_segment, start_method="spawn",
                should_stop=lambda: handle.is_cancel_requested or self._stop.is_set())
        except PlanCancelled:
            result.status, result.message = Status.CANCELED, "cancelled: nothing is returned"
            if handle.is_cancel_requested:
                handle.canceled()
            else:
                handle.abort()
            return result
        except SimulationUnavailable as exc:
            result.status, result.message = Status.UNAVAILABLE, str(exc)
            handle.abort()
            return result
        except (PlanError, ValueError) as exc:
            result.status, result.message = Status.INVALID_GOAL, str(exc)
            handle.abort()
            return result
        except Exception as exc:  # noqa: BLE001 - a goal must end, the node must live
            owner.get_logger().error(f"plan_seating failed: {exc!r}")
            result.status = Status.INTERNAL_ERROR
            result.message = f"plan_seating failed: {type(exc).__name__}: {exc}"
            handle.abort()
            return result
        fill_plan(result, plan)
        handle.succeed()
        return result
