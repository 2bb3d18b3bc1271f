"""Executors and lanes: which thread runs which callback.

The node's callbacks run in two lanes, each one thread with its own executor:

* the FAST lane (the thread that calls :func:`spin`, the process's main thread in
  :func:`~.wrenchcone_node.main`): the fixels subscription, the cheap services
  (``check_wrench``, ``get_cone``; their work is bounded by the ``max_*`` limits), the
  parameter services and the timers;
* the SLOW lane (:class:`SlowLane`, a thread the node starts): the services whose work can
  be long even within their limits (``classify_wrench``, ``force_directions``), hosted
  by a hidden helper node ``_<node>_slow_lane`` under the same names as before
  (``<node>/classify_wrench``). A long classification never holds up a check_wrench.

The publishing worker (a third thread, see wrenchcone_node.py) computes and publishes
the monitored cones. The pose has no callback at all: it is pulled by whoever needs a
snapshot (inputs.PoseInbox).

Executor: rclpy's ``EventsExecutor`` (rclpy.experimental, in Jazzy's rclpy 7.1): its
event queue is C++, so a 1 kHz pose stream costs a callback, not a Python wait-set
rebuild per message. Measured on this 2-core machine, 1 kHz poses and 16 monitored
modes (benchmarks/node_stream.py, docs/node.md): check_wrench p99 128-191 ms on a
4-thread MultiThreadedExecutor, a few ms on the EventsExecutor. Where it is missing, or
with ``WRENCHCONE_EXECUTOR=multi_threaded`` in the environment, the node falls back to
rclpy's MultiThreadedExecutor (:data:`FALLBACK_THREADS` threads).

Known EventsExecutor limits in Jazzy, handled here: coroutine (``async``) callbacks are
not supported (hence a lane, not an awaited thread pool), and ``spin()`` does not return
after ``shutdown()`` from another thread (so :func:`spin` loops over ``spin_once`` with a
stop flag).
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable
from typing import Any

from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.node import Node

try:
    from rclpy.experimental import EventsExecutor
except ImportError:  # an rclpy without it: the multi-threaded fallback
    EventsExecutor = None

#: Environment variable choosing the executor: ``events`` (default where available) or
#: ``multi_threaded``.
EXECUTOR_ENV = "WRENCHCONE_EXECUTOR"
#: Threads of the MultiThreadedExecutor fallback.
FALLBACK_THREADS = 4
#: spin_once timeout (s): how often a spin loop looks at its stop flag.
SPIN_POLL_S = 0.1
#: Executors stopped after their context had shut down (Ctrl-C), kept so that they are
#: never destroyed: the Jazzy EventsExecutor's destructor crashed the process (SIGSEGV or
#: SIGABRT, 4 of 8 Ctrl-C right after start) on events still queued after the shutdown.
#: :func:`~.wrenchcone_node.main` ends the process with ``os._exit`` after a clean
#: shutdown, so they are never finalized either.
_RETIRED: list[Any] = []


def stop_on_signals(stop: threading.Event) -> None:
    """SIGINT and SIGTERM set ``stop`` (main thread only); a second one ends the process
    at once (the default action).

    The node's process uses this instead of rclpy's signal handler, which lets the
    signal raise KeyboardInterrupt wherever the main thread happens to be: inside a
    callback that rclpy's C++ executor is calling, that aborted the process
    (``terminate called after throwing an instance of 'pybind11::error_already_set'``,
    SIGABRT) or left a traceback, 2 of 60 Ctrl-C right after start under load."""
    def handler(signum: int, _frame: Any) -> None:
        stop.set()
        signal.signal(signum, signal.SIG_DFL)

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, handler)


def keep_until_exit(*objects: Any) -> None:
    """Never finalize these objects (see _RETIRED): for a process about to end."""
    _RETIRED.extend(o for o in objects if o is not None)


def retire(executor: Any) -> None:
    """Shut an executor down; after a context shutdown, keep it alive (see _RETIRED)."""
    executor.shutdown()
    if not executor.context.ok():
        keep_until_exit(executor)


def executor_kind() -> str:
    """``events`` or ``multi_threaded``: what :func:`make_executor` makes here."""
    wanted = os.environ.get(EXECUTOR_ENV, "events").strip().lower()
    if wanted not in ("events", "multi_threaded"):
        raise ValueError(f"{EXECUTOR_ENV}={wanted!r}: allowed are 'events' and "
                         "'multi_threaded'")
    return "events" if wanted == "events" and EventsExecutor is not None else "multi_threaded"


def make_executor(context: Any = None) -> Any:
    """The executor one lane of the node runs on (see the module docstring)."""
    if executor_kind() == "events":
        return EventsExecutor(context=context)
    return MultiThreadedExecutor(num_threads=FALLBACK_THREADS, context=context)


def spin(executor: Any, logger: Any, stop: threading.Event | None = None) -> None:
    """Spin until the context shuts down or ``stop`` is set.

    An exception raised inside the executor (a callback's, or rclpy's own, e.g. the
    intermittent ``InvalidHandle: cannot use Destroyable because destruction was
    requested`` of the multi-threaded executor) is logged and spinning goes on: the node
    keeps answering instead of dying."""
    stop = stop or threading.Event()
    while executor.context.ok() and not stop.is_set() \
            and not getattr(executor, "_is_shutdown", False):
        try:
            executor.spin_once(timeout_sec=SPIN_POLL_S)
        except (KeyboardInterrupt, ExternalShutdownException):
            raise
        except Exception as exc:  # noqa: BLE001 - the node must not die
            if not executor.context.ok():
                return
            logger.error(f"executor: {type(exc).__name__}: {exc} (spinning on)",
                         throttle_duration_sec=5.0)


class SpinThread:
    """``spin(executor)`` of some nodes in a daemon thread; :meth:`stop` ends it."""

    def __init__(self, nodes: list[Any], logger: Any, name: str,
                 context: Any = None) -> None:
        self.executor = make_executor(context)
        for node in nodes:
            self.executor.add_node(node)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._run, args=(logger,), name=name,
                                       daemon=True)
        self.thread.start()

    def _run(self, logger: Any) -> None:
        try:
            spin(self.executor, logger, self._stop)
        except ExternalShutdownException:
            pass

    def stop(self) -> None:
        self._stop.set()
        if self.thread is not threading.current_thread():
            self.thread.join()
        retire(self.executor)


class SlowLane:
    """The slow lane: a hidden helper node spun in its own thread (see module docstring).

    Services created with :meth:`create_service` have the absolute name
    ``<owner's fully qualified name>/<name>``, so clients see no difference."""

    def __init__(self, owner: Any) -> None:
        self.owner = owner
        # no global arguments: a `-r __node:=other` for the owner must not rename this
        # node to the same name; namespace and context are the owner's
        self.node = Node(f"_{owner.get_name()}_slow_lane", namespace=owner.get_namespace(),
                         context=owner.context, use_global_arguments=False,
                         start_parameter_services=False, enable_rosout=False)
        self._spinner: SpinThread | None = None

    def create_service(self, srv_type: Any, name: str, callback: Any) -> Any:
        base = self.owner.get_fully_qualified_name()
        return self.node.create_service(srv_type, f"{base}/{name}", callback)

    def start(self) -> None:
        self._spinner = SpinThread([self.node], self.owner.get_logger(),
                                   f"{self.owner.get_name()}-slow-lane", self.owner.context)

    def destroy(self) -> None:
        if self._spinner is not None:
            self._spinner.stop()
            self._spinner = None
        self.node.destroy_node()


def lower_thread_priority(thread: threading.Thread, nice: int,
                          warn: Callable[[str], None]) -> int:
    """Give a started ``thread`` the scheduling niceness ``nice`` (0-19; Linux: per
    thread) and return the niceness it has. The node's publishing worker is its one
    long CPU consumer (about a core under a 1 kHz pose stream with 16 modes); at a
    lower priority it yields the CPU to anything that wakes: the compiled check_wrench
    lane, the fast lane and the other processes of the machine (parameter worker_nice;
    docs/node.md, "Live use under load"). Where that is not allowed, ``warn`` says so
    once and the thread keeps its priority."""
    tid = thread.native_id
    try:
        if nice:
            os.setpriority(os.PRIO_PROCESS, tid, nice)
        return os.getpriority(os.PRIO_PROCESS, tid)
    except (OSError, AttributeError, TypeError) as exc:
        warn(f"worker_nice {nice}: the publishing worker's priority was not changed: {exc}")
        return 0
