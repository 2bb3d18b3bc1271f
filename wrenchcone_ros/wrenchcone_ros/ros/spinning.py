# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An rclpy executor spinning some nodes in a background thread (tests, the in-process
closed loop of :mod:`wrenchcone_ros.sim`).
"""

from __future__ import annotations

import threading

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
    """

    def __init__(self, context: Context, executor: type[Executor] | None = None,
                 name: str = "wrenchcone-test-executor") -> None:
        self.executor = (executor or SingleThreadedExecutor)(context=context)
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._spin, name=name, daemon=True)
        self.thread.start()

    def _spin(self) -> None:
        try:
            self.executor.spin()
        except rclpy.executors.ExternalShutdownException:
            pass
        except BaseException as exc:  # noqa: BLE001 - reported by stop()
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
        self.executor.shutdown(timeout_sec=timeout)
        self.thread.join(timeout)
        if self.thread.is_alive():
            raise RuntimeError(f"the executor thread {self.thread.name} did not stop "
                               f"within {timeout} s")
        if self.error is not None:
            raise RuntimeError(f"the executor spinning the node raised "
                               f"{type(self.error).__name__}: {self.error}") from self.error
