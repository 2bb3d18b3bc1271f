# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An empty ``std_srvs/Trigger`` service ``<ns>/trigger`` in a process of its own, on the
node's executor kind: the floor of a service call on this machine, measured side by side
with the node. Prints "ready", serves until SIGTERM or SIGINT.

    python benchmarks/harness/empty_service.py NS

Started by ``harness.ros.start_trigger_server``.
"""

from __future__ import annotations

import sys

import rclpy
from rclpy.node import Node
from std_srvs.srv import Trigger

from wrenchcone_ros.node.executors import make_executor, spin

if __name__ == "__main__":
    rclpy.init()
    node = Node("empty", namespace=sys.argv[1])
    node.create_service(Trigger, "trigger", lambda req, resp: resp)
    executor = make_executor()  # the node's executor kind: a like-for-like floor
    executor.add_node(node)
    print("ready", flush=True)
    try:
        spin(executor, node.get_logger())
    except BaseException:  # noqa: BLE001 - ended by a signal: nothing to report
        pass
