# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Runs recorded as rosbag2 MCAP files (``rosbags``, a pure-Python rosbag2 writer).

:class:`BagRecorder` subscribes to the loop's topics and writes every message as it
arrived (serialized CDR, as rclpy received it: nothing is converted) into a rosbag2 bag
with the MCAP storage plugin: a directory with ``metadata.yaml`` and one ``.mcap`` file,
which ``ros2 bag play``, ``ros2 bag info`` and Foxglove open. Message definitions are
written into the file (the standard ones from rosbags' Jazzy type store, those of
``wrenchcone_msgs`` from the installed ``.msg`` files), so that a reader needs no ROS.
The scene (its YAML, ``Scene.to_dict``) is written once on the topic ``scene_yaml``
(``std_msgs/String``), so that ``wrenchcone replay`` needs no scene file.

Topics recorded by default (:data:`LOOP_TOPICS`): the pose, the fixels, the tilt
command, the true contact letters and the controller's state.
"""

from __future__ import annotations

import importlib
import threading
from pathlib import Path

import yaml
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

from ..replay.bag import SCENE_TOPIC

#: (topic, ROS type) the loop's recorder subscribes to by default.
LOOP_TOPICS: tuple[tuple[str, str], ...] = (
    ("/workpiece_pose", "geometry_msgs/msg/PoseStamped"),
    ("/fixels", "wrenchcone_msgs/msg/Fixels"),
    ("/tilt_command", "wrenchcone_msgs/msg/TiltCommand"),
    ("/contact_letters", "wrenchcone_msgs/msg/ContactLetters"),
    ("/tilt_controller/state", "wrenchcone_msgs/msg/ControllerState"),
)



def typestore():
    """rosbags' Jazzy type store with the wrenchcone_msgs messages added (from the
    installed .msg files).

    Returns
    -------
    rosbags.typesys.store.Typestore
        The type store.
    """
    from ament_index_python.packages import get_package_share_directory
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS2_JAZZY)
    share = Path(get_package_share_directory("wrenchcone_msgs")) / "msg"
    types = {}
    for f in sorted(share.glob("*.msg")):
        types.update(get_types_from_msg(f.read_text(), f"wrenchcone_msgs/msg/{f.stem}"))
    store.register(types)
    return store


def _message_class(ros_type: str):
    """The generated Python class of "pkg/msg/Name"."""
    pkg, kind, name = ros_type.split("/")
    return getattr(importlib.import_module(f"{pkg}.{kind}"), name)


class BagRecorder:
    """Record ``topics`` seen by ``node`` into the rosbag2 MCAP bag ``path`` (a new
    directory). ``scene``: written once on SCENE_TOPIC. Stamps are the node's clock at
    arrival (ns). Call :meth:`close` (or use as a context manager) to finish the file.

    Parameters
    ----------
    node : rclpy.node.Node
        The node whose subscriptions record.
    path : str or Path
        The bag directory to create.
    topics : sequence of (str, str), optional
        (topic, ROS type) pairs (default: the loop's topics).
    scene : Scene or None, optional
        The scene, written once as YAML.
    """

    def __init__(self, node: Node, path: str | Path, topics=LOOP_TOPICS, scene=None) -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer

        self.node = node
        self.path = Path(path)
        self.store = typestore()
        self.writer = Writer(self.path, version=9, storage_plugin=StoragePlugin.MCAP)
        self.writer.open()
        self.lock = threading.Lock()
        self.count = 0
        self.closed = False
        self._subs = []
        if scene is not None:
            self._write_scene(scene)
        for topic, ros_type in topics:
            conn = self.writer.add_connection(topic, ros_type, typestore=self.store)
            qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
            if topic.endswith("fixels"):
                qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                 durability=DurabilityPolicy.TRANSIENT_LOCAL)
            # no QoS event handlers: close() destroys these subscriptions while an
            # executor may be spinning the node, and rclpy's executor does not survive a
            # waitable (an event handler) destroyed under it (InvalidHandle)
            self._subs.append(node.create_subscription(
                _message_class(ros_type), topic,
                lambda data, c=conn: self._write(c, data), qos, raw=True,
                event_callbacks=SubscriptionEventCallbacks(use_default_callbacks=False)))

    def _write_scene(self, scene) -> None:
        conn = self.writer.add_connection(SCENE_TOPIC, "std_msgs/msg/String",
                                          typestore=self.store)
        String = self.store.types["std_msgs/msg/String"]
        text = yaml.safe_dump(scene.to_dict(), sort_keys=False)
        self._write(conn, self.store.serialize_cdr(String(data=text), "std_msgs/msg/String"))

    def _write(self, conn, data: bytes) -> None:
        with self.lock:
            if self.closed:
                return
            self.writer.write(conn, self.node.get_clock().now().nanoseconds, bytes(data))
            self.count += 1

    def close(self) -> None:
        """Stop recording and finish the bag."""
        with self.lock:
            if self.closed:
                return
            self.closed = True
        for sub in self._subs:
            self.node.destroy_subscription(sub)
        self.writer.close()

    def __enter__(self) -> BagRecorder:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


__all__ = ["BagRecorder", "LOOP_TOPICS", "SCENE_TOPIC", "typestore"]
