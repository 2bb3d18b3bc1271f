# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""One closed-loop run in one process: tray_sim, the wrenchcone node, tilt_controller.

:func:`closed_loop` starts the three nodes on a leased ROS domain (the wrenchcone node in
a DDS participant of its own, the tray and the controller in another: they talk over
real DDS, as three processes would), runs the controller until it reports SEATED or
FAILED (or a time limit), and returns what the tray saw (:class:`LoopResult`). The
launch-free test of the loop, the benchmark and the tutorial use it; a controller author
swaps in a controller of their own with ``controller_factory``.

By default the tray and the controller run in **lockstep** (:mod:`.tray_sim`,
:mod:`.tilt_controller`): the engine advances one publish period once the controller has
answered the last pose, so a run's poses, commands, letters and verdicts are the same on
any machine, loaded or not, for the same models (``LoopResult.lockstep_timeouts`` = 0
says no step went without its answer). A run's time limit is then in sim time
(``sim_timeout``), the controller's end parks the tray at once, and the tray's truth is
judged by stepping the engine with the last command in force, no controller in the loop.
``lockstep=False`` runs the tray against the wall clock at ``real_time_factor``: what
the loop's latency means against the motion's time scale is measured there.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Sequence
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..core import load_scene
from ..core.plan.execution import HOLD_LIMIT, HOLD_TIME, as_model
from ..core.plan.execution import moved  # the open loop's own test of rest
from ..core.scene import Scene
from ..core.tolerances import SIM_CONTACT_BAND
from ..core.uncertainty import Model, Uncertainty
from ..node.inprocess import NodeFactory
from ..ros.contexts import isolated_context
from ..ros.spinning import ExecutorThread
from .tilt_controller import TiltControllerNode
from .tray import TrayPhysics
from .tray_sim import LOCKSTEP_TIMEOUT_S, TraySimNode


@dataclass
class LoopResult:
    """A closed-loop run: seated (the tray's truth, :meth:`Loop.seated`: every target
    fixel within the engine's contact band, SIM_CONTACT_BAND L, and the part at rest, by
    the open loop's own test), the controller's
    final state and reason, its log, the distinct letter strings the tray read in order,
    the pose -> command latencies (wall s, sim s), the sim time used and the tray's
    largest slip behind real time in one step (s).

    Parameters
    ----------
    seated : bool
        The tray's truth: every target fixel within the contact band, the part at rest.
    state : str
        The controller's final state (SEATED, FAILED, ...).
    reason : str
        The controller's reason.
    plans : int
        How many plans the controller asked for.
    modes : list of str
        The planned modes, in order.
    events : list
        The controller's log.
    letters : list of str, optional
        The distinct letter strings the tray read, in order.
    latencies : list of (float, float), optional
        Pose -> command latencies (wall s, sim s).
    sim_time : float, optional
        The simulated time used (s).
    lag : float, optional
        The tray's largest slip behind real time in one step (s).
    final_pose : tuple of 3 float, optional
        (x m, y m, theta rad).
    refusals : list of str, optional
        Commands the tray refused, with the reason.
    previous_idle : bool, optional
        Whether the previous run's controller was idle when the tray was reset for this
        one.
    calls : dict of str to list of float, optional
        Wall seconds of the controller's calls to the node, by service.
    lockstep_timeouts : int, optional
        In lockstep: the steps the tray took without the controller's answer, after its
        ``lockstep_timeout`` (0: the run is the same on any machine).
    """

    seated: bool
    state: str
    reason: str
    plans: int
    modes: list[str]
    events: list
    letters: list[str] = field(default_factory=list)
    latencies: list[tuple[float, float]] = field(default_factory=list)
    sim_time: float = 0.0
    lag: float = 0.0
    final_pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    refusals: list[str] = field(default_factory=list)
    previous_idle: bool = True
    calls: dict[str, list[float]] = field(default_factory=dict)
    lockstep_timeouts: int = 0


