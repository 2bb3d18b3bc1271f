# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The programs ``tray_sim`` and ``tilt_controller``: one node spun until Ctrl-C."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

import rclpy
from rclpy.executors import ExternalShutdownException


def run_node(name: str, make_node: Callable[[], Any], make_executor: Callable[[], Any],
             args: list[str] | None = None) -> int:
    """Spin ``make_node()`` on ``make_executor()`` until Ctrl-C or the context's end.

    Parameters
    ----------
    name
        The program's name, for its error line.
    make_node
        Builds the node (after ``rclpy.init``); a ValueError or OSError is a bad start-up
        configuration: one line ``NAME: error: ...`` on stderr and status 2.
    make_executor
        Builds the executor that spins it.
    args
        The command line (None: ``sys.argv``).

    Returns
    -------
    int
        The exit status: 0, or 2 for a bad configuration.
    """
    rclpy.init(args=args)
    try:
        try:
            node = make_node()
        except (ValueError, OSError) as exc:
            print(f"{name}: error: {' '.join(str(exc).split())}", file=sys.stderr)
            return 2
        executor = make_executor()
        executor.add_node(node)
        try:
            executor.spin()
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        finally:
            node.destroy_node()
    finally:
        if rclpy.ok():
            rclpy.shutdown()
    return 0
