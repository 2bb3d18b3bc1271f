# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``tray_sim`` node: a simulated tilting tray for controllers to run against.

A scene file's workpiece on its fixels in the engine (:mod:`.tray`, pymunk through
:mod:`wrenchcone_ros.core.simulate`), pulled by the commanded tilt. Interface (every
name relative, so a namespace or a remap applies):

* subscribes ``tilt_command`` (``wrenchcone_msgs/TiltCommand``): direction (rad, fixture
  frame) and magnitude (m/s^2) of gravity's pull in the tray plane (with the parameter
  ``actuator`` ``"spring:X,Y"``: the same force, m times the magnitude, pulling at the
  spring's hook X, Y m in the workpiece frame). A refused command (not finite, magnitude
  outside [0, g]) is logged in one line and ignored;
* publishes ``workpiece_pose`` (``geometry_msgs/PoseStamped``, stamped with the sim time
  of the measurement; optional Gaussian noise ``pose_noise`` m, ``angle_noise`` rad, and
  a delay ``latency`` s, like a vision system), ``fixels`` (``wrenchcone_msgs/Fixels``:
  each fixel's position, radius and, where the scene file gives one, friction, as the
  fixture is built, not the sampled model's; latched: reliable, transient local, depth 1,
  the QoS the wrenchcone node subscribes with), ``/clock`` (``rosgraph_msgs/Clock``:
  nodes with ``use_sim_time`` follow it) and
  ``contact_letters`` (``wrenchcone_msgs/ContactLetters``: the true letters, gaps and
  speed, for evaluation, not for control);
* services ``~/reset`` (``wrenchcone_msgs/ResetPose``) and ``~/sample_model``
  (``wrenchcone_msgs/SampleModel``). After a reset the part is held at its pose until
  the first command of the new run (:mod:`.tray`). A command whose stamp (the stamp of
  the pose it was computed from; 0 for a command that names none) is not later than
  the last reset is ignored, also when it arrives while the reset is under way: it was
  meant for a part that is gone.

Time: every ``publish_period`` s of sim time the engine advances and publishes; with
``real_time_factor`` r > 0 the loop sleeps so that sim time runs r times wall time (1:
real time), with 0 as fast as the machine allows. A step that ends late does not make
the loop run faster to catch up: its schedule slips, so that sim time runs slower than
r times wall time for a moment and never faster (a burst of sim time would reach a
controller as a part that moved further between two of its steps than it can in real
time). Whether the machine keeps up is measured (:attr:`TraySimNode.lag`: the largest
slip of one step, s; :attr:`TraySimNode.slipped`: their sum, s).

