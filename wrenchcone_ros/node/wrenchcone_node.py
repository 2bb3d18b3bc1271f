"""The node class: a composition of the rooms of this package, and ``main``.

* parameters.py - declarations, validation, parameter values -> Workpiece / Scene;
* store.py      - input store, immutable Snapshot, answer cache, compute_answer;
* inputs.py     - the ``workpiece_pose`` / ``fixels`` subscriptions;
* services.py   - service handlers (one stamped reply per snapshot), registration;
* publishers.py - per-snapshot publishers (``~/cone/<mode>``);
* markers.py    - ``~/markers`` (RViz MarkerArray) from the core's drawing geometry;
* diagnostics.py - ``/diagnostics`` at ``diagnostics_rate``, request counts.
"""

from __future__ import annotations

from typing import Any

import rclpy
from rcl_interfaces.msg import SetParametersResult
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter

from wrenchcone_ros.core import SceneError
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.node import parameters as params
from wrenchcone_ros.node import store as st
from wrenchcone_ros.node.diagnostics import Diagnostics, RequestCounts
from wrenchcone_ros.node.inputs import InputSubscriptions
from wrenchcone_ros.node.markers import MarkerPublisher
from wrenchcone_ros.node.publishers import ConePublishers, SnapshotPublisher
from wrenchcone_ros.node.services import register_services
from wrenchcone_ros.node.status import SCENE_ERROR

NODE_NAME = "wrenchcone"


class WrenchConeNode(Node):
    """The wrench-cone node; see the package docstring and docs/node.md."""

    def __init__(self, node_name: str = NODE_NAME, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self._ready = False
        base = params.declare_parameters(self)
        self.store = st.InputStore(base)
        self.out_of_plane_tolerance = self._p("out_of_plane_tolerance")
        self.request_counts = RequestCounts()  # services.py records every reply
        self.diagnostics = Diagnostics(self, self.store, self.request_counts)
        #: Everything published per snapshot; each gets the same monitored answers.
        #: MERGE NOTE (issue 9): MarkerPublisher(self, force_directions=...) with
        #: wrenchcone_ros.core.directions.force_directions draws the force fans.
        self.snapshot_publishers: list[SnapshotPublisher] = [
            ConePublishers(self), MarkerPublisher(self), self.diagnostics]

        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._parameters_changed)

        self.inputs = InputSubscriptions(self, self.store, self._rebuild)
        self.service_groups = register_services(self)
        self._sync_publishers()
        self._ready = True
        self._rebuild("start")
        snap = self.snapshot
        self.get_logger().info(
            f"ready: {snap.scene.n_fixels if snap.scene else '?'} fixel(s), frame "
            f"{self._p('fixture_frame')!r}, monitoring modes {self._values()['modes']}")

    # --- parameters -----------------------------------------------------------------
    def _p(self, name: str) -> Any:
        return params.parameter_value(self, name)

    def _values(self, overrides: dict[str, Any] | None = None) -> dict[str, Any]:
        return params.read_values(self, overrides)

    def _validate_parameters(self, parameters: list[Parameter]) -> SetParametersResult:
        """Refuse values that cannot make a scene, whatever the pose and fixels."""
        try:
            params.validate_values(self._values({p.name: p.value for p in parameters}))
        except (SceneError, ValueError, TypeError) as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        return SetParametersResult(successful=True)

    def _parameters_changed(self, parameters: list[Parameter]) -> None:
        if not self._ready:  # during __init__'s declarations
            return
        names = {p.name for p in parameters}
        if "fixel_radius" in names:
            self.store.radius_overridden = True
        self._sync_publishers()  # modes, publish_markers, diagnostics_rate
        self.out_of_plane_tolerance = self._p("out_of_plane_tolerance")
        self._rebuild("parameters " + ", ".join(sorted(names)))

    # --- snapshots --------------------------------------------------------------------
    @property
    def snapshot(self) -> st.Snapshot:
        return self.store.snapshot

    def _rebuild(self, reason: str) -> None:
        """Make a new snapshot from the current inputs, then publish monitored modes."""
        snap = self.store.rebuild(self._values())
        if snap.status == SCENE_ERROR:
            self.get_logger().warning(f"{reason}: {snap.message}", throttle_duration_sec=5.0)
        self._publish(snap)

    def answer(self, snapshot: st.Snapshot, mode: str) -> st.Answer:
        """Cached answer of (snapshot, mode): each is computed at most once."""
        return st.cached_answer(snapshot, mode, self.get_logger().error)

    def classifier(self, snapshot: st.Snapshot) -> ModeClassifier:
        """The snapshot's mode classifier (created once, caches its cones)."""
        return st.classifier(snapshot)

    # --- publishing -------------------------------------------------------------------
    def _sync_publishers(self) -> None:
        values = self._values()
        for pub in self.snapshot_publishers:
            pub.sync(values)

    def _publish(self, snap: st.Snapshot) -> None:
        modes = sorted(set().union(*(p.modes() for p in self.snapshot_publishers)))
        answers = st.monitored_answers(snap, modes, self.get_logger().error)
        for pub in self.snapshot_publishers:
            pub.publish(snap, answers)


def main(args: list[str] | None = None) -> int:
    """Console entry point ``wrenchcone_node`` (``ros2 run wrenchcone_ros wrenchcone_node``)."""
    rclpy.init(args=args)
    node = None
    executor = SingleThreadedExecutor()
    try:
        node = WrenchConeNode()
        executor.add_node(node)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except SceneError as exc:
        if node is None:
            rclpy.logging.get_logger(NODE_NAME).fatal(str(exc))
            return 2
        raise
    finally:
        executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
