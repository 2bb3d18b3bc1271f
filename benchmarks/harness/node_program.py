# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ``wrenchcone_node`` program with another executor, for side-by-side figures.

``python node_program.py KIND --ros-args ...`` runs :func:`wrenchcone_node.run` (the
program as installed: its process tuning, its node) spinning the node on KIND:

* ``lane``: the program's default, :class:`wrenchcone_ros.node.executors.LaneExecutor`;
* ``multi_threaded``: rclpy's ``MultiThreadedExecutor`` with 4 threads;
* ``single_threaded``: rclpy's ``SingleThreadedExecutor`` (a classification or a plan
  then holds up every check_wrench behind it).

Benchmark tooling only (``harness.ros.NodeProcess(..., executor=KIND)``).
"""

from __future__ import annotations

import sys

from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor

from wrenchcone_ros.node import wrenchcone_node
from wrenchcone_ros.node.executors import make_executor

EXECUTORS = {
    "lane": make_executor,
    "multi_threaded": lambda: MultiThreadedExecutor(num_threads=4),
    "single_threaded": SingleThreadedExecutor,
}

if __name__ == "__main__":
    kind = sys.argv.pop(1)
    wrenchcone_node.run(executor_factory=EXECUTORS[kind])
