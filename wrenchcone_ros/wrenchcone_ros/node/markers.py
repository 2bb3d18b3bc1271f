# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``~/markers``: the scene and the monitored modes as RViz markers (latched MarkerArray).

All geometry comes from the core (:mod:`wrenchcone_ros.core.drawing`, the same numbers
as ``wrenchcone plot``); this module only turns it into visualization_msgs. Every array
starts with a DELETEALL, so a marker of a fixel that no longer exists disappears. In the
fixture frame, stamped with the newest input stamp; z = 0 (the plane of motion).

Namespaces (RViz can show or hide each):

* ``workpiece``: the outline (LINE_STRIP, id 0) and the centre of mass (SPHERE, id 1);
* ``fixels``: one CYLINDER per fixel (diameter 2 x pin radius; a point fixel is drawn
  with diameter ``POINT_FIXEL_SIZE`` L), id = the fixel's number (1-based, as on every
  interface: fixel i is ``Fixels.fixels[i - 1]`` and letter i of a mode);
* ``normals``: the contact normal n_i of each fixel in contact (ARROW), id = fixel number;
* ``friction_cone/<mode>``, per monitored mode: the friction cone n_i +- mu_i t_i of each
  fixel in contact (TRIANGLE_LIST, id = fixel number) in the colour of the mode's letter
  (opaque when the letter loads the contact: n, l, r; faint for a, s), and the force edge
  a sliding letter allows (ARROW, id = 1000 + fixel number);
* ``letters/<mode>``: the mode's letter at each fixel (TEXT_VIEW_FACING, id = fixel
  number, text "<mode>: <number><letter>");
* ``force_fan/<mode>``: the consistent force directions at the centre of mass
  (TRIANGLE_LIST, id 0), when the node was given a force-directions function (the node
  gives :func:`~wrenchcone_ros.node.services.monitored_directions`: the snapshot's
  cached answer, computed with its classifier);
* ``force_best/<mode>``: the most robust direction of each interval (ARROW, id = the
  interval's index in force_directions' answer, 0-based: intervals are not fixels), so a
  fan that is a single direction is still seen;
* ``status``: when the inputs make no scene, one TEXT_VIEW_FACING with the reason.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from geometry_msgs.msg import Point
from rclpy.node import Node
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.core import ModeError
from wrenchcone_ros.core.drawing import (
    LETTER_COLOURS,
    best_arrow,
    contact_sketches,
    fan_triangles,
    outline,
)
from wrenchcone_ros.node.publishers import (
    CONE_QOS,
    SnapshotPublisher,
    on_new_subscriber,
    snapshot_stamp,
)
from wrenchcone_ros.node.status import OK
from wrenchcone_ros.node.answers import Answer
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.store import Snapshot

#: Sizes as fractions of the scene's length scale L (so any workpiece size looks alike).
LINE_WIDTH = 0.02
ARROW_LENGTH = 0.35
POINT_FIXEL_SIZE = 0.06
TEXT_HEIGHT = 0.12
FAN_RADIUS = 0.6
#: Opacity of a friction cone whose letter loads the contact (n, l, r) and of one that
#: does not (a, s).
LOADED_ALPHA, UNLOADED_ALPHA = 0.6, 0.15
FAN_COLOUR = (0.85, 0.65, 0.0)
#: ``force_directions(snapshot, mode)`` -> intervals with ``lo``, ``hi``, ``best`` (rad,
#: fixture frame) of a force at the snapshot's centre of mass.
ForceDirections = Callable[[Snapshot, str], Sequence[Any]]


def _colour(rgb: Sequence[float], alpha: float = 1.0) -> ColorRGBA:
    return ColorRGBA(r=float(rgb[0]), g=float(rgb[1]), b=float(rgb[2]), a=float(alpha))


def _point(xy: Sequence[float], z: float = 0.0) -> Point:
    return Point(x=float(xy[0]), y=float(xy[1]), z=float(z))


