# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node class, a managed (lifecycle) node, and the program's ``main``.

:class:`WrenchConeNode` is a ``rclpy.lifecycle.LifecycleNode`` that a user constructs in
their own process and adds to any executor (``SingleThreadedExecutor``,
``MultiThreadedExecutor``); it changes no process-wide state. Its pieces, one module per
concern:

* parameters.py  - the parameters' schema, declarations, validation, -> Workpiece / Scene;
* store.py       - the input store (coalescing) and its immutable Snapshot;
* answers.py     - (snapshot, mode) -> Answer, cached in the snapshot; request limits;
* freshness.py   - how old a snapshot's inputs are against their timeouts;
* inputs.py      - the ``workpiece_pose`` and ``fixels`` subscriptions;
* worker.py      - the publishing worker (its own thread; public timing hook ``on_step``);
* services.py    - the service handlers (one stamped reply per snapshot), registration,
  public timing hook ``on_request``;
* lane.py        - the request lane that serves check_wrench and get_cone;
* plan_action.py - the ``~/plan_seating`` action;
* publishers.py, markers.py, diagnostics.py - what is published per snapshot.

Lifecycle (REP-2002 states): construction declares the parameters; ``configure`` reads
and checks them, loads the scene and creates the subscriptions, services, the action and
the publishers, its timers stopped; ``activate`` starts the publishing worker, the
node's timers and the answers; ``deactivate`` stops them all (nothing is published,
every service answers NOT_ACTIVE, the action rejects goals, and a running plan is
stopped: its goal ends ABORTED, status CANCELED, before deactivate returns);
``cleanup`` destroys what configure created; ``shutdown`` ends it all. Every transition
also calls the base class's (rclpy's managed entities). With parameter
``autostart`` (default true) the node configures and activates itself at construction,
so that ``ros2 run`` gives a working node.