#: Default ``sim_timeout`` of a lockstep :class:`Loop` (s of sim time): a run that has
#: not ended by then is stopped (TIMEOUT). Long enough for every plan, back-off and
#: open-loop period the controller's default parameters allow.
LOOP_SIM_TIMEOUT_S: float = 30.0

#: Contact tolerance (m) the loop gives the wrenchcone node, in units of the part's
#: length scale L: the engine's contact band, so that the node and the tray call the
#: same fixels "in contact".
LOOP_CONTACT_TOLERANCE: float = SIM_CONTACT_BAND


def node_parameters(scene: Scene, friction: Sequence[float] | None) -> dict:
    """The wrenchcone node's parameters for a loop: contact tolerance the engine's
    contact band, never stale (a loaded machine), the friction interval as its
    uncertainty (robust answers).

    Parameters
    ----------
    scene : Scene
        The scene (its length scale).
    friction : sequence of float or None
        The friction interval (lo, hi), or None.

    Returns
    -------
    dict
        Parameter name -> value.
    """
    params = {"input_timeout": 0.0, "fixels_timeout": 0.0,
              "contact_tolerance": LOOP_CONTACT_TOLERANCE * scene.length_scale}
    if friction:
        params["uncertainty.friction"] = [float(v) for v in friction]
    return params


