"""The node class: a thin composition of the rooms of this package, and ``main``.

* parameters.py  - declarations, validation, parameter values -> Workpiece / Scene;
* store.py       - the input store (coalescing) and its immutable Snapshot;
* answers.py     - (snapshot, mode) -> Answer, cached in the snapshot; request limits;
* freshness.py   - how old a snapshot's inputs are against their timeouts;
* inputs.py      - the ``fixels`` subscription and the pulled ``workpiece_pose`` (PoseInbox);
* worker.py      - the publishing worker (its own thread; public timing hook ``on_step``);
* fastcheck.py   - the compiled check_wrench lane (src/fastcheck.c): the poses' takes and
  ``~/check_wrench``, answered from the monitored cones or forwarded to services.py;
* services.py    - the service handlers (one stamped reply per snapshot), registration,
  public timing hook ``on_request``;
* publishers.py  - per-snapshot publishers (``~/cone/<mode>``);
* markers.py     - ``~/markers`` (RViz MarkerArray) from the core's drawing geometry;
* diagnostics.py - ``/diagnostics`` at ``diagnostics_rate``, request counts;
* executors.py   - the executors and lanes (which thread runs which callback).

Threading model (executors.py): the fast lane (the thread that spins the node: fixels,
get_cone, parameters, timers) and the slow lane (its own thread: classify_wrench,
force_directions) each run one executor; check_wrench is the compiled lane's (a C
thread, and a Python thread for what it forwards: fastcheck.py); the publishing worker
(worker.py) is a thread of its own, at the scheduling niceness ``worker_nice``.
"""

from __future__ import annotations

import atexit
import gc
import os
import sys
import threading
import weakref
from collections.abc import Callable
from typing import Any

import rclpy
from rcl_interfaces.msg import SetParametersResult
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions

from wrenchcone_ros.core import SceneError, batch
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.node import fastcheck
from wrenchcone_ros.node import parameters as params
from wrenchcone_ros.node.answers import Answer, Limits, cached_answer
from wrenchcone_ros.node.answers import classifier as snapshot_classifier
from wrenchcone_ros.node.diagnostics import Diagnostics, RequestCounts
from wrenchcone_ros.node.executors import (
    SlowLane,
    executor_kind,
    keep_until_exit,
    lower_thread_priority,
    make_executor,
    retire,
    spin,
    stop_on_signals,
)
from wrenchcone_ros.node.inputs import InputSubscriptions
from wrenchcone_ros.node.markers import MarkerPublisher
from wrenchcone_ros.node.plan_action import start_plan_lane
from wrenchcone_ros.node.freshness import Freshness, freshness
from wrenchcone_ros.node.publishers import ConePublishers, SnapshotPublisher
from wrenchcone_ros.node.services import (
    SERVICES,
    RequestTiming,
    monitored_directions,
    register_services,
)
from wrenchcone_ros.node.status import SCENE_ERROR
from wrenchcone_ros.node.store import InputStore, Snapshot
from wrenchcone_ros.node.worker import PublishWorker, StepTiming

NODE_NAME = "wrenchcone"
#: Python's GIL switch interval (s) set by :func:`main`: a service thread waits at most
#: about this long for the GIL while the worker computes cones (the default is 5 ms).
SWITCH_INTERVAL_S = 0.001


#: Nodes started and not destroyed yet; :func:`_destroy_live_nodes` ends them at exit.
_LIVE_NODES: weakref.WeakSet = weakref.WeakSet()


@atexit.register
def _destroy_live_nodes() -> None:
    """At interpreter exit, destroy every node its program did not destroy (one that
    raised, say): finalized with the interpreter, the node's threads (its executors' C++
    threads among them) aborted the process ("terminate called without an active
    exception", status 134), hiding the program's own error. rclpy registers no exit
    handler of its own; a program's handlers registered after this import run before
    this one (last in, first out), so they still see the node alive."""
    for node in list(_LIVE_NODES):
        try:
            node.destroy_node()
        except Exception:  # noqa: BLE001 - at exit: end the others regardless
            pass