Threads: every callback runs on the executor that spins the node, but for the fast
services' (check_wrench, get_cone): with parameter ``request_lane`` (default true) the
node's request lane answers them from a thread of its own (lane.py), from configure to
cleanup. Callback groups let a multi-threaded executor answer a classification, a
force-directions request and a plan side by side (services.py, plan_action.py). The
node's own threads: the request lane and its pool, the publishing worker, and while a
plan runs its Monte Carlo worker processes.
"""

from __future__ import annotations

import atexit
import gc
import signal
import sys
import threading
import warnings
import weakref
from collections.abc import Callable
from typing import Any

import rclpy
from rcl_interfaces.msg import SetParametersResult
from rclpy.executors import ExternalShutdownException
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions

from wrenchcone_ros.core import SceneError, engines
from wrenchcone_ros.core.geometry import UnverifiedRangeWarning
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.node import parameters as params
from wrenchcone_ros.node import rclpy_boundary
from wrenchcone_ros.node.answers import Answer, Limits, cached_answer
from wrenchcone_ros.node.answers import classifier as snapshot_classifier
from wrenchcone_ros.node.diagnostics import Diagnostics, RequestCounts
from wrenchcone_ros.node.executors import make_executor, spin
from wrenchcone_ros.node.freshness import Freshness, freshness
from wrenchcone_ros.node.inputs import InputSubscriptions
from wrenchcone_ros.node.markers import MarkerPublisher
from wrenchcone_ros.node.parameter_files import misaddressed_params_files
from wrenchcone_ros.node.plan_action import PlanAction
from wrenchcone_ros.node.publishers import ConePublishers, SnapshotPublisher
from wrenchcone_ros.node.services import (
    SERVICES,
    RequestTiming,
    monitored_directions,
    lane_services,
    register_services,
)
from wrenchcone_ros.node.status import SCENE_ERROR
from wrenchcone_ros.node.store import InputStore, Snapshot
from wrenchcone_ros.node.lane import RequestLane, answers_at_once
from wrenchcone_ros.node.worker import PublishWorker, StepTiming, lower_thread_priority

NODE_NAME = "wrenchcone"
SUCCESS, FAILURE = TransitionCallbackReturn.SUCCESS, TransitionCallbackReturn.FAILURE
#: Python's GIL switch interval (s) that :func:`main` sets for its process: a service
#: thread waits at most about this long for the GIL while the worker computes cones (the
#: interpreter's default is 5 ms). A node made inside another program leaves it alone.
SWITCH_INTERVAL_S = 0.001


#: Nodes made and not destroyed yet; :func:`_destroy_live_nodes` ends them at exit.
_LIVE_NODES: weakref.WeakSet = weakref.WeakSet()


@atexit.register
def _destroy_live_nodes() -> None:
    """At interpreter exit, destroy every node its program did not destroy (one that
    raised, say): its publishing worker, blocked in a wait set, was otherwise finalized
    with the interpreter and aborted the process ("terminate called without an active
    exception", status 134), hiding the program's own error. Only this module's nodes
    are touched; a program's handlers registered after this import run first."""
    for node in list(_LIVE_NODES):
        try:
            node.destroy_node()
        except Exception:  # noqa: BLE001 - at exit: end the others regardless
            pass


class StartError(SceneError):
    """The node could not configure itself at construction (autostart); the message is
    the one line saying why."""


class WrenchConeNode(LifecycleNode):
    """The wrench-cone node; see the module docstring and docs/node.md.

    Parameters
    ----------
    node_name
        The node's name (a ``-r __node:=...`` remap still applies).
    autostart
        Configure and activate at construction; None (default): parameter ``autostart``.
    on_step, on_request
        Timing hooks of the publishing worker (:class:`~.worker.StepTiming`) and of every
        service reply (:class:`~.services.RequestTiming`); benchmarks use them.
    **kwargs
        Passed to ``rclpy.node.Node`` (``namespace``, ``context``, ``parameter_overrides``,
        ``cli_args``, ...).

    Raises
    ------
    StartError
        With autostart, when the configuration is wrong (scene_file, a parameter value);
        the node is destroyed first.
    """

    def __init__(self, node_name: str = NODE_NAME, *, autostart: bool | None = None,
                 on_step: Callable[[StepTiming], None] | None = None,
                 on_request: Callable[[RequestTiming], None] | None = None,
                 **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        #: Called after each service reply with its RequestTiming (None: nothing).
        self.on_request = on_request
        self._on_step = on_step
        self.active = False
        self.state_label = "unconfigured"
        self.store: InputStore | None = None
        self.worker: PublishWorker | None = None
        self.inputs: InputSubscriptions | None = None
        self.endpoints: dict[str, Any] = {}
        self.lane: RequestLane | None = None
        self.plan_action: PlanAction | None = None
        self.snapshot_publishers: list[SnapshotPublisher] = []
        self.request_counts = RequestCounts()
        self.start_error = ""
        self._starting = False
        self._destroyed = False
        _LIVE_NODES.add(self)
        try:
            self._base = params.declare_parameters(self)
        except SceneError as exc:  # scene_file: one line
            self._abandon()
            raise StartError(str(exc)) from None
        except Exception:
            self._abandon()
            raise
        self.add_pre_set_parameters_callback(params.coerce_types)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._parameters_changed)
        if autostart is None:
            autostart = bool(self._p("autostart")) if "autostart" in params.PARAMETERS \
                else True
        if autostart:
            self._starting = True  # a failure is raised (StartError), not logged here
            if self.trigger_configure() != SUCCESS or self.trigger_activate() != SUCCESS:
                why = self.start_error or "configure or activate failed"
                self.destroy_node()
                raise StartError(why)
            self._starting = False

    def _abandon(self) -> None:
        """Destroy a node whose construction failed before anything was configured."""
        self._destroyed = True
        _LIVE_NODES.discard(self)
        rclpy_boundary.release_lifecycle_state_machine(self)
        super().destroy_node()

    # --- lifecycle ------------------------------------------------------------------
    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Read and check the parameters, build the input store, create the endpoints.

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS, or FAILURE for a bad configuration (``start_error`` says why, in one
            line).
        """
        try:
            values = self._values()
            params.validate_values(values, self._topic_error)
            store = InputStore(self._base, values)
            store.workpiece_given = bool(values["scene_file"]) or any(
                name.startswith("workpiece.")
                for name in rclpy_boundary.parameter_overrides(self))
            start = store.current()
            if start.status == SCENE_ERROR:
                raise SceneError(f"start: {start.message}")
        except Exception as exc:  # noqa: BLE001 - a bad configuration: one line, FAILURE
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            self.start_error = (text if isinstance(exc, SceneError)
                                else f"bad configuration: {text}")
            if not self._starting:
                self.get_logger().error(f"configure failed: {self.start_error}")
            return FAILURE
        self.store = store
        self._apply(values)
        self.request_counts = RequestCounts()
        self.diagnostics = Diagnostics(self, self.request_counts)
        self.snapshot_publishers = [ConePublishers(self),
                                    MarkerPublisher(self, monitored_directions),
                                    self.diagnostics]
        self.inputs = InputSubscriptions(self, store, self._wake_worker)
        use_lane = bool(values["request_lane"]) and rclpy_boundary.lane_available()
        self.endpoints = register_services(self, SERVICES, lane=use_lane)
        fast = lane_services(self.endpoints)
        if fast:
            self.lane = RequestLane(self.context, fast, lambda req: answers_at_once(self, req),
                                    self.get_logger().error)
        self.plan_action = PlanAction(self)
        self._sync_publishers()
        self._stop_timers()  # inactive: nothing runs until activate
        self.state_label = "inactive"
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Start the publishing worker and publish the current cones on the latched topics.

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS, or the base class's FAILURE (a managed entity's).
        """
        base = super().on_activate(state)
        if base != SUCCESS:
            return base
        self.worker = PublishWorker(self, self.inputs.pose_slot, self._on_step)
        self.plan_action.activate()
        self.active = True
        self.state_label = "active"
        snap = self.snapshot
        self.worker.publish(snap)  # latched topics get the current cones at once
        self.worker.start()
        nice = lower_thread_priority(self.worker.thread, self.store.values["worker_nice"],
                                     self.get_logger().warning)
        missing = "" if snap.scene is not None else f" ({snap.message})"
        self.get_logger().info(
            f"ready: active, {self._scene_summary(snap)}{missing}; frame "
            f"{self._p('fixture_frame')!r}, monitoring modes {self.store.values['modes']}; "
            f"cone engine {engines.resolve_engine()}; publishing worker at nice {nice}")
        for timer in self.timers:
            timer.reset()
        return SUCCESS

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop the publishing worker, every timer and a running plan (its goal ends
        ABORTED, status CANCELED, before this returns); the services answer NOT_ACTIVE
        and goals are rejected until reactivated.

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS.
        """
        self.active = False
        self.state_label = "inactive"
        self._stop_worker()
        self._stop_timers()
        if self.plan_action is not None:
            self.plan_action.deactivate()
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Destroy the endpoints and the input store that on_configure created.

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS.
        """
        self._release()
        self.state_label = "unconfigured"
        return super().on_cleanup(state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop the worker and destroy the endpoints (finalized).

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS.
        """
        self.active = False
        self._release()
        self.state_label = "finalized"
        return super().on_shutdown(state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Stop the worker and destroy the endpoints after an error in a transition.

        Parameters
        ----------
        state : LifecycleState
            The state the transition starts from.

        Returns
        -------
        TransitionCallbackReturn
            SUCCESS (back to unconfigured).
        """
        self.active = False
        self._release()
        self.state_label = "unconfigured"
        return SUCCESS

    def _stop_timers(self) -> None:
        """Cancel every timer of the node (a cancelled timer never wakes the executor);
        activate resets them."""
        for timer in self.timers:
            timer.cancel()

    def _stop_worker(self) -> None:
        if self.worker is not None:
            self.worker.stop()
            self.worker = None

    def _release(self) -> None:
        """Destroy what on_configure created (after stopping the worker)."""
        self._stop_worker()
        if self.plan_action is not None:
            self.plan_action.destroy()
            self.plan_action = None
        if self.lane is not None:
            self.lane.stop()
            self.lane = None
        for srv in self.endpoints.values():
            self.destroy_service(srv)
        self.endpoints = {}
        if self.inputs is not None:
            self.inputs.destroy()
            self.inputs = None
        for pub in self.snapshot_publishers:
            pub.destroy()
        self.snapshot_publishers = []
        self.store = None

    def destroy_node(self) -> None:  # passes rclpy's result on: numpydoc ignore=RT01
        """Stop the worker, destroy the endpoints and the lifecycle state machine, then the node
        (at most once; later calls do nothing).
        """
        if self._destroyed:  # at most once
            return None
        self._destroyed = True
        _LIVE_NODES.discard(self)
        self.active = False
        self._release()
        rclpy_boundary.release_lifecycle_state_machine(self)
        return super().destroy_node()

    @staticmethod
    def _scene_summary(snap: Snapshot) -> str:
        if snap.scene is None:
            return "no scene yet"
        return f"{snap.scene.n_fixels} fixel(s)"

    # --- parameters -----------------------------------------------------------------
    def _p(self, name: str) -> Any:
        return params.parameter_value(self, name)

    def _values(self, overrides: dict[str, Any] | None = None) -> dict[str, Any]:
        return params.read_values(self, overrides)

    def _apply(self, values: dict[str, Any]) -> None:
        self.out_of_plane_tolerance = values["out_of_plane_tolerance"]
        self.input_timeout = values["input_timeout"]
        self.max_publish_rate = values["max_publish_rate"]
        self.pose_reuse_window_ns = round(values["pose_reuse_window"] * 1e9)
        self.fixels_timeout = values["fixels_timeout"]
        self.limits = Limits(values["max_mode_length"], values["max_concrete_modes"],
                             values["max_classify_nodes"], values["max_request_time"])

    def _topic_error(self, mode: str) -> str | None:
        try:
            self.resolve_topic_name(f"~/cone/{mode}")
        except Exception as exc:  # noqa: BLE001 - any rcl refusal is a reason
            return str(exc).splitlines()[0][:200]
        return None

    def _validate_parameters(self, parameters: list[Parameter]) -> SetParametersResult:
        """Refuse values that cannot make a scene, whatever the pose and fixels."""
        try:
            params.validate_values(self._values({p.name: p.value for p in parameters}),
                                   self._topic_error)
        except (SceneError, ValueError, TypeError) as exc:
            return SetParametersResult(successful=False, reason=str(exc)[:1000])
        except Exception as exc:  # noqa: BLE001 - a parameter set must never kill the node
            return SetParametersResult(successful=False,
                                       reason=f"{type(exc).__name__}: {exc}"[:1000])
        return SetParametersResult(successful=True)

    def _parameters_changed(self, parameters: list[Parameter]) -> None:
        if self.store is None:  # not configured: configure reads them
            return
        try:
            names = {p.name for p in parameters} & set(params.PARAMETERS)
            if not names:
                return
            values = self._values()
            self._apply(values)
            if names & {"modes", "publish_markers", "diagnostics_rate"}:
                self._sync_publishers()
            if any(name.startswith("workpiece.") for name in names):
                self.store.workpiece_given = True
            self.store.set_values(values)
            self._wake_worker()
        except Exception as exc:  # noqa: BLE001 - a parameter set must never kill the node
            self.get_logger().error(f"applying parameters failed: {exc!r}")

    # --- snapshots -------------------------------------------------------------------
    @property
    def snapshot(self) -> Snapshot:
        """The newest snapshot (built now if the inputs changed since the last one)."""
        return self.store.current()

    def request_snapshot(self) -> Snapshot:
        """The snapshot a service request is answered from: the newest, or the current
        one when the newest pose is within ``pose_reuse_window`` of its pose.

        Returns
        -------
        Snapshot
            The snapshot.
        """
        return self.store.current(self.pose_reuse_window_ns)

    def freshness(self, snap: Snapshot) -> Freshness:
        """How old the snapshot's inputs are now (node clock: respects use_sim_time).

        Parameters
        ----------
        snap : Snapshot
            The snapshot.

        Returns
        -------
        Freshness
            The ages of its pose and fixels, and whether they are stale.
        """
        return freshness(snap, self.get_clock().now().nanoseconds, self.input_timeout,
                         self.fixels_timeout)

    def answer(self, snapshot: Snapshot, mode: str) -> Answer:
        """Cached answer of (snapshot, mode): each is computed at most once.

        Parameters
        ----------
        snapshot : Snapshot
            The snapshot.
        mode : str
            The mode, wildcards allowed.

        Returns
        -------
        Answer
            The answer (a status and a message for bad input).
        """
        return cached_answer(snapshot, mode, self.get_logger().error, self.limits)

    def classifier(self, snapshot: Snapshot) -> ModeClassifier:
        """The snapshot's mode classifier (created once, caches its cones).

        Parameters
        ----------
        snapshot : Snapshot
            The snapshot.

        Returns
        -------
        ModeClassifier
            Its classifier.
        """
        return snapshot_classifier(snapshot)

    def serving(self):
        """Marks a fast request in progress: the publishing worker waits for it.

        Returns
        -------
        contextlib.AbstractContextManager
            A context manager held while the request is served.
        """
        worker = self.worker
        if worker is None:
            return _NO_WAIT
        return worker.serving()

    # --- publishing -------------------------------------------------------------------
    def _wake_worker(self) -> None:
        worker = self.worker
        if worker is not None:
            worker.wake()

    def _sync_publishers(self) -> None:
        values = self._values()
        for pub in self.snapshot_publishers:
            pub.sync(values)


class _NoWait:
    """A context manager that does nothing (no worker to hold back)."""

    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: Any) -> None:
        return None


_NO_WAIT = _NoWait()


def freeze_start_up_objects() -> int:
    """Collect once, then move every object alive to the garbage collector's permanent
    generation (``gc.freeze``); returns how many. A full collection then scans only what
    was made later, not the objects of rclpy, numpy, numba and the node made at start.
    For a program's ``main`` (process-wide), never for a node inside another program."""
    gc.collect()
    gc.freeze()
    return gc.get_freeze_count()


def main(args: list[str] | None = None,
         configure: Callable[[WrenchConeNode], None] | None = None,
         executor_factory: Callable[[], Any] = make_executor) -> int:
    """Console entry point ``wrenchcone_node`` (``ros2 run wrenchcone_ros wrenchcone_node``).

    The program, not the node, tunes its process: the GIL switch interval
    (:data:`SWITCH_INTERVAL_S`) and a garbage-collector freeze of the start-up objects.
    It spins the node with ``executor_factory()``: by default
    :func:`~.executors.make_executor`'s :class:`~.executors.LaneExecutor` (benchmarks
    pass rclpy's executors to compare).
    A start-up configuration that is wrong (scene_file, a parameter value or type) exits
    with status 2 and one log line; SIGINT / SIGTERM end it with status 0.
    ``configure(node)``, if given, is called once the node is built and before it is
    spun (benchmarks set the timing hooks there).

    Parameters
    ----------
    args : list of str or None, optional
        Command-line arguments for rclpy (default: the process's).
    configure : callable or None, optional
        Called with the node before it is spun.
    executor_factory : callable, optional
        Makes the executor the node is spun with.

    Returns
    -------
    int
        The exit status: 0, or 2 for a wrong start-up configuration.
    """
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = threading.Event()

    def on_signal(signum: int, _frame: Any) -> None:
        stop.set()
        signal.signal(signum, signal.SIG_DFL)  # a second signal ends the process at once

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, on_signal)
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    # the node logs a workpiece outside the verified range itself (once per workpiece)
    warnings.filterwarnings("ignore", category=UnverifiedRangeWarning)
    node = None
    spinner = None
    executor = executor_factory()
    try:
        try:
            node = WrenchConeNode()
        except Exception as exc:  # noqa: BLE001 - a bad configuration: one line, exit 2
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            if not isinstance(exc, SceneError):
                text = f"bad start-up configuration: {text}"
            rclpy.logging.get_logger(NODE_NAME).fatal(text)
            return 2
        for line in misaddressed_params_files(sys.argv if args is None else args,
                                              node.get_name(), node.get_namespace()):
            node.get_logger().warning(line)
        frozen = freeze_start_up_objects()
        node.get_logger().info(
            f"program: {type(executor).__name__}; {frozen} "
            "start-up objects frozen for the garbage collector")
        if configure is not None:
            configure(node)
        executor.add_node(node)
        logger = node.get_logger()

        def spin_until_stopped() -> None:
            try:
                spin(executor, logger)
            finally:
                stop.set()  # the executor ended: so does the program

        spinner = threading.Thread(target=spin_until_stopped, name="wrenchcone-spin",
                                   daemon=True)
        spinner.start()
        # no polling: a signal (its handler runs in this thread) or the spinner's end
        # sets ``stop``; an idle program's main thread never wakes up
        stop.wait()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown(timeout_sec=5.0)
        if spinner is not None:
            spinner.join(5.0)  # before the node's entities are destroyed under it
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


def run(args: list[str] | None = None,
        configure: Callable[[WrenchConeNode], None] | None = None,
        executor_factory: Callable[[], Any] = make_executor) -> None:
    """``main(args, configure, executor_factory)``, then exit with its status.

    Parameters
    ----------
    args : list of str or None, optional
        Command-line arguments for rclpy (default: the process's).
    configure : callable or None, optional
        Called with the node before it is spun.
    executor_factory : callable, optional
        Makes the executor the node is spun with.
    """
    code = main(args, configure, executor_factory)
    sys.stdout.flush()
    sys.stderr.flush()
    sys.exit(code)