class _Builder:
    """Markers of one array, all with the same header."""

    def __init__(self, frame_id: str, stamp: tuple[int, int] | None) -> None:
        self.array = MarkerArray()
        self.frame_id, self.stamp = frame_id, conv.time_to_msg(stamp)
        clear = Marker(action=Marker.DELETEALL)
        clear.header.frame_id = frame_id
        self.array.markers.append(clear)

    def add(self, ns: str, id_: int, type_: int, rgb: Sequence[float], alpha: float = 1.0,
            **fields: Any) -> Marker:
        m = Marker(ns=ns, id=id_, type=type_, action=Marker.ADD, **fields)
        m.header.frame_id = self.frame_id
        m.header.stamp = self.stamp
        m.pose.orientation.w = 1.0
        m.color = _colour(rgb, alpha)
        self.array.markers.append(m)
        return m


def scene_markers(snap: Snapshot, modes: Sequence[str], answers: dict[str, Answer],
                  force_directions: ForceDirections | None = None) -> MarkerArray:
    """The MarkerArray of one snapshot (module docstring)."""
    b = _Builder(snap.frame_id, snapshot_stamp(snap))
    scene = snap.scene
    if scene is None:
        m = b.add("status", 0, Marker.TEXT_VIEW_FACING, (0.8, 0.0, 0.0),
                  text=f"wrenchcone: {snap.message}")
        m.scale.z = 0.1
        return b.array
    L = scene.length_scale
    line = b.add("workpiece", 0, Marker.LINE_STRIP, (0.1, 0.1, 0.1),
                 points=[_point(p) for p in outline(scene)])
    line.scale.x = LINE_WIDTH * L
    com = b.add("workpiece", 1, Marker.SPHERE, (0.0, 0.0, 0.0))
    com.pose.position = _point(scene.com_world)
    com.scale.x = com.scale.y = com.scale.z = 2 * LINE_WIDTH * L
    sketches = contact_sketches(scene)
    for sk in sketches:
        pin = b.add("fixels", sk.index + 1, Marker.CYLINDER, (0.35, 0.35, 0.35), 0.8)
        pin.pose.position = _point(sk.position)
        pin.scale.x = pin.scale.y = 2 * sk.radius if sk.radius > 0 else POINT_FIXEL_SIZE * L
        pin.scale.z = LINE_WIDTH * L
        if sk.in_contact:
            arrow = b.add("normals", sk.index + 1, Marker.ARROW, (0.0, 0.0, 0.0),
                          points=[_point(sk.point), _point(sk.point + ARROW_LENGTH * L *
                                                           sk.normal)])
            arrow.scale.x, arrow.scale.y, arrow.scale.z = (LINE_WIDTH * L, 2 * LINE_WIDTH * L,
                                                           3 * LINE_WIDTH * L)
    for k, mode in enumerate(modes):
        ans = answers.get(mode)
        if ans is None or ans.status != OK:
            continue
        try:
            per_mode = contact_sketches(scene, mode)
        except ModeError:  # cannot happen for an OK answer; never let it stop the rest
            continue
        for sk in per_mode:
            rgb = LETTER_COLOURS[sk.letter]
            text = b.add(f"letters/{mode}", sk.index + 1, Marker.TEXT_VIEW_FACING, rgb,
                         text=f"{mode}: {sk.index + 1}{sk.letter}")
            text.pose.position = _point(sk.position - (sk.radius + (0.2 + TEXT_HEIGHT * k)
                                                       * L) * sk.normal)
            text.scale.z = TEXT_HEIGHT * L
            if not sk.in_contact:
                continue
            loaded = sk.force_edges.shape[0] > 0
            p = sk.point
            tri = b.add(f"friction_cone/{mode}", sk.index + 1, Marker.TRIANGLE_LIST, rgb,
                        LOADED_ALPHA if loaded else UNLOADED_ALPHA,
                        points=[_point(p), *(_point(p + ARROW_LENGTH * L * e)
                                             for e in sk.full_cone)])
            tri.scale.x = tri.scale.y = tri.scale.z = 1.0
            if sk.force_edges.shape[0] == 1:
                e = sk.force_edges[0]
                edge = b.add(f"friction_cone/{mode}", 1000 + sk.index + 1, Marker.ARROW, rgb,
                             points=[_point(p), _point(p + ARROW_LENGTH * L * e)])
                edge.scale.x, edge.scale.y, edge.scale.z = (
                    LINE_WIDTH * L, 2 * LINE_WIDTH * L, 3 * LINE_WIDTH * L)
        if force_directions is not None:
            intervals = force_directions(snap, mode)  # a force at the com
            tris = [t for iv in intervals for t in fan_triangles(
                scene.com_world, iv.lo, iv.hi, FAN_RADIUS * L)]
            if tris:
                fan = b.add(f"force_fan/{mode}", 0, Marker.TRIANGLE_LIST, FAN_COLOUR, 0.4,
                            points=[_point(v) for v in np.reshape(tris, (-1, 2))])
                fan.scale.x = fan.scale.y = fan.scale.z = 1.0
            # the most robust direction of each interval as an arrow (also what shows a
            # fan that is a single direction)
            c = np.asarray(scene.com_world, dtype=float)
            for j, iv in enumerate(intervals):
                best = b.add(f"force_best/{mode}", j, Marker.ARROW, FAN_COLOUR,
                             points=[_point(p) for p in best_arrow(c, iv.best,
                                                                   FAN_RADIUS * L)])
                best.scale.x, best.scale.y, best.scale.z = (
                    LINE_WIDTH * L, 2 * LINE_WIDTH * L, 3 * LINE_WIDTH * L)
    return b.array