class Loop:
    """The three nodes, started once, for many runs (module docstring).

    Use as a context manager; :meth:`run` resets the tray (a model, the start pose) and
    runs the controller once. Parameters as :func:`closed_loop`.

    Parameters
    ----------
    scene : str, Path or Scene
        The scene, or its YAML file.
    target : sequence of int
        The target fixels (1-based).
    friction : sequence of float or None, optional
        The friction interval (lo, hi) the planner and the node assume.
    runs : int, optional
        Monte Carlo runs of each plan (the controller's ``runs`` parameter).
    real_time_factor : float, optional
        Sim time runs this many times wall time.
    pose_noise : float, optional
        Gaussian noise of the published position (m).
    angle_noise : float, optional
        Gaussian noise of the published angle (rad).
    latency : float, optional
        Delay of the published pose (s).
    controller_parameters : dict or None, optional
        More parameters of the controller node.
    lockstep : bool, optional
        Run the tray and the controller in lockstep (module docstring; default). False:
        the tray runs against the wall clock at ``real_time_factor``.
    lockstep_timeout : float, optional
        Wall seconds the lockstep tray waits for an answer before it steps without one
        (tray_sim's ``lockstep_timeout``).
    sim_timeout : float, optional
        In lockstep: a run that has not ended SEATED or FAILED after this many seconds of
        sim time is stopped there (state TIMEOUT).
    node_scene : str, Path, Scene or None, optional
        The scene file the wrenchcone node is given, when it is not the tray's (a
        fixture the node knows differently from the one the tray simulates: a pin whose
        radius differs from the file's); None: the tray's.
    """

    def __init__(self, scene: str | Path | Scene, target: Sequence[int],
                 friction: Sequence[float] | None = None, *, runs: int = 0,
                 real_time_factor: float = 1.0, pose_noise: float = 0.0,
                 angle_noise: float = 0.0, latency: float = 0.0,
                 controller_parameters: dict | None = None, lockstep: bool = True,
                 lockstep_timeout: float = LOCKSTEP_TIMEOUT_S,
                 sim_timeout: float = LOOP_SIM_TIMEOUT_S,
                 node_scene: str | Path | Scene | None = None) -> None:
        self.scene = load_scene(scene) if isinstance(scene, (str, Path)) else scene
        self.node_scene = (self.scene if node_scene is None else load_scene(node_scene)
                           if isinstance(node_scene, (str, Path)) else node_scene)
        self.target = [int(t) for t in target]
        self.friction = [float(v) for v in friction or []]
        self.physics = TrayPhysics(self.scene, Uncertainty(friction=tuple(self.friction))
                                   if self.friction else None)
        self.lockstep = bool(lockstep)
        self.sim_timeout = float(sim_timeout)
        self.tray_parameters = {"real_time_factor": float(real_time_factor),
                                "pose_noise": float(pose_noise),
                                "angle_noise": float(angle_noise), "latency": float(latency),
                                "lockstep": self.lockstep,
                                "lockstep_timeout": float(lockstep_timeout)}
        self.controller_parameters = {"target": self.target,
                                      "friction": self.friction or [0.0], "runs": int(runs),
                                      "lockstep": self.lockstep}
        self.controller_parameters.update(controller_parameters or {})
        self.letters: list[str] = []

    def __enter__(self) -> Loop:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from rclpy.parameter import Parameter
        from wrenchcone_msgs.msg import ContactLetters

        self._tmp = tempfile.TemporaryDirectory()
        self._ctx_manager = isolated_context()
        ctx = self._ctx_manager.__enter__()
        self.factory = NodeFactory(ctx.get_domain_id(), Path(self._tmp.name))
        self.wrenchcone = self.factory.make(
            self.node_scene, parameters=node_parameters(self.scene, self.friction))
        # one thread is enough (the controller's calls block its own thread, never a
        # callback), and rclpy's MultiThreadedExecutor here spins a core busy while idle:
        # measured, a loop run took 20-40 s instead of 2-4 s (the GIL it holds starves
        # the physics and the planner)
        self.spinner = ExecutorThread(ctx, SingleThreadedExecutor, name="loop-executor")
        self.tray = TraySimNode(physics=self.physics, context=ctx, start=False,
                                parameter_overrides=[Parameter(k, value=v) for k, v in
                                                     self.tray_parameters.items()])
        self.controller = TiltControllerNode(
            context=ctx, start=False,
            parameter_overrides=[Parameter(k, value=v)
                                 for k, v in self.controller_parameters.items()])
        self.tray.create_subscription(ContactLetters, "contact_letters", self._on_letters, 100)
        self.recorder_node = Node("loop_recorder", context=ctx)
        self.spinner.add_node(self.recorder_node)
        self.spinner.add_node(self.tray)
        self.spinner.add_node(self.controller)
        if self.lockstep:
            self.tray.pause()  # it starts parked: no step before the first run
        self.tray.thread.start()
        return self

    def _on_letters(self, msg) -> None:
        if not self.letters or self.letters[-1] != msg.letters:
            self.letters.append(msg.letters)

    def run(self, model: Model | Sequence | None = None, timeout: float = 120.0,
            record: str | Path | None = None) -> LoopResult:
        """Reset the tray to its start pose with ``model`` (None: the nominal one), run
        the controller until SEATED or FAILED or ``timeout`` wall seconds; ``record``: a
        new rosbag2 MCAP bag directory to record the run into (:mod:`.recorder`). The
        tray is reset only once the previous run's controller has ended (or could not:
        ``previous_idle``).

        Parameters
        ----------
        model : Model, sequence of float or None, optional
            The physics' model (None: the nominal one; a sequence: mu per fixel).
        timeout : float, optional
            Wall seconds.
        record : str, Path or None, optional
            A new bag directory.

        Returns
        -------
        LoopResult
            What the tray saw.
        """
        self._previous_idle = self.controller.stop()
        recorder = None
        if record is not None:
            from .recorder import BagRecorder
            recorder = BagRecorder(self.recorder_node, record, scene=replace(
                self.scene, contact_tolerance=node_parameters(self.scene, None)[
                    "contact_tolerance"]))
            time.sleep(0.2)  # the recorder's subscriptions matched before the run starts
        try:
            return self._run(model, timeout)
        finally:
            if recorder is not None:
                time.sleep(0.1)  # the last messages in flight
                recorder.close()

    def _run(self, model, timeout: float) -> LoopResult:
        if self.lockstep:
            return self._run_lockstep(model, timeout)
        physics, ctl, tray = self.physics, self.controller, self.tray
        with tray.lock:
            physics.set_model(as_model(self.scene, model))
            tray.after_reset()
            n_lat = len(tray.latencies)
            self.letters.clear()
        time.sleep(0.05)  # the reset pose is published before the controller looks
        ctl.restart()
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not ctl.done.is_set():
            time.sleep(0.02)
        timed_out = not ctl.done.is_set()
        seated = self.seated(deadline + timeout)
        with tray.lock:
            r = physics.readout()
        return LoopResult(
            seated=seated, state="TIMEOUT" if timed_out else ctl.state,
            reason=(f"no SEATED or FAILED within {timeout} s ({ctl.state}: {ctl.reason})"
                    if timed_out else ctl.reason),
            plans=ctl.log.plans, modes=list(ctl.log.modes), events=list(ctl.log.events),
            letters=list(self.letters), latencies=list(tray.latencies[n_lat:]),
            sim_time=physics.clock, lag=tray.lag, final_pose=r.pose,
            refusals=list(tray.refusals), previous_idle=self._previous_idle,
            calls={k: list(v) for k, v in ctl.log.calls.items()})

    def _run_lockstep(self, model, timeout: float) -> LoopResult:
        """:meth:`run` in lockstep: the tray parked between runs, the run's limit in sim
        time, the truth judged with the controller out of the loop."""
        physics, ctl, tray = self.physics, self.controller, self.tray
        tray.pause()
        with tray.lock:
            physics.set_model(as_model(self.scene, model))
            tray.after_reset()
            n_lat, n_timeouts = len(tray.latencies), tray.lockstep_timeouts
            tray.pause_at = physics.clock + self.sim_timeout
        ctl.restart()
        tray.pause_when = ctl.done.is_set
        tray.resume()
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not ctl.done.is_set() and not tray.parked:
            time.sleep(0.02)
        # the controller's end (or the sim-time limit) parks the tray before its next
        # step; a wall timeout parks it wherever it is
        wall_out = not tray.parked and not ctl.done.is_set()
        tray.pause()
        tray.pause_when, tray.pause_at = None, None
        done = ctl.done.is_set()
        # its answer to the last pose, held until it turns to the next one, goes out
        # right after its end (tilt_controller: done first, then the answer)
        flush_deadline = time.monotonic() + 5.0
        while done and ctl.command_pending and time.monotonic() < flush_deadline:
            time.sleep(0.005)
        ctl.stop()
        if ctl.last_command_stamp is not None:  # its last answer taken before the watch
            tray.wait_for_command(ctl.last_command_stamp)
        state, reason = ctl.state, ctl.reason
        if not done:
            limit = (f"{timeout} s of wall time" if wall_out
                     else f"{self.sim_timeout} s of sim time")
            state, reason = "TIMEOUT", f"no SEATED or FAILED within {limit} ({state}: {reason})"
        seated = self._seated_lockstep()
        with tray.lock:
            r = physics.readout()
        return LoopResult(
            seated=seated, state=state, reason=reason, plans=ctl.log.plans,
            modes=list(ctl.log.modes), events=list(ctl.log.events),
            letters=list(tray.lockstep_letters), latencies=list(tray.latencies[n_lat:]),
            sim_time=physics.clock, lag=tray.lag, final_pose=r.pose,
            refusals=list(tray.refusals), previous_idle=self._previous_idle,
            calls={k: list(v) for k, v in ctl.log.calls.items()},
            lockstep_timeouts=tray.lockstep_timeouts - n_timeouts)

    def _seated_lockstep(self) -> bool:
        """:meth:`seated` with the tray parked and the controller stopped: the engine
        stepped here, the last command in force, the windows exact in sim time."""
        physics, tray = self.physics, self.tray
        with tray.lock:
            T, L = physics.sim.sp.time_scale, physics.sim.sp.length_scale
            start, pose0, band = physics.clock, physics.readout().pose, SIM_CONTACT_BAND * L
        steps = max(1, math.ceil(0.25 * HOLD_TIME * T / tray.period - 1e-9))
        while True:
            for _ in range(steps):
                tray.step_unobserved()
            with tray.lock:
                now, r = physics.clock, physics.readout()
            at_rest = moved(pose0, r.pose, L) <= band
            if at_rest or now - start >= HOLD_LIMIT * T:
                break
            pose0 = r.pose  # still moving: one more window
        return at_rest and all(r.gaps[i - 1] <= band for i in self.target)

    def seated(self, wall_deadline: float) -> bool:
        """The tray's truth, judged as the open loop judges a run
        (:func:`wrenchcone_ros.core.plan.execution.trace`): every target fixel within the
        contact band (SIM_CONTACT_BAND L) and the part at rest, no point of it moving
        more than the band over a window of HOLD_TIME / 4 T of sim time (a speed read at
        one instant is no test: the engine's velocities spike now and then); a part
        still moving is watched window after window, up to HOLD_LIMIT T (or the wall
        ``wall_deadline``). The controller's last command stays in force meanwhile.

        Parameters
        ----------
        wall_deadline : float
            ``time.monotonic()`` after which a part still moving is judged as it is.

        Returns
        -------
        bool
            Seated: the target fixels within the band and the part at rest.
        """
        physics, tray = self.physics, self.tray
        with tray.lock:
            T, L = physics.sim.sp.time_scale, physics.sim.sp.length_scale
            start, pose0, band = physics.clock, physics.readout().pose, SIM_CONTACT_BAND * L
        at_rest, t0 = False, start
        while True:
            time.sleep(0.01)
            with tray.lock:
                now, r = physics.clock, physics.readout()
            if now - t0 < 0.25 * HOLD_TIME * T:
                if time.monotonic() < wall_deadline:
                    continue
            at_rest = moved(pose0, r.pose, L) <= band
            if at_rest or now - start >= HOLD_LIMIT * T or time.monotonic() >= wall_deadline:
                break
            t0, pose0 = now, r.pose  # still moving: one more window
        return at_rest and all(r.gaps[i - 1] <= band for i in self.target)

    def __exit__(self, *exc) -> None:
        try:
            self.controller.stop()
            self.tray.stop()
            self.spinner.stop()
            self.controller.destroy_node()
            self.tray.destroy_node()
            self.recorder_node.destroy_node()
            self.factory.close()
        finally:
            self._ctx_manager.__exit__(None, None, None)
            self._tmp.cleanup()


def closed_loop(scene: str | Path | Scene, target: Sequence[int],
                friction: Sequence[float] | None = None, model: Model | Sequence | None = None,
                *, timeout: float = 120.0, **kwargs) -> LoopResult:
    """One run of a new :class:`Loop` (``model``: the physics' model, None the scene's
    nominal one; ``friction``: the interval the planner and the node assume; ``timeout``:
    wall seconds; other keywords: :class:`Loop`'s).

    Parameters
    ----------
    scene : str, Path or Scene
        The scene, or its YAML file.
    target : sequence of int
        The target fixels (1-based).
    friction : sequence of float or None, optional
        The friction interval (lo, hi) the planner and the node assume.
    model : Model, sequence of float or None, optional
        The physics' model.
    timeout : float, optional
        Wall seconds.
    **kwargs
        Keywords of :class:`Loop`.

    Returns
    -------
    LoopResult
        What the tray saw.
    """
    with Loop(scene, target, friction, **kwargs) as loop:
        return loop.run(model, timeout)


__all__ = ["LOOP_CONTACT_TOLERANCE", "LOOP_SIM_TIMEOUT_S", "Loop", "LoopResult", "closed_loop",
           "node_parameters"]