Lockstep (parameter ``lockstep``, default false): the engine advances one publish period
only once the command answering the last published pose has arrived: a command stamped
with that pose's stamp (the stamp every controller command carries, TiltCommand.msg),
or after ``lockstep_timeout`` wall seconds (default LOCKSTEP_TIMEOUT_S), when it
advances with the command in force and counts the step in
:attr:`TraySimNode.lockstep_timeouts`. Sim time (``/clock``) then runs as fast as the
controller answers, never faster, and a controller sees every pose, however slow the
machine: a run gives the same poses, commands and letters on any machine for the same
models, as long as no step timed out (``real_time_factor`` does not apply). While it
waits, the tray publishes the awaited pose again every LOCKSTEP_REPEAT_S wall seconds
(the same message, the same stamp), so that a controller started after the tray still
gets it. :meth:`TraySimNode.pause` and :meth:`TraySimNode.resume` stop and restart the
lockstep thread between two steps (a test harness between runs); ``pause_when``, a
condition the thread checks between steps, parks it when it holds.
"""

from __future__ import annotations

import collections
import math
import sys
import threading
import time

import numpy as np
import rclpy
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from wrenchcone_msgs.msg import ContactLetters, Fixels, TiltCommand
from wrenchcone_msgs.srv import ResetPose, SampleModel

from ..core import load_scene
from ..core.simulate import Actuator
from ..core.uncertainty import Uncertainty, load_uncertainty
from ..ros.conversions import fixels_message
from ..ros.qos import fixels_qos
from .program import run_node
from .tray import CommandError, TrayPhysics

#: Default sim time between two published poses (s): 200 Hz, a fast camera.
PUBLISH_PERIOD_S: float = 0.005

#: Default ``lockstep_timeout`` (wall s): how long a lockstep tray waits for the command
#: answering its last pose before it advances with the command in force. Longer than a
#: plan takes (the controller keeps its answer to the pose a plan starts from until the
#: plan has come), so that only a controller that stopped answering trips it.
LOCKSTEP_TIMEOUT_S: float = 120.0

#: Wall seconds between two publications of the pose a lockstep tray waits for an answer
#: to (the same message again: a controller that subscribed late still gets it, and a
#: wrenchcone node does not find it older than its default ``input_timeout``, 1 s).
LOCKSTEP_REPEAT_S: float = 0.5


def _time_msg(t: float):
    from builtin_interfaces.msg import Time
    sec = int(math.floor(t))
    return Time(sec=sec, nanosec=int(round((t - sec) * 1e9)) % 1_000_000_000)


def stamp_seconds(stamp) -> float:
    """A builtin_interfaces/Time as seconds.

    Parameters
    ----------
    stamp : builtin_interfaces.msg.Time
        The stamp.

    Returns
    -------
    float
        s.
    """
    return stamp.sec + 1e-9 * stamp.nanosec


class TraySimNode(Node):
    """The simulated tray (module docstring). ``physics``: a TrayPhysics to use instead
    of the one the parameters describe (tests, benchmarks).

    Parameters
    ----------
    name : str, optional
        The node's name.
    physics : TrayPhysics or None, optional
        The physics to simulate (None: from the parameters ``scene_file``,
        ``uncertainty_file``, ``friction``).
    start : bool, optional
        Start the simulation's thread at once.
    **kwargs
        Passed to ``rclpy.node.Node`` (``context``, ``parameter_overrides``, ...).

    Raises
    ------
    ValueError
        A parameter out of range, or no ``scene_file`` without ``physics``.
    """

    def __init__(self, name: str = "tray_sim", *, physics: TrayPhysics | None = None,
                 start: bool = True, **kwargs) -> None:
        super().__init__(name, **kwargs)
        p = self.declare_parameter
        scene_file = p("scene_file", "").value
        uncertainty_file = p("uncertainty_file", "").value
        friction = list(p("friction", [0.0]).value)
        actuator = p("actuator", "tilt").value
        self.period = float(p("publish_period", PUBLISH_PERIOD_S).value)
        self.real_time_factor = float(p("real_time_factor", 1.0).value)
        self.pose_noise = float(p("pose_noise", 0.0).value)
        self.angle_noise = float(p("angle_noise", 0.0).value)
        self.latency = float(p("latency", 0.0).value)
        self.frame_id = p("frame_id", "world").value
        self.lockstep = bool(p("lockstep", False).value)
        self.lockstep_timeout = float(p("lockstep_timeout", LOCKSTEP_TIMEOUT_S).value)
        self.rng = np.random.default_rng(int(p("seed", 0).value))
        for what, v in (("publish_period", self.period), ("real_time_factor",
                        self.real_time_factor), ("pose_noise", self.pose_noise),
                        ("angle_noise", self.angle_noise), ("latency", self.latency),
                        ("lockstep_timeout", self.lockstep_timeout)):
            if not (math.isfinite(v) and v >= 0.0) or (
                    what in ("publish_period", "lockstep_timeout") and v <= 0):
                raise ValueError(f"parameter {what} must be a finite number >= 0 "
                                 f"(publish_period and lockstep_timeout > 0), got {v!r}")
        if physics is None:
            if not scene_file:
                raise ValueError("parameter scene_file is required (a scene YAML file)")
            scene = load_scene(scene_file)
            unc = load_uncertainty(uncertainty_file) if uncertainty_file else None
            if unc is None and len(friction) == 2 and friction[0] < friction[1]:
                unc = Uncertainty(friction=tuple(friction))
            physics = TrayPhysics(scene, unc, Actuator.parse(actuator))
        self.physics = physics
        self.lock = threading.Lock()
        self._init_lockstep()
        self.lag = 0.0  # the largest slip of one step behind the wall schedule (s)
        self.slipped = 0.0  # all slips (s): wall time the sim did not keep up with
        self.reset_clock = 0.0  # sim time of the last reset (s)
        self._reset_key = (0, 0)  # and as a stamp (sec, nanosec)
        self.stale_commands = 0  # commands stamped before it, ignored
        self.refusals: list[str] = []
        self._pending: collections.deque = collections.deque()  # (due sim time, msg)
        self._published: collections.OrderedDict = collections.OrderedDict()
        self.latencies: list[tuple[float, float]] = []  # (wall s, sim s) pose -> command
        self.pose_pub = self.create_publisher(PoseStamped, "workpiece_pose", 10)
        self.fixels_pub = self.create_publisher(Fixels, "fixels", fixels_qos())
        self.clock_pub = self.create_publisher(
            Clock, "/clock", QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        self.letters_pub = self.create_publisher(ContactLetters, "contact_letters", 10)
        self.create_subscription(TiltCommand, "tilt_command", self._on_command, 10)
        self.create_service(ResetPose, "~/reset", self._on_reset)
        self.create_service(SampleModel, "~/sample_model", self._on_sample)
        self.publish_fixels()
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._lockstep_loop if self.lockstep
                                       else self._loop, name=f"{name}-physics", daemon=True)
        if start:
            self.thread.start()

    # --- outputs -------------------------------------------------------------------------
    def publish_fixels(self) -> None:
        """Publish the fixture (positions, radii, per-fixel friction; latched: transient
        local) at the simulation's clock."""
        self.fixels_pub.publish(fixels_message(self.physics.start.fixels, self.frame_id,
                                               _time_msg(self.physics.clock)))

    def _measure(self) -> tuple[PoseStamped, ContactLetters]:
        r = self.physics.readout()
        x, y, th = r.pose
        if self.pose_noise:
            x, y = x + self.rng.normal(0, self.pose_noise), y + self.rng.normal(0, self.pose_noise)
        if self.angle_noise:
            th = th + self.rng.normal(0, self.angle_noise)
        stamp = _time_msg(self.physics.clock)
        pose = PoseStamped()
        pose.header.frame_id = self.frame_id
        pose.header.stamp = stamp
        pose.pose.position.x, pose.pose.position.y = float(x), float(y)
        pose.pose.orientation.z, pose.pose.orientation.w = math.sin(th / 2), math.cos(th / 2)
        letters = ContactLetters(letters=r.letters, gaps=[float(g) for g in r.gaps],
                                 speed=float(self.physics.speed()))
        letters.header.frame_id = self.frame_id
        letters.header.stamp = stamp
        return pose, letters

    def step_once(self) -> list[PoseStamped]:
        """Advance one publish period and publish what is due (the loop's body).

        Returns
        -------
        list of PoseStamped
            The poses published in this step (none while a ``latency`` delays them).
        """
        with self.lock:
            self.physics.advance(self.period)
            now = self.physics.clock
            pose, letters = self._measure()
            self._pending.append((now + self.latency, pose))
            due = []
            while self._pending and self._pending[0][0] <= now + 1e-12:
                msg = self._pending.popleft()[1]
                self._published[(msg.header.stamp.sec, msg.header.stamp.nanosec)] = (
                    time.monotonic(), now)
                due.append(msg)
            while len(self._published) > 1000:
                self._published.popitem(last=False)
        self.clock_pub.publish(Clock(clock=_time_msg(now)))
        self.letters_pub.publish(letters)
        for msg in due:
            self.pose_pub.publish(msg)
        self.last_letters = letters.letters
        return due

    def wall_clock(self) -> float:
        """The wall clock of the real-time schedule.

        Returns
        -------
        float
            Seconds, monotonic (``time.monotonic``).
        """
        return time.monotonic()

    def wait_wall(self, seconds: float) -> None:
        """Wait on the real-time schedule's wall clock (a stop ends the wait).

        Parameters
        ----------
        seconds : float
            How long (s).
        """
        self._stop.wait(seconds)

    def _loop(self) -> None:
        t0, sim0 = self.wall_clock(), 0.0
        while not self._stop.is_set():
            try:
                self.step_once()
            except Exception as exc:  # noqa: BLE001 - one line, the loop goes on
                self.get_logger().error(f"tray_sim step failed: {type(exc).__name__}: {exc}")
                time.sleep(0.1)
            sim0 += self.period
            if self.real_time_factor > 0:
                due = t0 + sim0 / self.real_time_factor
                delay = due - self.wall_clock()
                if delay > 0:
                    self.wait_wall(delay)
                else:  # late: the schedule slips (module docstring), no sprint
                    self.lag = max(self.lag, -delay)
                    self.slipped -= delay
                    t0 -= delay

    def stop(self) -> None:
        """End the physics thread (joined)."""
        self._stop.set()
        if self.thread.is_alive():
            self.thread.join(5.0)

    def destroy_node(self) -> None:
        """Stop the simulation's thread, then destroy the node."""
        self.stop()
        super().destroy_node()

    def after_reset(self) -> None:
        """Call with the lock held after the physics was reset: poses not yet published
        are dropped, commands stamped before now are ignored from now on."""
        self._pending.clear()
        self.reset_clock = self.physics.clock
        t = _time_msg(self.reset_clock)
        self._reset_key = (t.sec, t.nanosec)
        self._lockstep_reset()

    # --- lockstep (module docstring) ---------------------------------------------------
    def _init_lockstep(self) -> None:
        self.lockstep_timeouts = 0  # steps taken without the answer, after the timeout
        self.last_letters = ""
        self.pause_when = None  # callable: the lockstep thread parks when it returns True
        self.pause_at: float | None = None  # sim s: park before a step that starts there
        self.lockstep_letters: list[str] = []  # the distinct letters since the last reset
        self._answer = threading.Condition()
        self._awaited: tuple[int, int] | None = None  # stamp of the pose awaiting its answer
        self.last_answer: tuple[int, int] | None = None  # stamp of the last command taken
        self._hold = threading.Event()  # asked to park
        self._parked = threading.Event()  # parked, between two steps

    def _answered(self, key: tuple[int, int]) -> None:
        """A command stamped ``key`` was taken (the physics has it): the answer to the
        awaited pose when its stamp is at least that pose's."""
        with self._answer:
            if self.last_answer is None or key > self.last_answer:
                self.last_answer = key
            self._answer.notify_all()

    def _lockstep_reset(self) -> None:
        """After a reset nobody answers a pose of the part that is gone."""
        with self._answer:
            self._awaited = None
            self.lockstep_letters = []
            self._answer.notify_all()

    def _note_letters(self, letters: str) -> None:
        if not self.lockstep_letters or self.lockstep_letters[-1] != letters:
            self.lockstep_letters.append(letters)

    def _must_park(self) -> bool:
        if self.pause_when is not None and self.pause_when():
            self._hold.set()
        return self._hold.is_set() or self._stop.is_set()

    def _await_answer(self, pose: PoseStamped) -> None:
        """Wait until the command answering ``pose`` was taken, the timeout (counted),
        a reset, a pause or the end; publish ``pose`` again every LOCKSTEP_REPEAT_S."""
        key = (pose.header.stamp.sec, pose.header.stamp.nanosec)
        t0 = time.monotonic()
        repeat = t0 + LOCKSTEP_REPEAT_S
        with self._answer:
            self._awaited = key
            while True:
                if (self._awaited != key or (self.last_answer is not None
                                            and self.last_answer >= key)):
                    return  # answered, or a reset made the pose moot
                if self._must_park():
                    return
                now = time.monotonic()
                if now - t0 >= self.lockstep_timeout:
                    self.lockstep_timeouts += 1
                    return
                if now >= repeat:
                    self.pose_pub.publish(pose)
                    repeat = now + LOCKSTEP_REPEAT_S
                self._answer.wait(min(0.05, repeat - now,
                                      t0 + self.lockstep_timeout - now))

    def _lockstep_loop(self) -> None:
        while not self._stop.is_set():
            if self.pause_at is not None and self.physics.clock >= self.pause_at - 1e-9:
                self._hold.set()  # checked here only, after the last pose's answer
            if self._must_park():
                self._parked.set()
                with self._answer:
                    while self._hold.is_set() and not self._stop.is_set():
                        self._answer.wait(0.05)
                self._parked.clear()
                continue
            try:
                due = self.step_once()
            except Exception as exc:  # noqa: BLE001 - one line, the loop goes on
                self.get_logger().error(f"tray_sim step failed: {type(exc).__name__}: {exc}")
                time.sleep(0.1)
                continue
            self._note_letters(self.last_letters)
            if due:
                self._await_answer(due[-1])

    @property
    def parked(self) -> bool:
        """Is the lockstep thread parked between two steps?"""
        return self._parked.is_set()

    def pause(self, timeout: float = 10.0) -> bool:
        """Park the lockstep thread between two steps (it takes no step until
        :meth:`resume`); wait until it is parked. Called before the thread is started,
        the thread starts parked.

        Parameters
        ----------
        timeout : float, optional
            Wall seconds to wait.

        Returns
        -------
        bool
            Parked (False: not a lockstep tray, its thread not running, or the timeout).
        """
        self._hold.set()
        with self._answer:
            self._answer.notify_all()
        if not (self.lockstep and self.thread.is_alive()):
            return False
        return self._parked.wait(timeout)

    def resume(self) -> None:
        """Let a parked lockstep thread step again (``pause_when`` is checked anew)."""
        with self._answer:
            self._hold.clear()
            self._parked.clear()
            self._answer.notify_all()

    def wait_for_command(self, key: tuple[int, int], timeout: float = 5.0) -> bool:
        """Wait until a command stamped ``key`` (sec, nanosec) or later was taken.

        Parameters
        ----------
        key : tuple of 2 int
            The stamp (sec, nanosec).
        timeout : float, optional
            Wall seconds.

        Returns
        -------
        bool
            Taken within the timeout.
        """
        deadline = time.monotonic() + timeout
        with self._answer:
            while self.last_answer is None or self.last_answer < key:
                left = deadline - time.monotonic()
                if left <= 0:
                    return False
                self._answer.wait(min(left, 0.05))
        return True

    def step_unobserved(self) -> str:
        """Advance one publish period with the command in force and publish ``/clock``
        and the letters, but no pose: a harness watching the part come to rest after
        the controller has ended (nothing is there to answer a pose).

        Returns
        -------
        str
            The letters after the step.
        """
        with self.lock:
            self.physics.advance(self.period)
            now = self.physics.clock
            _, letters = self._measure()
        self.clock_pub.publish(Clock(clock=_time_msg(now)))
        self.letters_pub.publish(letters)
        self.last_letters = letters.letters
        self._note_letters(letters.letters)
        return letters.letters

    # --- inputs --------------------------------------------------------------------------
    def _refuse(self, line: str) -> None:
        self.refusals.append(line)
        self.get_logger().warning(line)

    def _on_command(self, msg: TiltCommand) -> None:
        key = (msg.header.stamp.sec, msg.header.stamp.nanosec)
        try:
            with self.lock:  # the check and the command against the same reset
                if key != (0, 0) and key <= self._reset_key:
                    # computed from a pose of the part before the last reset (the last
                    # one published is stamped with the reset's instant): it is gone
                    self.stale_commands += 1
                    return
                self.physics.set_command(msg.direction, msg.magnitude)
                sim_now = self.physics.clock
                sent = self._published.get(key)
        except CommandError as exc:
            self._refuse(str(exc))
            self._answered(key)  # an answer all the same: the command in force stays
            return
        self._answered(key)
        if sent is not None:  # a command computed from a pose this tray published
            self.latencies.append((time.monotonic() - sent[0], sim_now - sent[1]))

    def _on_reset(self, request, response):
        pose = (request.pose.x, request.pose.y, request.pose.theta)
        try:
            with self.lock:
                self.physics.reset(pose)
                self.after_reset()
            response.success, response.message = True, f"reset to {pose}"
        except CommandError as exc:
            self._refuse(str(exc))
            response.success, response.message = False, str(exc)
        return response

    def _on_sample(self, request, response):
        try:
            with self.lock:
                m = self.physics.sample(request.seed, request.nominal)
                self.after_reset()
        except CommandError as exc:
            self._refuse(str(exc))
            response.success, response.message = False, str(exc)
            return response
        response.success = True
        response.message = "nominal model" if request.nominal else f"model of seed {request.seed}"
        response.friction = [float(v) for v in m.friction]
        response.mass, response.inertia = float(m.mass), float(m.inertia)
        response.com.x, response.com.y = (float(v) for v in m.com)
        return response


def main(args: list[str] | None = None) -> int:
    """``tray_sim --ros-args -p scene_file:=...``: run the node until Ctrl-C.

    Parameters
    ----------
    args : list of str or None, optional
        Command-line arguments for rclpy (default: the process's).

    Returns
    -------
    int
        The exit status: 0, or 2 for a bad start-up configuration.
    """
    return run_node("tray_sim", TraySimNode, rclpy.executors.SingleThreadedExecutor, args)


def run() -> None:
    """``main()``, then exit with its status (the console script and the launcher)."""
    sys.exit(main())


if __name__ == "__main__":
    run()
