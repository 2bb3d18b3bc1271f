# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Executors for programs and tests that spin the node: what :func:`main` uses, and a
spinner thread.

The node itself runs on whatever executor its user adds it to; it owns no executor and
no spinning thread. :func:`make_executor` is the one :func:`~.wrenchcone_node.main` uses
(rclpy's ``MultiThreadedExecutor``: its callback groups let check_wrench be answered
while a classification or a plan runs); :class:`SpinThread` spins some nodes in a daemon
thread (tests, benchmarks, a controller's own process).
"""

from __future__ import annotations

import threading
from typing import Any

from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor

#: Threads of :func:`make_executor`'s executor: the fast services, one slow request, a
#: plan and the parameter and lifecycle services at once.
EXECUTOR_THREADS = 4


def executor_kind() -> str:
    """The kind of executor :func:`make_executor` makes (for reports)."""
    return "multi_threaded"


def make_executor(context: Any = None) -> MultiThreadedExecutor:
    """The executor :func:`~.wrenchcone_node.main` spins the node with."""
    return MultiThreadedExecutor(num_threads=EXECUTOR_THREADS, context=context)


def spin(executor: Any, logger: Any = None) -> None:
    """``executor.spin()`` until it is shut down or its context ends, raising nothing:
    an exception out of rclpy's executor while the program ends (entities destroyed
    under it) is expected; at any other time it is logged (``logger``) and spinning goes
    on, so that the node keeps answering."""
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
    """``spin(executor)`` of some nodes in a daemon thread; :meth:`stop` ends it."""

    def __init__(self, nodes: list[Any], logger: Any = None, name: str = "spin",
                 context: Any = None, executor: Any = None) -> None:
        self.executor = executor if executor is not None else make_executor(context)
        for node in nodes:
            self.executor.add_node(node)
        self.thread = threading.Thread(target=spin, args=(self.executor, logger),
                                       name=name, daemon=True)
        self.thread.start()

    def stop(self) -> None:
        self.executor.shutdown(timeout_sec=2.0)
        if self.thread is not threading.current_thread():
            self.thread.join(timeout=5.0)
