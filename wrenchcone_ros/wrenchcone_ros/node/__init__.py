"""ROS 2 node ``wrenchcone``: pose and fixels in, wrench cones out.

Data flow (one way): messages / parameters -> immutable :class:`Snapshot` (a Scene and
the stamps of the inputs it was built from, with a version number) -> (snapshot, mode)
-> Cone (cached in the snapshot) -> service answers and published F.

* Subscribes ``workpiece_pose`` (geometry_msgs/PoseStamped) and ``fixels``
  (geometry_msgs/PoseArray), both in the fixture frame (parameter ``fixture_frame``).
* Services ``~/check_wrench`` (wrenchcone_msgs/srv/CheckWrench; wildcard modes and an
  optional classification over all modes), ``~/get_cone`` (wrenchcone_msgs/srv/GetCone)
  and ``~/classify_wrench`` (wrenchcone_msgs/srv/ClassifyWrench): answer for any mode,
  from one snapshot.
* Publishes ``~/cone/<mode>`` (wrenchcone_msgs/msg/WrenchCone, reliable + transient
  local, depth 1) for every mode in the ``modes`` parameter and ``~/markers``
  (visualization_msgs/MarkerArray, latched) each time the inputs change, and
  ``/diagnostics`` at ``diagnostics_rate``.

Every accepted input or parameter change makes a new snapshot; a snapshot is never
modified (its cone cache only grows), so an answer never mixes a pose from one update
with fixels from another. Nothing is computed for a mode that is neither requested nor
monitored. Bad input never raises out of a callback: services answer with a status code
and a message; refused topic messages are logged (at once when the reason changes, at
most every 5 s while it repeats) and leave the snapshot as it was. See docs/node.md for
the full interface.

Layout (one module per concern; the node class is a composition of them):

* :mod:`.parameters`  declarations, validation, parameter values -> Workpiece / Scene;
* :mod:`.store`       the input store (coalescing) and its immutable Snapshot;
* :mod:`.answers`     (snapshot, mode) -> Answer, cached in the snapshot; request limits;
  :func:`~.answers.monitored_answers` (the per-snapshot work of the published modes);
* :mod:`.freshness`   how old a snapshot's inputs are against their timeouts;
* :mod:`.inputs`      the inputs: fixels subscription, pulled pose (PoseInbox), INPUT_QOS,
  refusal logging;
* :mod:`.worker`      the publishing worker (:class:`~.worker.PublishWorker`), its timing
  hook ``on_step`` (:class:`~.worker.StepTiming`);
* :mod:`.services`    every service handler (check_wrench, get_cone, classify_wrench,
  force_directions), :data:`~.services.SERVICES` (each registered in its lane),
  :func:`~.services.stamp_response`, the timing hook ``on_request``
  (:class:`~.services.RequestTiming`);
* :mod:`.fastcheck`   the compiled check_wrench lane;
* :mod:`.publishers`  per-snapshot publishers (:class:`~.publishers.SnapshotPublisher`,
  CONE_QOS); the node's ``snapshot_publishers`` list;
* :mod:`.markers`     ``~/markers`` from the core's drawing geometry;
* :mod:`.diagnostics` ``/diagnostics``, request counts;
* :mod:`.executors`   the executors and lanes (fast lane, slow lane, spin);
* :mod:`.status`      the status codes;
* :mod:`.wrenchcone_node`  :class:`WrenchConeNode` and :func:`main`.
"""

import wrenchcone_ros.ros  # noqa: F401 - first: one line, exit 2, when ROS is not sourced
from wrenchcone_ros.node.inputs import INPUT_QOS, REFUSAL_LOG_PERIOD_S
from wrenchcone_ros.node.parameters import MODE_LETTERS, PARAMETERS
from wrenchcone_ros.node.publishers import CONE_QOS
from wrenchcone_ros.node.status import *  # noqa: F401,F403 - the status codes, STATUS_NAMES
from wrenchcone_ros.node.status import __all__ as _STATUS_CODES
from wrenchcone_ros.node.answers import CACHE_LIMIT, Answer, compute_answer
from wrenchcone_ros.node.store import Snapshot
from wrenchcone_ros.node.executors import make_executor, spin
from wrenchcone_ros.node.wrenchcone_node import NODE_NAME, WrenchConeNode, main, run

__all__ = [
    "CACHE_LIMIT", "CONE_QOS", "INPUT_QOS", "MODE_LETTERS", "NODE_NAME", "PARAMETERS",
    "REFUSAL_LOG_PERIOD_S", "Answer", "Snapshot", "WrenchConeNode", "compute_answer", "main",
    "make_executor", "run", "spin",
] + _STATUS_CODES  # the status codes and STATUS_NAMES
