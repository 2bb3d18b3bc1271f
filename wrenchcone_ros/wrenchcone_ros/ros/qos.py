# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The QoS profiles of the node's input topics, shared by the node, the simulated tray
and the test kit's publishers.

* ``fixels``: latched static data (reliable, transient local, keep last 1), like nav2's
  map: :func:`fixels_qos`, :data:`FIXELS_QOS`;
* ``workpiece_pose``, as a publisher offers it: reliable, volatile, keep last 10, which
  reaches a best-effort "sensor data" subscription as well as a reliable one
  (:data:`POSE_QOS`).
"""

from __future__ import annotations

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy


def fixels_qos() -> QoSProfile:
    """The fixels' QoS: latched static data (reliable, transient local, depth 1).

    Returns
    -------
    rclpy.qos.QoSProfile
        A new profile (the caller may change it).
    """
    return QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


#: The ``fixels`` publisher's QoS: reliable, transient local, depth 1 (latched static
#: data, as a fixture description or nav2's map publishes it).
FIXELS_QOS = fixels_qos()
#: The ``workpiece_pose`` publisher's QoS: reliable, volatile, depth 10 (it reaches a
#: best-effort "sensor data" subscription as well as a reliable one).
POSE_QOS = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)
