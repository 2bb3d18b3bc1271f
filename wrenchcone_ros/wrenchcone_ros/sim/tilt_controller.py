# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``tilt_controller`` node: executes the wrenchcone node's seating plans with feedback.

It does no contact mechanics of its own: every question goes to the wrenchcone node.

1. **Plan.** With the tray level and the part at rest, it sends the node's
   ``plan_seating`` action (``target``, ``friction``, ``runs``) and takes its segments.
2. **Execute, with feedback.** At every observed pose (``workpiece_pose``, the topic the
   node reads too) it asks ``force_directions`` (the segment's mode, ``exclusive``) and
   commands the plan's direction when it lies inside an interval the node returns for that
   pose, or, outside them, while ``classify_wrench`` of it still counts the segment's mode
   among those it may give (for some model: the intervals drift as the part moves, and a
   plan that is not guaranteed was chosen knowing its direction leaves them); else the
   most robust direction (``best``) of the interval nearest to it. The magnitude is the
   segment's (g sin(tilt)). The contact event is asked first, at every
   step of a moving segment: when the fixels the segment reaches (:func:`reached_fixels`)
   are in contact by the node's word (``get_cone`` of :func:`contact_probe`: one cone,
   cheap), it switches segments and commands the next segment's direction at once, as
   the open loop does when those fixels are reached. At an impact the part bounces off
   its other contacts for a moment, and every control step of the old segment's pull
   after it turns the part further from its seat (asked last, after two
   ``force_directions`` calls, the switch came up to 0.2 s after the impact when the
   calls were slow, and a pawl of the seating family tipped over its stop). It switches
   too when the segment's mode is no longer allowed at the observed pose and the next
   segment's is.
3. **Watch.** ``classify_wrench`` of the command at the observed pose gives the modes it
   is consistent with; a planned mode that is not among them, a mode allowed neither now
   nor next, or a part at rest before the seat (a stall: it moved less than
   ``stall_distance`` m in ``stall_time`` s) is a deviation; after ``deviation_steps``
   consecutive deviations (or a stall) it waits, under the plan's hold tilt, for the part
   to stop and plans again from where it is (robustly, then, when the node has no such plan,
   for the nominal model), at most ``max_plans`` plans in all. Under the hold's tilt a
   part that still moves is settling, not deviating, for at most ``hold_limit`` s (pose
   stamps; a part that left the fixture never comes to rest).
4. **Back off.** When the node has no plan from where the part is stuck, it pulls the
   part off the contact it is stuck on (:meth:`TiltControllerNode.backoff_direction`:
   a pull the node classifies as separating the fixels the last segment approached and
   keeping a contact) for ``backoff_time`` s, then resumes the plan's hold, at most
   ``max_backoffs`` times.
5. **Open loop, the last resort.** With neither a plan from where the part is nor a
   back-off (none qualifies, or ``max_plans`` / ``max_backoffs`` are spent), it goes on
   executing the plan it has from the segment it was in, as the open loop would: the
   same commands and segment switches, no more replans; state OPEN_LOOP (WARN). It ends
   SEATED, or FAILED when the part comes to rest elsewhere or after ``open_loop_time`` s
   (pose stamps), the last command staying in force: a controller that stopped
   commanding there would do worse than its own plan executed open loop.
6. **Seated** when the part is in its seat and at rest, whatever the segment or state
   (after the first plan): every target fixel in contact by the node's word (the
   :func:`contact_probe` of the targets, one cone: the node's fixels with their radii,
   and its ``contact_tolerance``, which a loop sets to the engine's contact band,
   SIM_CONTACT_BAND L: the tray's own test of a seat) and the part moved no more than
   ``stall_distance`` over the last ``settle_time`` s. Checked at every control step
   once the part has been at rest that long, and before every replan (a part that
   came to rest in its seat is not replanned). Also when the hold segment's mode is
   allowed at the observed pose and the command gives it. It keeps the hold's tilt.
   A part at rest where the node refuses the pose (``SCENE_ERROR``: a fixel overlaps
   it beyond the tolerance, a fixture the node knows otherwise than it is) is a
   deviation at once, not an endless impact: the run ends, FAILED with that reason,
   rather than running out of time.

State and reason on ``~/state`` (``wrenchcone_msgs/ControllerState``) at every step and
on ``/diagnostics`` (OK seated or executing, WARN replanning, backing off or open loop,
ERROR failed). Commands on
``tilt_command`` (``wrenchcone_msgs/TiltCommand``), each stamped with the stamp of the
pose it was computed from, so that a tray can measure the loop's latency.