class WrenchConeNode(Node):
    """The wrench-cone node; see the package docstring and docs/node.md."""

    def __init__(self, node_name: str = NODE_NAME, freeze_start_up: bool = False,
                 on_step: Callable[[StepTiming], None] | None = None,
                 on_request: Callable[[RequestTiming], None] | None = None,
                 **kwargs: Any) -> None:
        """``freeze_start_up``: when ready, move every object alive to the garbage
        collector's permanent generation (:func:`freeze_start_up_objects`; the program
        does, a node made inside another program does not). ``on_step``: the publishing
        worker's timing hook (:attr:`.worker.PublishWorker.on_step`, also
        ``node.worker.on_step``); ``on_request``: the services' timing hook
        (:attr:`on_request`)."""
        super().__init__(node_name, **kwargs)
        #: Called after each service reply computed in Python with its
        #: :class:`~.services.RequestTiming` (None: nothing is called).
        self.on_request = on_request
        self._ready = False
        # load the compiled cone kernel now (from numba's cache; compiled by `make build`)
        # so that the first pose is not the one that pays
        self._warm_up_s = batch.warm_up()
        base = params.declare_parameters(self)
        values = self._values()
        try:  # the start-up values get the same checks as any later change
            params.validate_values(values, self._topic_error)
        except (SceneError, ValueError, TypeError) as exc:
            raise SceneError(f"parameters: {exc}") from None
        self.store = InputStore(base, values)
        start = self.store.current()  # the scene file and parameters, before any message
        if start.status == SCENE_ERROR:  # main(): one line, exit 2
            raise SceneError(f"start: {start.message}")
        self._apply(values)
        self.request_counts = RequestCounts()  # services.py records every reply
        self.diagnostics = Diagnostics(self, self.request_counts)
        #: Everything published per snapshot; each gets the same monitored answers. The
        #: first (the cone topics) is published before the compiled lane is offered the
        #: cones (PublishWorker.publish).
        #: The markers draw each monitored mode's force fan at the com from the same
        #: per-snapshot cache and classifier as ~/force_directions.
        self.snapshot_publishers: list[SnapshotPublisher] = [
            ConePublishers(self), MarkerPublisher(self, monitored_directions),
            self.diagnostics]

        self.add_pre_set_parameters_callback(params.coerce_types)
        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._parameters_changed)

        self.worker: PublishWorker | None = None
        self.inputs = InputSubscriptions(self, self.store, self._wake_worker)
        self.worker = PublishWorker(self, self.inputs.pose_inbox, on_step)
        #: The compiled check_wrench lane (fastcheck.py): takes the poses, answers
        #: check_wrench from the monitored cones the worker offers it
        self.lane = self.inputs.pose_inbox.lane
        fastcheck.configure(self.lane, values)
        self.store.on_inputs_changed = self.lane.clear
        self.request_counts.compiled = self.lane.stats if self.lane else None
        self.slow_lane = SlowLane(self)
        self.service_groups = register_services(self, SERVICES,
                                                self.slow_lane, self.lane)
        self._sync_publishers()
        self._ready = True
        generation = self.lane.generation()  # before the inputs are read
        snap = self.snapshot
        self.worker.publish(snap, generation)  # latched topics get the start-up cones at once
        self.worker.start()
        worker_nice = lower_thread_priority(self.worker.thread, values["worker_nice"],
                                            self.get_logger().warning)
        self.slow_lane.start()
        self.plan_lane = start_plan_lane(self)  # ~/plan_seating (plan_action.py)
        self._destroyed = False
        _LIVE_NODES.add(self)
        frozen = (f"; {freeze_start_up_objects()} start-up objects frozen for the garbage "
                  "collector" if freeze_start_up else "")
        self.get_logger().info(
            f"ready: {snap.scene.n_fixels if snap.scene else '?'} fixel(s), frame "
            f"{self._p('fixture_frame')!r}, monitoring modes {values['modes']}; cone engine "
            f"{batch.resolve_engine()} (loaded in {self._warm_up_s:.2f} s); executor "
            f"{executor_kind()}; publishing worker at nice {worker_nice}{frozen}")

    def destroy_node(self) -> None:
        if not hasattr(self, "_destroyed"):  # start-up failed: no threads to stop
            return super().destroy_node()
        if self._destroyed:  # at most once (the program, then _destroy_live_nodes)
            return None
        self._destroyed = True
        _LIVE_NODES.discard(self)
        self.inputs.pose_inbox.close()
        self.worker.stop()
        self.inputs.destroy()
        self.slow_lane.destroy()
        self.plan_lane.destroy()
        super().destroy_node()

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
        if not self._ready:  # during __init__'s declarations
            return
        try:
            names = {p.name for p in parameters} & set(params.PARAMETERS)
            if not names:
                return
            values = self._values()
            self._apply(values)
            fastcheck.configure(self.lane, values)
            if names & {"modes", "publish_markers", "diagnostics_rate"}:
                self._sync_publishers()
            self.store.set_values(values, radius_overridden="fixel_radius" in names)
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
        one when the newest pose is within ``pose_reuse_window`` of its pose."""
        return self.store.current(self.pose_reuse_window_ns)

    def freshness(self, snap: Snapshot) -> Freshness:
        """How old the snapshot's inputs are now (node clock: respects use_sim_time)."""
        return freshness(snap, self.get_clock().now().nanoseconds, self.input_timeout,
                         self.fixels_timeout)

    def answer(self, snapshot: Snapshot, mode: str) -> Answer:
        """Cached answer of (snapshot, mode): each is computed at most once."""
        return cached_answer(snapshot, mode, self.get_logger().error, self.limits)

    def classifier(self, snapshot: Snapshot) -> ModeClassifier:
        """The snapshot's mode classifier (created once, caches its cones)."""
        return snapshot_classifier(snapshot)

    def serving(self):
        """Marks a fast-lane request in progress: the publishing worker waits for it."""
        return self.worker.serving()

    # --- publishing -------------------------------------------------------------------
    def _wake_worker(self) -> None:
        if self.worker is not None:
            self.worker.wake()

    def _sync_publishers(self) -> None:
        values = self._values()
        for pub in self.snapshot_publishers:
            pub.sync(values)


