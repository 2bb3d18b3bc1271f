# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Executors for programs and tests that spin the node: what :func:`main` uses, and a
spinner thread.

The node itself runs on whatever executor its user adds it to (rclpy's
``SingleThreadedExecutor`` or ``MultiThreadedExecutor``, or :class:`LaneExecutor`); it
owns no executor and no spinning thread. Its callbacks that may run long (a
classification over many modes, force directions) are in :class:`LongRunningGroup`
callback groups, and a plan runs as the action's execute task.

:class:`LaneExecutor`, the one :func:`~.wrenchcone_node.main` uses, hands the callbacks
that may run side by side or long (a ``ReentrantCallbackGroup``'s: check_wrench and
get_cone; a :class:`LongRunningGroup`'s; entity-less tasks such as an action's execute
callback) to a small thread pool, and runs the rest (parameters, lifecycle, inputs) in
its spinning thread, as the ``SingleThreadedExecutor`` does. rclpy's
``MultiThreadedExecutor`` hands every callback to its pool; on a 2-core machine under a
1 kHz pose stream its spinning thread re-yields a handed-over task until a pool thread
has started it, and that loop holds the GIL the pool and the node's publishing worker
wait for (docs/node.md has the figures). :class:`SpinThread` spins some nodes in a
daemon thread (tests, benchmarks, a controller's own process).
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.executors import (
    ConditionReachedException,
    Executor,
    ExternalShutdownException,
    ShutdownException,
    TimeoutException,
)

#: Pool threads of :class:`LaneExecutor` as :func:`make_executor` makes it: a check, one
#: classification, one force-directions request and one plan at once.
EXECUTOR_THREADS = 4

#: Longest wait, in seconds, of the spinning thread for a pool thread to start a task it
#: handed over (then it spins on; the task still runs once).
HANDOVER_TIMEOUT_S = 0.1

#: Seconds the spinning thread then waits for a handed-over ``ReentrantCallbackGroup``
#: callback (a check_wrench, a get_cone) to finish before it spins on. A cheap check
#: (tens of microseconds) finishes within it, and the spinning thread does not rebuild
#: its wait set in Python meanwhile, competing for the GIL with the check; a check that
#: computes long holds the next request up by this much at most.
REENTRANT_WAIT_S = 0.002


class LongRunningGroup(MutuallyExclusiveCallbackGroup):
    """A mutually exclusive callback group whose callbacks may take long (seconds).

    For any executor it is a ``MutuallyExclusiveCallbackGroup``; :class:`LaneExecutor`
    runs its callbacks on its pool instead of its spinning thread."""


class LaneExecutor(Executor):
    """Runs concurrent and long callbacks on a thread pool, the rest in the spinning
    thread.

    A callback of a ``ReentrantCallbackGroup`` (callbacks that may run side by side: one
    check_wrench that computes up to ``max_request_time`` then never holds up another)
    or of a :class:`LongRunningGroup`, or a task with no entity (an action's execute
    callback, a future's done callback), is handed to a pool of ``num_threads`` threads;
    every other callback runs in the thread that spins, one at a time, as rclpy's
    ``SingleThreadedExecutor`` runs it. The spinning thread waits (GIL released)
    until a pool thread has started a task it handed over, so it never re-yields that
    task in a loop, and for a reentrant group's callback up to :data:`REENTRANT_WAIT_S`
    more, until it has finished.

    Parameters
    ----------
    num_threads
        Pool threads: long-running callbacks that may run at once.
    context
        The rclpy context (the default context if None).
    """

    def __init__(self, num_threads: int = EXECUTOR_THREADS, *, context: Any = None) -> None:
        super().__init__(context=context)
        self._pool = ThreadPoolExecutor(num_threads, thread_name_prefix="wrenchcone-long")
        self._handed: set[Any] = set()
        self._handed_lock = threading.Lock()

    @staticmethod
    def runs_long(entity: Any) -> bool:
        """Whether a ready callback goes to the pool: no entity (a task), or an entity
        in a ``ReentrantCallbackGroup`` or a :class:`LongRunningGroup`."""
        return entity is None or isinstance(getattr(entity, "callback_group", None),
                                            (LongRunningGroup, ReentrantCallbackGroup))

    def _hand_over(self, task: Any, wait_s: float = 0.0) -> None:
        with self._handed_lock:
            if task in self._handed:
                return  # re-yielded before its pool thread marked it executing
            self._handed.add(task)
        started, finished = threading.Event(), threading.Event()

        def run() -> None:
            started.set()
            try:
                task()
            finally:
                with self._handed_lock:
                    self._handed.discard(task)
                finished.set()
                self._guard.trigger()  # a task that awaits is yielded again

        self._pool.submit(run)
        if started.wait(HANDOVER_TIMEOUT_S) and wait_s > 0.0:
            finished.wait(wait_s)

    def _spin_once_impl(self, timeout_sec: Any = None,
                        wait_condition: Any = lambda: False) -> None:
        try:
            handler, entity, _node = self.wait_for_ready_callbacks(
                timeout_sec, None, wait_condition)
        except (ShutdownException, ExternalShutdownException, TimeoutException,
                ConditionReachedException):
            return
        if self.runs_long(entity):
            reentrant = isinstance(getattr(entity, "callback_group", None),
                                   ReentrantCallbackGroup)
            self._hand_over(handler, REENTRANT_WAIT_S if reentrant else 0.0)
            return
        handler()
        if handler.exception() is not None:
            raise handler.exception()

    def spin_once(self, timeout_sec: float | None = None) -> None:
        self._spin_once_impl(timeout_sec)

    def spin_once_until_future_complete(self, future: Any, timeout_sec: Any = None) -> None:
        future.add_done_callback(lambda _f: self.wake())
        self._spin_once_impl(timeout_sec, future.done)

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        done = super().shutdown(timeout_sec)
        self._pool.shutdown(wait=False, cancel_futures=True)
        return done


def executor_kind() -> str:
    """The kind of executor :func:`make_executor` makes (for reports)."""
    return "lane"


def make_executor(context: Any = None) -> LaneExecutor:
    """The executor :func:`~.wrenchcone_node.main` spins the node with.

    Parameters
    ----------
    context : rclpy.context.Context or None, optional
        The context (default: rclpy's global one).

    Returns
    -------
    LaneExecutor
        A LaneExecutor with ``EXECUTOR_THREADS`` pool threads.
    """
    return LaneExecutor(EXECUTOR_THREADS, context=context)


def spin(executor: Any, logger: Any = None) -> None:
    """``executor.spin()`` until it is shut down or its context ends, raising nothing:
    an exception out of rclpy's executor while the program ends (entities destroyed
    under it) is expected; at any other time it is logged (``logger``) and spinning goes
    on, so that the node keeps answering.

    Parameters
    ----------
    executor : rclpy.executors.Executor
        The executor.
    logger : object or None, optional
        An rclpy logger for unexpected exceptions (None: end quietly).
    """
    while True:
        try:
            executor.spin()
            return
        except (KeyboardInterrupt, ExternalShutdownException):
            return
        except Exception as exc:  # noqa: BLE001 - the node must not die with its spinner
            if not executor.context.ok() or logger is None:
                return
            logger.error(f"executor: {type(exc).__name__}: {exc} (spinning on)",
                         throttle_duration_sec=5.0)


class SpinThread:
    """``spin(executor)`` of some nodes in a daemon thread; :meth:`stop` ends it.

    Parameters
    ----------
    nodes : list of rclpy.node.Node
        The nodes to spin.
    logger : object or None, optional
        An rclpy logger for unexpected exceptions.
    name : str, optional
        The thread's name.
    context : rclpy.context.Context or None, optional
        The context of a new executor.
    executor : rclpy.executors.Executor or None, optional
        The executor to spin (default: :func:`make_executor`).
    """

    def __init__(self, nodes: list[Any], logger: Any = None, name: str = "spin",
                 context: Any = None, executor: Any = None) -> None:
        self.executor = executor if executor is not None else make_executor(context)
        for node in nodes:
            self.executor.add_node(node)
        self.thread = threading.Thread(target=spin, args=(self.executor, logger),
                                       name=name, daemon=True)
        self.thread.start()

    def stop(self) -> None:
        """Shut the executor down and join the thread (at most a few seconds)."""
        self.executor.shutdown(timeout_sec=2.0)
        if self.thread is not threading.current_thread():
            self.thread.join(timeout=5.0)
