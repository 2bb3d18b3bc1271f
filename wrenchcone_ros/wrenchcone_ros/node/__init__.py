# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""ROS 2 node ``wrenchcone``: pose and fixels in, wrench cones out.

:class:`WrenchConeNode` is a managed (lifecycle) node that any executor can spin;
:func:`main` is the ``wrenchcone_node`` program. Its endpoints, all the node's own
(remappable, in its namespace):

* subscribes ``workpiece_pose`` (geometry_msgs/PoseStamped, sensor-data QoS) and
  ``fixels`` (wrenchcone_msgs/Fixels: positions, radii, optional per-fixel friction;
  latched and volatile publishers both heard) or ``fixel_poses`` (geometry_msgs/PoseArray,
  with parameter ``fixel_radius`` only), all in the fixture frame (parameter
  ``fixture_frame``);
* services ``~/check_wrench`` (wrenchcone_msgs/srv/CheckWrench; wildcard modes and an
  optional classification over all modes), ``~/get_cone`` (GetCone),
  ``~/classify_wrench`` (ClassifyWrench) and ``~/force_directions`` (ForceDirections);
* the action ``~/plan_seating`` (wrenchcone_msgs/action/PlanSeating);
* publishes ``~/cone/<mode>`` (wrenchcone_msgs/msg/WrenchCone, latched) for every mode
  of the ``modes`` parameter and ``~/markers`` (visualization_msgs/MarkerArray, latched)
  each time the inputs change, ``/diagnostics`` at ``diagnostics_rate``, and
  ``~/plan_seating/rejections`` (diagnostic_msgs/DiagnosticStatus, latched) the reason
  of each rejected plan goal;
* the lifecycle services ``~/change_state``, ``~/get_state``, ...

Data flow (one way): messages / parameters -> immutable :class:`Snapshot` (a Scene and
the stamps of the inputs it was built from, with a version number) -> (snapshot, mode)
-> Cone (cached in the snapshot) -> service answers and published F. A snapshot is never
modified, so an answer never mixes a pose from one update with fixels from another.
Without ``scene_file`` every answer is NO_INPUTS until the user's pose and fixels have
arrived. Bad input never raises out of a callback: services answer with a status code
(wrenchcone_msgs/msg/Status) and a message; refused topic messages are logged and leave
the snapshot as it was. See docs/node.md for the full interface, and wrenchcone_node.py
for the modules the node is made of.
"""

import wrenchcone_ros.ros  # noqa: F401 - first: one line, exit 2, when ROS is not sourced
from wrenchcone_ros.node.inputs import INPUT_QOS, REFUSAL_LOG_PERIOD_S
from wrenchcone_ros.node.parameters import MODE_LETTERS, PARAMETERS
from wrenchcone_ros.node.publishers import CONE_QOS
from wrenchcone_ros.node.status import *  # noqa: F401,F403 - the status codes, STATUS_NAMES
from wrenchcone_ros.node.status import __all__ as _STATUS_CODES
from wrenchcone_ros.node.answers import CACHE_LIMIT, Answer, compute_answer
from wrenchcone_ros.node.store import Snapshot
from wrenchcone_ros.node.executors import SpinThread, make_executor, spin
from wrenchcone_ros.node.wrenchcone_node import (
    NODE_NAME,
    StartError,
    WrenchConeNode,
    main,
    run,
)

__all__ = [
    "CACHE_LIMIT", "CONE_QOS", "INPUT_QOS", "MODE_LETTERS", "NODE_NAME", "PARAMETERS",
    "REFUSAL_LOG_PERIOD_S", "Answer", "Snapshot", "SpinThread", "StartError",
    "WrenchConeNode", "compute_answer", "main", "make_executor", "run", "spin",
] + _STATUS_CODES  # the status codes and STATUS_NAMES
