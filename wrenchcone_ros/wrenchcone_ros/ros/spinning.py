# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An rclpy executor spinning some nodes in a background thread (tests, the in-process
closed loop of :mod:`wrenchcone_ros.sim`).
"""

from __future__ import annotations

import threading
import traceback
from pathlib import Path

import rclpy
from rclpy.context import Context
from rclpy.executors import Executor, SingleThreadedExecutor
from rclpy.node import Node


class ExecutorThread:
    """An rclpy executor spinning some nodes in a background thread.

    Parameters
    ----------
    context : rclpy.context.Context
        The nodes' context.
    executor : type, optional
        The executor class, called as ``executor(context=context)``; default
        ``SingleThreadedExecutor`` (a ``MultiThreadedExecutor`` works the same).
    name : str
        The thread's name.

    Attributes
    ----------
    executor : rclpy.executors.Executor
        The executor; add nodes with :meth:`add_node`.
    error : BaseException or None
        What ended the spinning thread early (an exception raised out of the executor:
        a callback's), or None.
    shutdown_race : BaseException or None
        The exception rclpy's own executor raised while :meth:`stop` was shutting it
        down (:func:`is_rclpy_shutdown_race`), or None: not an error of the nodes.
    """

    def __init__(self, context: Context, executor: type[Executor] | None = None,
                 name: str = "wrenchcone-test-executor") -> None:
        self.executor = (executor or SingleThreadedExecutor)(context=context)
        self.error: BaseException | None = None
        self.shutdown_race: BaseException | None = None
        self._stopping = threading.Event()
        self.thread = threading.Thread(target=self._spin, name=name, daemon=True)
        self.thread.start()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except rclpy.executors.ExternalShutdownException:
            pass
        except BaseException as exc:  # noqa: BLE001 - reported by stop()
            if self._stopping.is_set() and is_rclpy_shutdown_race(exc):
                self.shutdown_race = exc
            else:
                self.error = exc

    def add_node(self, node: Node) -> None:
        """Spin ``node`` too (from now on).

        Parameters
        ----------
        node : rclpy.node.Node
            A node of the thread's context.
        """
        self.executor.add_node(node)

    def stop(self, timeout: float = 10.0) -> None:
        """Shut the executor down and join its thread.

        Parameters
        ----------
        timeout : float
            Seconds to wait for the thread.

        Raises
        ------
        RuntimeError
            The thread is still running after ``timeout`` s, or it had ended with an
            exception (chained).
        """
        self._stopping.set()
        self.executor.shutdown(timeout_sec=timeout)
        self.thread.join(timeout)
        if self.thread.is_alive():
            raise RuntimeError(f"the executor thread {self.thread.name} did not stop "
                               f"within {timeout} s")
        if self.error is not None:
            raise RuntimeError(f"the executor spinning the node raised "
                               f"{type(self.error).__name__}: {self.error}") from self.error


def is_rclpy_shutdown_race(exc: BaseException) -> bool:
    """Whether ``exc`` is rclpy's executor tripping over its own shutdown.

    Jazzy's executor may raise ``AttributeError: 'NoneType' object has no attribute
    'trigger'`` from a handler it made for an entity that became ready just before
    ``shutdown`` (the handler's guard condition is None on that path; ros2/rclpy's
    open shutdown-race reports). Recognised by its type and by the innermost frame being
    in rclpy's ``executors.py``; only :meth:`ExecutorThread.stop` lets it pass.

    Parameters
    ----------
    exc : BaseException
        What the spinning thread raised.

    Returns
    -------
    bool
        True for that race only.
    """
    frames = traceback.extract_tb(exc.__traceback__)
    return (isinstance(exc, AttributeError) and bool(frames)
            and Path(frames[-1].filename).resolve()
            == Path(rclpy.executors.__file__).resolve())