**Lockstep** (parameter ``lockstep``, for a tray in lockstep, :mod:`.tray_sim`): the
controller answers every pose exactly once. The commands it computes at a pose are held
and only the last one is published, when it turns to the next pose (or ends): the tray
advances on the first command stamped with its pose, so a second one would race the
step. Each reply of the node is checked to be about the pose being handled (its
``pose_stamp``), and asked again until it is (the node and the controller receive the
pose separately), at most LOCKSTEP_SYNC_S wall seconds; before a plan the node is asked
once the same way, so the plan starts from the pose the controller stands at. Before
the first plan it answers every pose with the level tray. Its wait for the part to come
to rest is bounded in pose stamps, not wall seconds. What it does then depends on the
poses and the node's answers only, not on how fast the machine is.
"""

from __future__ import annotations

import math
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import rclpy
from action_msgs.msg import GoalStatus
from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseStamped
from rclpy.action import ActionClient
from rclpy.node import Node
from wrenchcone_msgs.action import PlanSeating
from wrenchcone_msgs.msg import ControllerState, Status, TiltCommand

from ..core.tilt import STANDARD_GRAVITY
from ..ros.client import DEFAULT_SERVER, DEFAULT_TIMEOUT_S, ServiceUnavailable, WrenchConeClient
from .controller_states import ControllerStates
from .program import run_node

#: Wall seconds a lockstep controller asks the node again until its reply is about the
#: pose being handled (beyond it, the reply is taken as it is, with a warning).
LOCKSTEP_SYNC_S: float = 5.0



def inside(phi: float, lo: float, hi: float) -> bool:
    """Is direction ``phi`` in the closed interval from ``lo`` counter-clockwise to ``hi``
    (rad)?

    Parameters
    ----------
    phi : float
        The direction (rad).
    lo, hi : float
        The interval's ends (rad), counter-clockwise from ``lo``.

    Returns
    -------
    bool
        True when ``phi`` lies in it (1e-12 rad of slack).
    """
    two_pi = 2.0 * math.pi
    return (phi - lo) % two_pi <= (hi - lo) % two_pi + 1e-12


def angular_distance(a: float, b: float) -> float:
    """|a - b| on the circle (rad).

    Parameters
    ----------
    a, b : float
        Two directions (rad).

    Returns
    -------
    float
        In [0, pi].
    """
    return abs(math.remainder(a - b, 2.0 * math.pi))


def choose_direction(planned: float, lo, hi, best) -> tuple[float, bool]:
    """The plan's direction if it lies in one of the intervals [lo_i, hi_i], else the
    ``best`` of the interval with the nearest edge; (direction, kept the plan's).

    Parameters
    ----------
    planned : float
        The plan's direction (rad).
    lo, hi : sequence of float
        The intervals' ends (rad), valid at the observed pose.
    best : sequence of float
        Each interval's best direction (rad).

    Returns
    -------
    direction : float
        The direction to apply (rad).
    kept : bool
        Whether it is the plan's.
    """
    if any(inside(planned, a, b) for a, b in zip(lo, hi)):
        return planned, True
    k = min(range(len(lo)), key=lambda i: min(angular_distance(planned, lo[i]),
                                              angular_distance(planned, hi[i])))
    return float(best[k]), False


def reached_fixels(mode: str, next_mode: str) -> list[int]:
    """The fixels (0-based) a moving segment's contact event brings into contact, read
    from the plan's two modes: approaching (``a``) in the segment and a contact (``l``,
    ``r`` or ``n``) in the next. The open loop switches segments when these are reached
    (:func:`wrenchcone_ros.core.plan.execution.trace`).

    Parameters
    ----------
    mode : str
        The segment's mode.
    next_mode : str
        The next segment's mode.

    Returns
    -------
    list of int
        The fixels, in order (empty when the modes name none).
    """
    return [i for i, (a, b) in enumerate(zip(mode, next_mode)) if a == "a" and b in "lrn"]


def segment_pull(seg) -> float:
    """The magnitude (m/s^2) of a plan segment's pull: g sin(tilt).

    Parameters
    ----------
    seg : wrenchcone_msgs.msg.PlanSegment
        The segment.

    Returns
    -------
    float
        g sin(tilt).
    """
    return STANDARD_GRAVITY * math.sin(seg.tilt)


def contact_probe(n_fixels: int, fixels: list[int]) -> str:
    """The mode the node is asked about to learn whether ``fixels`` (0-based) are in
    contact: ``n`` (rolling, possible only in contact) at those, ``s`` (separating,
    possible in or out of contact) at every other fixel. The node refuses it
    (``MODE_NOT_ALLOWED``) exactly when one of ``fixels`` is not in contact at the
    observed pose, by its contact tolerance.

    Parameters
    ----------
    n_fixels : int
        How many fixels the scene has.
    fixels : list of int
        The fixels (0-based) asked about.

    Returns
    -------
    str
        One letter per fixel.
    """
    return "".join("n" if i in fixels else "s" for i in range(n_fixels))


def _key(stamp) -> tuple[int, int]:
    """A builtin_interfaces/Time as (sec, nanosec), for comparisons."""
    return (stamp.sec, stamp.nanosec)


class _Superseded(Exception):
    """Raised in the thread of a run that a restart replaced."""


@dataclass
class Observation:
    """What the controller saw at one pose.

    Parameters
    ----------
    stamp : float
        The pose's stamp (s).
    pose : tuple of 3 float
        (x m, y m, theta rad).
    """

    stamp: float  # s, the pose's stamp
    pose: tuple[float, float, float]


@dataclass
class RunLog:
    """What happened in one run: the plans asked, the events observed, the segments'
    modes in the order executed, the states entered with their reasons.

    Parameters
    ----------
    plans : int, optional
        The plans asked for.
    events : list of (float, int, str), optional
        (stamp s, segment, mode) of each event observed.
    modes : list of str, optional
        The segments' modes in the order executed.
    states : list of (str, str), optional
        The states entered, with their reasons.
    commands : int, optional
        The tilt commands published.
    calls : dict of str to list of float, optional
        Wall seconds of each call to the node, by service: where a control step's time
        goes.
    """

    plans: int = 0
    events: list[tuple[float, int, str]] = field(default_factory=list)  # (stamp, seg, mode)
    modes: list[str] = field(default_factory=list)
    states: list[tuple[str, str]] = field(default_factory=list)
    commands: int = 0
    calls: dict[str, list[float]] = field(default_factory=dict)


class TiltControllerNode(Node):
    """The reference tilt controller (module docstring).

    Parameters
    ----------
    name : str, optional
        The node's name.
    start : bool, optional
        Start the control loop's thread at once (else :meth:`restart` starts it).
    **kwargs
        Passed to ``rclpy.node.Node`` (``context``, ``parameter_overrides``, ...).
    """

    def __init__(self, name: str = "tilt_controller", *, start: bool = True, **kwargs) -> None:
        super().__init__(name, **kwargs)
        p = self.declare_parameter
        self.server = p("server", DEFAULT_SERVER).value  # relative: this namespace's node
        self.target = [int(v) for v in p("target", [1]).value]
        self.friction = [float(v) for v in p("friction", [0.0]).value]
        if self.friction == [0.0]:
            self.friction = []
        self.runs = int(p("runs", 0).value)
        self.seed = int(p("seed", 0).value)
        self.stall_time = float(p("stall_time", 0.5).value)
        self.stall_distance = float(p("stall_distance", 5e-5).value)
        self.settle_time = float(p("settle_time", 0.3).value)
        self.hold_limit = float(p("hold_limit", 3.0).value)
        self._unsettled_since: float | None = None  # pose stamp (s) the hold's mode was lost
        self.deviation_steps = int(p("deviation_steps", 5).value)
        self.max_plans = int(p("max_plans", 6).value)
        self.max_backoffs = int(p("max_backoffs", 2).value)
        self.backoff_time = float(p("backoff_time", 0.03).value)
        self.backoffs = 0
        self.open_loop_time = float(p("open_loop_time", 5.0).value)
        self.open_loop_since: float | None = None  # pose stamp (s) open loop began, or None
        self._rested = False  # did the last wait for rest end at rest?
        self.plan_timeout = float(p("plan_timeout", 120.0).value)
        # the plan search's work bounds, sent with every goal (0: the planner's defaults)
        self.plan_max_candidates = int(p("plan_max_candidates", 0).value)
        self.plan_max_trials = int(p("plan_max_trials", 0).value)
        if self.plan_max_candidates < 0 or self.plan_max_trials < 0:
            self.get_logger().error(
                f"plan_max_candidates and plan_max_trials must be >= 0 (0: the planner's "
                f"defaults), got {self.plan_max_candidates} and {self.plan_max_trials}: "
                "the planner's defaults are used")
            self.plan_max_candidates = self.plan_max_trials = 0
        self.lockstep = bool(p("lockstep", False).value)
        self._held_command: TiltCommand | None = None  # lockstep: the answer not yet sent
        self.last_command_stamp: tuple[int, int] | None = None  # the last one published
        self.states = ControllerStates()
        self.segments: list = []
        self.k = -1
        self.log = RunLog()
        self.last_direction, self.last_magnitude, self.last_margin = 0.0, 0.0, float("nan")
        self.observed_mode = ""
        self._state_stamp = None  # the stamp of the pose the current state was seen at
        self._pose: PoseStamped | None = None
        self._pose_event = threading.Condition()
        self.client = WrenchConeClient(self, self.server)
        self.action = ActionClient(self, PlanSeating, f"{self.server}/plan_seating")
        self.cmd_pub = self.create_publisher(TiltCommand, "tilt_command", 10)
        self.state_pub = self.create_publisher(ControllerState, "~/state", 10)
        self.diag_pub = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        self.create_subscription(PoseStamped, "workpiece_pose", self._on_pose, 10)
        self.reuse_plan = bool(p("reuse_plan", False).value)
        self.nominal_fallback = bool(p("nominal_fallback", True).value)
        self._first_plan: tuple | None = None  # (start pose, segments) for reuse_plan
        self._stop = threading.Event()
        self.done = threading.Event()
        self.thread: threading.Thread | None = threading.Thread(
            target=self._run, name=f"{name}-loop", daemon=True)
        if start:
            self.thread.start()

    def restart(self) -> None:
        """Stop the current run and start a new one (a reset tray, a new model). With
        ``reuse_plan`` the first plan is taken again when the part starts where that plan
        started (within stall_distance): the node's planner would return the same plan
        for the same inputs; replans always ask the node."""
        self.stop()
        self._stop.clear()
        self.done.clear()
        self.log = RunLog()
        self.backoffs = 0
        self.open_loop_since = None
        self._unsettled_since = None
        self.segments, self.k = [], -1
        self._held_command = None
        self.states.reset()
        with self._pose_event:
            self._pose = None
        self.thread = threading.Thread(target=self._run, name=f"{self.get_name()}-loop",
                                       daemon=True)
        self.thread.start()

    @property
    def state(self) -> str:
        """The controller's state (:data:`.controller_states.STATES`)."""
        return self.states.state

    @state.setter
    def state(self, value: str) -> None:
        self.states.state = value

    @property
    def reason(self) -> str:
        """Why the controller is in its state, in words."""
        return self.states.reason

    # --- plumbing ------------------------------------------------------------------------
    def _on_pose(self, msg: PoseStamped) -> None:
        with self._pose_event:
            self._pose = msg
            self._pose_event.notify_all()

    def _next_pose(self, after: PoseStamped | None, timeout: float = 5.0):
        """The newest pose, newer than ``after`` (None when none came in ``timeout`` s).
        In lockstep the answer to ``after`` is sent first, and a pose is newer by its
        stamp (a lockstep tray publishes a pose again while it waits)."""
        self._flush_command()
        deadline = time.monotonic() + timeout
        with self._pose_event:
            while self._pose is None or self._pose is after or (
                    self.lockstep and after is not None
                    and _key(self._pose.header.stamp) <= _key(after.header.stamp)):
                left = deadline - time.monotonic()
                if left <= 0 or self._stop.is_set() or not self._is_current():
                    return None
                self._pose_event.wait(min(left, 0.1))
            return self._pose

    @staticmethod
    def _observe(msg: PoseStamped) -> Observation:
        q = msg.pose.orientation
        th = 2.0 * math.atan2(q.z, q.w)
        return Observation(msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec,
                           (msg.pose.position.x, msg.pose.position.y, th))

    def _is_current(self) -> bool:
        """Is this thread the current run's (not stopped, not replaced by restart())?"""
        return threading.current_thread() is self.thread and not self._stop.is_set()

    def _check_current(self) -> None:
        """Raise _Superseded in the thread of a run that was stopped or that restart()
        replaced: called before every command and state change and after every wait on
        the node, so that a run ends at its next step and never commands the tray or
        changes the next run's plan, log or state."""
        if not self._is_current():
            raise _Superseded

    def _call(self, service: str, *args, **kwargs):
        """Call the wrenchcone node's ``service`` (a WrenchConeClient method), log its
        wall time in the run's log; _Superseded when the run was stopped meanwhile. In
        lockstep, asked again until the reply is about the newest pose (module
        docstring)."""
        t0 = time.perf_counter()
        reply = getattr(self.client, service)(*args, **kwargs)
        if self.lockstep and self._pose is not None and reply.pose_stamp is not None:
            want = _key(self._pose.header.stamp)
            deadline = time.monotonic() + LOCKSTEP_SYNC_S
            while _key(reply.pose_stamp) < want:
                self._check_current()
                if time.monotonic() >= deadline:
                    self.get_logger().warning(
                        f"{service}: the node still answers at the pose of "
                        f"{_key(reply.pose_stamp)}, not {want}, after {LOCKSTEP_SYNC_S} s")
                    break
                time.sleep(0.001)
                reply = getattr(self.client, service)(*args, **kwargs)
        self.log.calls.setdefault(service, []).append(time.perf_counter() - t0)
        self._check_current()
        return reply

    def _set_state(self, state: str, reason: str) -> None:
        self._check_current()
        if self.states.enter(state, reason, open_loop=self.open_loop_since is not None):
            self.get_logger().info(f"{self.state}: {self.reason}")
            self.log.states.append((self.state, self.reason))
        self._publish_state()

    def _publish_state(self) -> None:
        seg = self.segments[self.k] if 0 <= self.k < len(self.segments) else None
        msg = ControllerState(state=self.state, reason=self.reason, segment=self.k,
                              segments=len(self.segments),
                              planned_mode=seg.mode if seg is not None else "",
                              observed_mode=self.observed_mode,
                              direction=float(self.last_direction),
                              magnitude=float(self.last_magnitude),
                              margin=float(self.last_margin), plans=self.log.plans)
        msg.header.stamp = self._state_stamp or self.get_clock().now().to_msg()
        self.state_pub.publish(msg)
        level = {"OK": DiagnosticStatus.OK, "WARN": DiagnosticStatus.WARN,
                 "ERROR": DiagnosticStatus.ERROR}[self.states.level]
        status = DiagnosticStatus(level=level, name=f"{self.get_name()}: tilt controller",
                                  message=f"{self.state}: {self.reason}",
                                  hardware_id=self.server)
        status.values = [KeyValue(key="segment", value=f"{self.k + 1} of {len(self.segments)}"),
                         KeyValue(key="planned_mode", value=msg.planned_mode),
                         KeyValue(key="observed_mode", value=self.observed_mode),
                         KeyValue(key="plans", value=str(self.log.plans))]
        diag = DiagnosticArray(status=[status])
        diag.header.stamp = msg.header.stamp
        self.diag_pub.publish(diag)

    def _command(self, direction: float, magnitude: float, stamp) -> None:
        self._check_current()
        msg = TiltCommand(direction=float(direction), magnitude=float(magnitude))
        msg.header.stamp = stamp
        msg.header.frame_id = "world"
        self._held_command = msg
        if not self.lockstep:
            self._flush_command()
        self.last_direction, self.last_magnitude = direction, magnitude
        self.log.commands += 1

    @property
    def command_pending(self) -> bool:
        """Is a command computed but not yet published (lockstep: the answer to the pose
        being handled)?"""
        return self._held_command is not None

    def _flush_command(self) -> None:
        """Publish the command held (lockstep: the last one computed at the pose just
        handled); nothing from a run that is no longer the current one."""
        msg, self._held_command = self._held_command, None
        if msg is not None and self._is_current():
            self.cmd_pub.publish(msg)
            self.last_command_stamp = _key(msg.header.stamp)

    def _command_segment(self, seg, stamp) -> None:
        """Command segment ``seg``'s direction and pull (:func:`segment_pull`)."""
        self._command(seg.direction, segment_pull(seg), stamp)

    def level(self, stamp=None) -> None:
        """Level the tray (no pull).

        Parameters
        ----------
        stamp : builtin_interfaces.msg.Time or None, optional
            The command's stamp (None: zero).
        """
        self._command(self.last_direction, 0.0, stamp or Time())

    # --- planning --------------------------------------------------------------------------
    def _plan(self, failed: str = "FAILED") -> bool:
        """Ask for a plan from the node's current inputs; False when none (state
        ``failed``, with the reason: FAILED for the first plan, REPLANNING for a replan,
        whose caller still has the plan it had)."""
        self._check_current()
        if self.log.plans >= self.max_plans:
            self._set_state(failed, f"no seat after {self.log.plans} plan(s), the most "
                            f"max_plans allows")
            return False
        self.log.plans += 1
        here = self._observe(self._pose).pose if self._pose is not None else None
        if (self.reuse_plan and self.log.plans == 1 and self._first_plan is not None
                and here is not None and math.dist(here[:2], self._first_plan[0][:2])
                <= self.stall_distance):
            self.segments, self.k = list(self._first_plan[1]), 0
            self.log.modes.append(self.segments[0].mode)
            self._set_state("EXECUTING", "plan 1 (the first plan again, same start): "
                            + " -> ".join(s.mode for s in self.segments))
            return True
        self._set_state("PLANNING", f"plan {self.log.plans} of at most {self.max_plans}: "
                        f"asking {self.server}/plan_seating")
        if not self._wait_for_server(10.0):
            self._set_state(failed, f"{self.server}/plan_seating is not offered")
            return False
        if self.lockstep:  # the plan from the pose the controller stands at (the node's)
            self._call("classify_wrench", (0.0, 0.0, 0.0))
        res, status, error = self._ask(self.friction)
        if (error is None and self.friction and self.nominal_fallback
                and (status != GoalStatus.STATUS_SUCCEEDED or not res.feasible)):
            robust = res.message
            self._set_state("PLANNING", f"plan {self.log.plans}: none for every model "
                            f"({robust}); asking for the nominal model's")
            res, status, error = self._ask([])
        if error is not None:
            self._set_state(failed, error)
            return False
        if status != GoalStatus.STATUS_SUCCEEDED or not res.feasible or not res.segments:
            self._set_state(failed, f"no plan: {res.message}")
            return False
        self.segments, self.k = list(res.segments), 0
        if self.log.plans == 1 and self._first_plan is None and here is not None:
            self._first_plan = (here, tuple(self.segments))
        self.log.modes.append(self.segments[0].mode)
        verdict = "guaranteed" if res.guaranteed else "not guaranteed"
        self._set_state("EXECUTING", f"plan {self.log.plans} ({verdict}): "
                        + " -> ".join(s.mode for s in self.segments))
        return True

    def _ask(self, friction: list[float]):
        """Send one PlanSeating goal and wait: (result, goal status, error line or None)."""
        goal = PlanSeating.Goal(target=self.target, actuator="tilt", friction=friction,
                                runs=self.runs, seed=self.seed,
                                max_candidates=self.plan_max_candidates,
                                max_trials=self.plan_max_trials)
        done = threading.Event()
        holder: dict = {}

        def on_goal(fut) -> None:
            handle = fut.result()
            if not handle.accepted:
                holder["error"] = "goal rejected"
                done.set()
                return
            handle.get_result_async().add_done_callback(
                lambda f: (holder.__setitem__("result", f.result()), done.set()))

        self.action.send_goal_async(goal).add_done_callback(on_goal)
        if not self._wait(done, self.plan_timeout):
            return None, None, f"no plan within {self.plan_timeout} s"
        if "error" in holder:
            return None, None, holder["error"]
        return holder["result"].result, holder["result"].status, None

    #: Seconds between two looks at whether the run was stopped, while it waits on the
    #: node (for the plan server to appear, for a plan).
    STOP_POLL_S = 0.05

    def _wait(self, event: threading.Event, timeout: float) -> bool:
        """Wait up to ``timeout`` s for ``event``; _Superseded as soon as the run is
        stopped (a stop does not wait for a plan)."""
        deadline = time.monotonic() + timeout
        while not event.wait(min(self.STOP_POLL_S, max(0.0, deadline - time.monotonic()))):
            self._check_current()
            if time.monotonic() >= deadline:
                return False
        self._check_current()
        return True

    def _wait_for_server(self, timeout: float) -> bool:
        """Is the plan_seating action offered (within ``timeout`` s)? _Superseded as soon
        as the run is stopped."""
        deadline = time.monotonic() + timeout
        while not self.action.server_is_ready():
            self._check_current()
            if time.monotonic() >= deadline:
                return False
            time.sleep(self.STOP_POLL_S)
        return True

    def _recover(self, pose: PoseStamped) -> PoseStamped | None:
        """Plan again from where the part is; when the node has no plan from there, back
        off (:meth:`_back_off`, at most ``max_backoffs`` times in a run) and resume the
        previous plan at its hold segment; with no back-off either, go on with the
        previous plan open loop (:meth:`_open_loop`). The pose to go on from, or None
        (state FAILED, or the run was stopped)."""
        previous, k = list(self.segments), self.k
        if self._plan(failed="REPLANNING"):
            return pose
        if not previous:
            self._set_state("FAILED", self.reason)
            return None
        if (self.log.plans >= self.max_plans or self.backoffs >= self.max_backoffs
                or not self._back_off(pose)):
            return self._open_loop(previous, k, pose)
        # resume the previous plan at its hold: the part, just pulled off the contact
        # it was stuck on, is pressed into the seat by the hold's tilt
        self.segments, self.k = previous, len(previous) - 1
        self.log.modes.append(self.segments[self.k].mode)
        self._set_state("EXECUTING", f"back-off {self.backoffs} done: resuming segment "
                        f"{self.k + 1} ({self.segments[self.k].mode})")
        return self._pose

    def _open_loop(self, segments: list, k: int, pose: PoseStamped) -> PoseStamped | None:
        """Go on with ``segments`` from segment ``k``, open loop (module docstring, 5):
        the plan's own command at once, then the control steps without replans. The pose
        to go on from, or None (the run was stopped, or the poses stopped arriving)."""
        why = self.reason
        if self._pose is None:
            return None
        self.segments, self.k = segments, max(0, k)
        seg = self.segments[self.k]
        self.open_loop_since = self._observe(self._pose).stamp
        self.log.modes.append(seg.mode)
        self._command_segment(seg, self._pose.header.stamp)
        self._set_state("EXECUTING", f"segment {self.k + 1} ({seg.mode}) of the plan it has, "
                        f"after: {why}")
        return self._pose

    #: Candidate back-off directions: every BACKOFF_STEP_DEG degrees around the circle.
    BACKOFF_STEP_DEG = 10

    def backoff_direction(self) -> tuple[float, str] | None:
        """A direction that undoes the last contact event, from the node's classification
        (classify_wrench) of candidate pulls at the observed pose: every mode the pull may
        give (for some model, under the node's uncertainty) separates ('s') the fixels the
        last moving segment approached and keeps at least one contact (l, r or n), so the
        part neither stays stuck nor leaves the fixture; among those, the pulls whose every
        mode approaches or touches the target fixels not in contact first, then the
        largest smallest margin. (direction rad, why) or None.

        Returns
        -------
        tuple of (float, str) or None
            (direction rad, the modes it may give), or None when no pull qualifies.
        """
        moving = self.segments[:-1]
        if not moving:
            return None
        approached = [i for i, ch in enumerate(moving[-1].mode) if ch == "a"]
        best = None
        for deg in range(-180, 180, self.BACKOFF_STEP_DEG):
            phi = math.radians(deg)
            c = self._call("classify_wrench", (math.cos(phi), math.sin(phi), 0.0))
            modes = [m.mode for m in c.matches]
            if c.status != Status.OK or not modes:
                continue
            if not all(all(m[i] == "s" for i in approached) and any(ch in "lrn" for ch in m)
                       for m in modes):
                continue
            towards = all(all(m[t - 1] != "s" for t in self.target) for m in modes)
            score = (towards, min(m.margin for m in c.matches))
            if best is None or score > best[0]:
                best = (score, phi, ", ".join(modes))
        if best is None:
            return None
        return best[1], best[2]

    def _back_off(self, pose: PoseStamped) -> bool:
        """Undo the last contact event: pull along :meth:`backoff_direction` for
        ``backoff_time`` s (pose stamps; the caller then resumes its plan: a level tray
        would let a moving part coast away, nothing in the plane brakes it). False when
        there is no such direction (state REPLANNING with the reason: the caller decides
        what follows)."""
        found = self.backoff_direction()
        self._check_current()
        if found is None:
            self._set_state("REPLANNING", "no plan, and no pull undoes the last contact event")
            return False
        direction, modes = found
        magnitude = segment_pull(self.segments[0])
        self.backoffs += 1
        self._set_state("BACKING_OFF", f"no plan from here: back-off {self.backoffs} along "
                        f"{math.degrees(direction):.0f} deg (modes {modes}) for "
                        f"{self.backoff_time} s")
        t0 = None
        while not self._stop.is_set():
            pose = self._next_pose(pose)
            if pose is None:
                return False
            stamp = self._observe(pose).stamp
            t0 = stamp if t0 is None else t0
            if stamp - t0 >= self.backoff_time:
                break
            self._command(direction, magnitude, pose.header.stamp)
        # the hold's tilt at once: the back-off must not last until the next control step
        # (a loop latency later, long enough to pull the part off its pins)
        hold = self.segments[-1]
        self._command_segment(hold, pose.header.stamp)
        return True

    def _wait_at_rest(self, last: PoseStamped | None) -> PoseStamped | None:
        """Wait until the observed part has not moved more than stall_distance for
        stall_time (at most 10 stall times); the last pose. Before any plan the tray is
        level (the part is at rest); after one, the plan's hold tilt is kept meanwhile: a
        level tray would let a moving part coast away (nothing in the tray's plane brakes
        it), the hold's tilt presses it towards the seat."""
        self._rested = False
        hold = self.segments[-1] if self.segments else None
        if hold is None:  # stamped: a tray tells the command from a previous run's
            self.level(last.header.stamp if last is not None else None)
        hist: list[Observation] = []
        pose = last
        limit = 10.0 * max(self.stall_time, 0.1) + 5.0  # wall s; in lockstep pose stamps
        t_end = time.monotonic() + limit
        while not self._stop.is_set():
            if not self.lockstep and time.monotonic() >= t_end:
                break
            pose = self._next_pose(pose)
            if pose is None:
                return None
            if hold is not None:
                self._command_segment(hold, pose.header.stamp)
            elif self.lockstep:  # every pose answered: the tray waits for it
                self.level(pose.header.stamp)
            hist.append(self._observe(pose))
            if self._stalled(hist):
                self._rested = True
                return pose
            if self.lockstep and hist[-1].stamp - hist[0].stamp >= limit:
                break
        self._rested = False
        return pose

    def _stalled(self, hist: list[Observation]) -> bool:
        """Has the part moved less than stall_distance over the last stall_time s?"""
        if not hist or hist[-1].stamp - hist[0].stamp < self.stall_time:
            return False
        t_end = hist[-1].stamp
        recent = [o for o in hist if o.stamp >= t_end - self.stall_time]
        x0 = recent[0].pose
        return all(math.hypot(o.pose[0] - x0[0], o.pose[1] - x0[1]) <= self.stall_distance
                   for o in recent)

    # --- the loop --------------------------------------------------------------------------
    def _run(self) -> None:
        try:
            self._execute()
        except _Superseded:
            return
        except ServiceUnavailable as exc:
            self._finish("FAILED", f"the wrenchcone node did not answer: {exc}")
        except Exception as exc:  # noqa: BLE001 - one state line, the node lives on
            if not self._stop.is_set() and self.context.ok():
                self._finish("FAILED", f"{type(exc).__name__}: {exc}")
        if threading.current_thread() is self.thread:
            # done first, then the answer held: a lockstep harness that parks the tray
            # when the controller is done then parks it before the next step, whichever
            # of the two it sees first
            self.done.set()
            self._at_shutdown_quietly(self._flush_command)

    def _at_shutdown_quietly(self, publish: Callable[[], None]) -> None:
        """``publish()``; when the process's ROS context has ended meanwhile (Ctrl-C
        while a run was going on), its failure ends the run quietly, not a traceback."""
        try:
            publish()
        except Exception:
            if self.context.ok():
                raise

    def _finish(self, state: str, reason: str) -> None:
        try:
            self._at_shutdown_quietly(lambda: self._set_state(state, reason))
        except _Superseded:
            pass

    def _execute(self) -> None:
        pose = self._next_pose(None, timeout=30.0)
        if pose is None:
            self._set_state("FAILED", "no pose within 30 s")
            return
        pose = self._wait_at_rest(pose)
        if pose is None or not self._plan():
            return
        deviations, hist = 0, []
        while not self._stop.is_set():
            pose = self._next_pose(pose)
            if pose is None:
                self._set_state("FAILED", "the pose stopped arriving")
                return
            obs = self._observe(pose)
            hist.append(obs)
            hist = [o for o in hist if o.stamp >= obs.stamp - 2.0 * self.stall_time]
            why = self._step(pose, hist)
            if self.state != "SEATED" and self._in_seat(hist):
                why = None
            if (self.open_loop_since is not None and self.state != "SEATED"
                    and obs.stamp - self.open_loop_since > self.open_loop_time):
                self._set_state("FAILED", f"open loop: not seated after {self.open_loop_time} "
                                "s; the last command stays")
                return
            if why is None:
                deviations = 0
                if self.state == "SEATED":
                    self.done.set()
                continue
            deviations += 1
            at_once = why.startswith(("stall", "unsettled"))
            if self.open_loop_since is not None:
                if at_once:
                    self._set_state("FAILED", f"open loop: {why}; the last command stays")
                    return
                continue
            if deviations >= self.deviation_steps or at_once:
                self._set_state("REPLANNING", f"{why} (plans so far {self.log.plans} of at "
                                f"most {self.max_plans})")
                pose = self._wait_at_rest(pose)
                self._unsettled_since = None
                if pose is not None and self._rested and self._in_seat(None):
                    self.done.set()  # it came to rest in its seat: no replan
                    deviations, hist = 0, []
                    continue
                if pose is None or self._recover(pose) is None:
                    return
                deviations, hist = 0, []

    def _step(self, pose: PoseStamped, hist: list[Observation]) -> str | None:
        """One control step at ``pose``; None, or why this step is a deviation."""
        seg = self.segments[self.k]
        hold = self.k == len(self.segments) - 1
        self._state_stamp = pose.header.stamp
        if not hold and self._reached(seg.mode, self.segments[self.k + 1].mode):
            # the contact event, asked first (one cone, cheap) and answered at once with
            # the next segment's command: at an impact the part bounces, and every ms of
            # the old segment's pull after it turns the part further from its seat
            self._switch(pose)
            seg, hold = self.segments[self.k], self.k == len(self.segments) - 1
            self._command_segment(seg, pose.header.stamp)
        r = self._call("force_directions", seg.mode, exclusive=True)
        if r.status == Status.MODE_NOT_ALLOWED and not hold:
            nxt = self.segments[self.k + 1]
            r2 = self._call("force_directions", nxt.mode, exclusive=True)
            if r2.status == Status.OK:
                self._switch(pose)
                seg, r, hold = nxt, r2, self.k == len(self.segments) - 1
        if r.status == Status.SCENE_ERROR:
            # a fixel overlaps the part beyond the node's contact tolerance: an impact
            # (the engine's contacts are soft for a few steps). Not a deviation: the
            # contact was made; go on with the next segment's command. But a part at
            # rest is not bouncing: the node's fixture is not the part's (a deviation
            # at once, so that the run ends rather than holding for ever)
            if not hold:
                self._switch(pose)
                seg = self.segments[self.k]
            self._command_segment(seg, pose.header.stamp)
            self._set_state("HOLDING" if self.k == len(self.segments) - 1 else "EXECUTING",
                            f"impact: {r.message}")
            if self._stalled(hist):
                return f"stalled where the node refuses the pose: {r.message}"
            return None
        magnitude = segment_pull(seg)
        if r.status != Status.OK or len(r.intervals) == 0:
            self._command(seg.direction, magnitude, pose.header.stamp)
            why = (f"mode {seg.mode} at the observed pose: {r.message}" if r.status != Status.OK
                   else f"no direction gives only {seg.mode} at the observed pose")
            if hold:
                self._set_state("HOLDING", why)
                # a part still moving under the hold's tilt is settling into the seat:
                # a deviation once it has come to rest elsewhere, or when it has not
                # settled within hold_limit s (it left the fixture: nothing stops it)
                now = self._observe(pose).stamp
                if self._unsettled_since is None:
                    self._unsettled_since = now
                if self._stalled(hist):
                    return f"stalled before the seat: {why}"
                if now - self._unsettled_since > self.hold_limit:
                    return f"unsettled for {self.hold_limit} s under the hold's tilt: {why}"
                return None
            self._set_state("EXECUTING", why)
            return why
        self._unsettled_since = None
        ivs = r.intervals
        direction, kept = choose_direction(seg.direction, [iv.lo for iv in ivs],
                                           [iv.hi for iv in ivs], [iv.best for iv in ivs])
        c, note = None, ""
        if not kept:
            # the plan's direction is not among those that give only the segment's mode
            # for every model at this pose. It stays the command as long as it may still
            # give that mode (for some model: what a plan that is not guaranteed was
            # chosen knowing, and checked in the engine with the part's motion): the
            # robust interval, a quasi-static answer at one pose, drifts as the part
            # moves, and following its best direction step after step steers the part
            # off the plan's path (a tall part turning on a pin tipped off its other pin
            # after a drift of 8 degrees and more, in every model, where the open loop seated some)
            c = self._call("classify_wrench", (math.cos(seg.direction),
                                               math.sin(seg.direction), 0.0))
            if c.status == Status.OK and seg.mode in {m.mode for m in c.matches}:
                direction, kept = seg.direction, True
                note = (" (the plan's direction, outside the interval for every model, "
                        "may still give it)")
            else:
                c, note = None, (" (the plan's direction left the interval: its best "
                                 "direction)")
        self._command(direction, magnitude, pose.header.stamp)
        if c is None:
            c = self._call("classify_wrench", (math.cos(direction), math.sin(direction), 0.0))
        matches = list(c.matches) if c.status == Status.OK else []
        modes = [m.mode for m in matches]
        self.observed_mode = modes[0] if modes else ""
        margins = {m.mode: m.margin for m in matches}
        self.last_margin = float(margins.get(seg.mode, float("nan")))
        self._state_stamp = c.pose_stamp  # the pose the node classified at
        if seg.mode not in modes:
            why = (f"the command gives {modes or 'no mode'} at the observed pose, "
                   f"not the planned {seg.mode}")
            self._set_state("HOLDING" if hold else "EXECUTING", why)
            return why
        if hold:
            if self._stalled_for(hist, self.settle_time):
                self._set_state("SEATED", f"{seg.mode} holds at the observed pose, at rest")
            elif self.state != "SEATED":
                self._set_state("HOLDING", f"segment {self.k + 1}: {seg.mode}")
            return None
        if self._stalled(hist):
            return f"stalled in segment {self.k + 1} ({seg.mode}) before its event"
        self._set_state("EXECUTING", f"segment {self.k + 1}: {seg.mode}{note}")
        return None

    def _in_seat(self, hist: list[Observation] | None) -> bool:
        """Is the part at rest in its seat (module docstring, 6)? ``hist``: the recent
        observations, at rest when the part moved no more than stall_distance over
        settle_time (None: known to be at rest). Every target fixel in contact by the
        node's word: the :func:`contact_probe` of the targets is allowed at the observed
        pose. False before the first plan (the number of fixels is the plan's). When
        seated: state SEATED, with the reason."""
        if not self.segments:
            return False
        if hist is not None and not self._stalled_for(hist, self.settle_time):
            return False
        n = len(self.segments[-1].mode)
        targets = [t - 1 for t in self.target if 1 <= t <= n]
        if not targets:
            return False
        c = self._call("get_cone", contact_probe(n, targets))
        if c.status not in (Status.OK, Status.MODE_INFEASIBLE):
            return False
        rest = (f"at rest {self.settle_time} s" if hist is not None
                else f"at rest {self.stall_time} s")
        self._set_state("SEATED", f"target fixel(s) {self.target} in contact (the node's "
                        f"contact tolerance), {rest}")
        return True

    def _switch(self, pose: PoseStamped) -> None:
        """On to the next segment (a contact event at ``pose``), logged."""
        self.k += 1
        self.log.events.append((self._observe(pose).stamp, self.k, self.segments[self.k].mode))
        self.log.modes.append(self.segments[self.k].mode)

    def _reached(self, mode: str, next_mode: str) -> bool:
        """Are the fixels the segment reaches (:func:`reached_fixels`) in contact at the
        observed pose, by the node's word (its answer to :func:`contact_probe`)? False
        when the modes name none or the node cannot say."""
        fixels = reached_fixels(mode, next_mode)
        if not fixels:
            return False
        c = self._call("get_cone", contact_probe(len(mode), fixels))
        return c.status in (Status.OK, Status.MODE_INFEASIBLE)

    def _stalled_for(self, hist: list[Observation], duration: float) -> bool:
        saved = self.stall_time
        self.stall_time = duration
        try:
            return self._stalled(hist)
        finally:
            self.stall_time = saved

    def stop(self) -> bool:
        """End the control loop: from now on its thread can neither command the tray nor
        change the state (it is no longer the current run's); then wait until it has
        ended. Its waits for a plan or a server end at once; a call to a node service in
        flight ends with its reply or its timeout (DEFAULT_TIMEOUT_S).

        Returns
        -------
        bool
            True when the thread has ended (the controller is idle).
        """
        self._stop.set()
        old, self.thread = self.thread, None
        if old is not None and old.is_alive():
            old.join(DEFAULT_TIMEOUT_S + 1.0)
            if old.is_alive():
                self.get_logger().warning(
                    f"the previous run is still in a call to {self.server} after "
                    f"{DEFAULT_TIMEOUT_S + 1.0} s; it can no longer command or change state")
                return False
        return True

    def destroy_node(self) -> None:
        """Stop the control loop, destroy the service and action clients, then the node."""
        self.stop()
        self.client.destroy()
        self.action.destroy()
        super().destroy_node()


def main(args: list[str] | None = None) -> int:
    """``tilt_controller --ros-args -p target:=[1,2,3]``: run until Ctrl-C.

    Parameters
    ----------
    args : list of str or None, optional
        Command-line arguments for rclpy (default: the process's).

    Returns
    -------
    int
        The exit status: 0, or 2 for a bad start-up configuration.
    """
    # one executor thread: the control loop runs in its own thread and blocks only there
    return run_node("tilt_controller", TiltControllerNode, rclpy.executors.SingleThreadedExecutor,
                    args)


def run() -> None:
    """``main()``, then exit with its status (the console script and the launcher)."""
    sys.exit(main())


if __name__ == "__main__":
    run()