def freeze_start_up_objects() -> int:
    """Collect once, then move every object alive to the garbage collector's permanent
    generation (``gc.freeze``); returns how many. A full collection then scans only what
    was made later, not the ~150,000 objects of rclpy, numpy, numba and the node made at
    start: in a 3,000-input fuzz run in one process, five full collections took 388 ms
    (the longest 103 ms, a pause for every thread) against 13 ms (4.9 ms) after a freeze.
    """
    gc.collect()
    gc.freeze()
    return gc.get_freeze_count()


def main(args: list[str] | None = None,
         configure: Callable[[WrenchConeNode], None] | None = None) -> int:
    """Console entry point ``wrenchcone_node`` (``ros2 run wrenchcone_ros wrenchcone_node``).

    A start-up configuration that is wrong (scene_file, a parameter value or type) exits
    with status 2 and one log line; nothing else ends the node but a shutdown.
    ``configure(node)``, if given, is called once the node is built and before it is
    spun (benchmarks set the timing hooks ``node.worker.on_step`` and
    ``node.on_request`` there)."""
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    stop = threading.Event()
    stop_on_signals(stop)  # Ctrl-C and SIGTERM end the spin below, raising nothing
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    node = None
    try:
        executor = make_executor()
    except ValueError as exc:  # a bad WRENCHCONE_EXECUTOR: one line, exit 2
        rclpy.logging.get_logger(NODE_NAME).fatal(str(exc))
        rclpy.try_shutdown()
        return 2
    try:
        try:
            node = WrenchConeNode(freeze_start_up=True)
        except Exception as exc:  # noqa: BLE001 - a bad configuration: one line, exit 2
            text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            if not isinstance(exc, SceneError):
                text = f"bad start-up configuration: {text}"
            rclpy.logging.get_logger(NODE_NAME).fatal(text)
            return 2
        if configure is not None:
            configure(node)
        executor.add_node(node)
        spin(executor, node.get_logger(), stop)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        retire(executor)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
        # the process ends next (run(): os._exit): never finalize the executor or the
        # node. retire() keeps an executor only if the context was already shut down;
        # when Ctrl-C came before that, this frame's exit finalized the executor after
        # try_shutdown and crashed the process (SIGSEGV, 1 in 30 tries under load)
        keep_until_exit(executor, node)
    return 0


def run(args: list[str] | None = None,
        configure: Callable[[WrenchConeNode], None] | None = None) -> None:
    """``main(args, configure)``, then end the process at once (``os._exit``) with its
    status: after a clean shutdown nothing is left to finalize, and finalizing rclpy's
    EventsExecutor after a Ctrl-C could crash the process (see executors._RETIRED)."""
    code = main(args, configure)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