class MarkerPublisher(SnapshotPublisher):
    """``~/markers`` (visualization_msgs/MarkerArray, latched), while the parameter
    ``publish_markers`` is true; switching it off publishes one DELETEALL (latched, so a
    late RViz shows nothing either) and nothing more. No marker is computed while off.

    Markers are built only while someone subscribes (building them costs about as much
    as computing the monitored cones: docs/node.md). A snapshot that arrives with no
    subscriber is kept and published when a subscriber appears (the publisher's matched
    event), so a late RViz sees the current scene.

    ``force_directions`` (the core's, passed by the node) draws the force fans; None
    draws none.
    """

    def __init__(self, node: Node, force_directions: ForceDirections | None = None) -> None:
        super().__init__(node)
        self.force_directions = force_directions
        self._pub: Any = None
        self._on = False
        self._modes: list[str] = []
        self._pending: tuple[Snapshot, dict[str, Answer]] | None = None
        # publish() runs on the node's publishing worker, sync() and the matched events
        # on executor threads
        self._lock = threading.Lock()

    def modes(self) -> set[str]:
        return set(self._modes) if self._on else set()

    def destroy(self) -> None:
        super().destroy()
        with self._lock:
            if self._pub is not None:
                self.node.destroy_publisher(self._pub)
            self._pub, self._on, self._pending = None, False, None

    def sync(self, values: dict[str, Any]) -> None:
        with self._lock:
            self._modes = sorted(values["modes"])
            on = bool(values["publish_markers"])
            if on and self._pub is None:
                self._pub = self.node.create_publisher(
                    MarkerArray, "~/markers", CONE_QOS,
                    event_callbacks=on_new_subscriber(self.node, self._catch_up))
            elif not on and self._on:
                clear = MarkerArray(markers=[Marker(action=Marker.DELETEALL)])
                clear.markers[0].header.frame_id = values["fixture_frame"]
                self._pub.publish(clear)
                self._pending = None
            self._on = on

    def publish(self, snap: Snapshot, answers: dict[str, Answer],
                freshness: Freshness) -> None:
        """When the inputs are stale, ``answers`` is empty: the scene without any mode."""
        with self._lock:
            if not self._on:
                return
            self._pending = (snap, answers)
            if self._pub.get_subscription_count() > 0:
                self._send()

    def _catch_up(self) -> None:
        with self._lock:
            if (self._on and self._pending is not None
                    and self._pub.get_subscription_count() > 0):
                self._send()

    def _send(self) -> None:
        """Build and publish the pending snapshot (lock held)."""
        snap, answers = self._pending
        self._pending = None
        try:
            self._pub.publish(scene_markers(snap, self._modes, answers,
                                            self.force_directions))
        except Exception as exc:  # noqa: BLE001 - markers must never stop the node
            self.node.get_logger().error(f"publishing markers failed: {exc!r}")
