# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A controller that only commands a wrench the wrenchcone node calls consistent.

Every ``period`` seconds it asks the node's ``check_wrench`` whether its wrench (parameter
``wrench``: fx N, fy N, tz N m) is consistent with its contact mode (parameter ``mode``)
and keeps the answer: ``approved`` is True only for status OK and a consistent wrench.
The call is asynchronous, so the node's executor never blocks on it.
"""

import threading

import rclpy
from rclpy.node import Node
from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import CheckWrench


class TiltController(Node):
    """Ask check_wrench, keep whether the wrench may be commanded."""

    def __init__(self, **kwargs):
        super().__init__("my_tilt_controller", **kwargs)
        self.mode = self.declare_parameter("mode", "na").value
        self.wrench = [float(v) for v in self.declare_parameter("wrench", [0.0, -1.0, 0.0]).value]
        server = self.declare_parameter("server", "wrenchcone").value  # relative name
        self.client = self.create_client(CheckWrench, f"{server}/check_wrench")
        self.approved = None  # None until the first answer
        self.answered = threading.Event()
        self._pending = None
        self.create_timer(self.declare_parameter("period", 0.1).value, self.tick)

    def tick(self):
        if self._pending is not None or not self.client.service_is_ready():
            return
        request = CheckWrench.Request(mode=self.mode)
        force, torque = request.wrench.force, request.wrench.torque
        force.x, force.y, torque.z = self.wrench
        self._pending = self.client.call_async(request)
        self._pending.add_done_callback(self.on_reply)

    def on_reply(self, future):
        self._pending = None
        reply = future.result()
        self.approved = reply.status == Status.OK and reply.consistent
        self.answered.set()


def main(args=None):
    rclpy.init(args=args)
    node = TiltController()
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
