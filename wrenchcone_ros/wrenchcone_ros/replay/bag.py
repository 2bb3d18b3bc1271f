# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A recorded run read from a rosbag2 bag, without ROS (``rosbags``).

Topics are found by their message type, not their name (a remapped recording works):
``geometry_msgs/msg/PoseStamped`` (the workpiece pose; required), ``wrenchcone_msgs/msg/
TiltCommand`` (required), ``wrenchcone_msgs/msg/Fixels`` or ``geometry_msgs/msg/PoseArray``
(the fixels' positions), ``wrenchcone_msgs/msg/ContactLetters``,
``wrenchcone_msgs/msg/ControllerState`` and the scene's YAML
(``std_msgs/msg/String`` on ``/scene_yaml``). Times: ``t`` is the recording time (s) since
the bag's first message; ``stamp`` the message header's stamp (s). Message definitions
that are not in rosbags' Jazzy type store are taken from the bag itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

#: The scene's topic in bags of the loop's recorder.
SCENE_TOPIC = "/scene_yaml"


class BagError(ValueError):
    """The bag cannot be replayed (the message says what is wrong and what is needed)."""


@dataclass(frozen=True)
class Stamped:
    """One recorded message: recording time t (s since the bag's start), header stamp
    (s), and its values.

    Parameters
    ----------
    t : float
        Recording time (s since the bag's start).
    stamp : float
        Header stamp (s).
    value : tuple
        The message's values.
    """

    t: float
    stamp: float
    value: tuple


@dataclass
class RecordedRun:
    """Everything :func:`read_run` found, each list in recording order.

    Parameters
    ----------
    path : str
        The bag.
    poses : list of Stamped, optional
        (x m, y m, theta rad).
    commands : list of Stamped, optional
        (direction rad, magnitude m/s^2).
    fixels : list of Stamped, optional
        ((x, y), ...), m.
    letters : list of Stamped, optional
        (letters,).
    states : list of Stamped, optional
        (state, planned_mode, direction, margin) of the controller.
    scene_yaml : str or None, optional
        The scene, when recorded.
    topics : dict, optional
        Every topic of the bag and its type.
    """

    path: str
    poses: list[Stamped] = field(default_factory=list)  # (x m, y m, theta rad)
    commands: list[Stamped] = field(default_factory=list)  # (direction rad, magnitude m/s^2)
    fixels: list[Stamped] = field(default_factory=list)  # ((x, y), ...)
    letters: list[Stamped] = field(default_factory=list)  # (letters,)
    states: list[Stamped] = field(default_factory=list)  # (state, planned_mode, direction, margin)
    scene_yaml: str | None = None
    topics: dict[str, str] = field(default_factory=dict)  # topic -> type


def _stamp(header) -> float:
    return header.stamp.sec + 1e-9 * header.stamp.nanosec


def _yaw(q) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def read_run(path: str | Path) -> RecordedRun:
    """Read a recorded run (module docstring); BagError when the file is missing, is not a
    readable rosbag2 bag, or lacks the pose or the command topic.

    Parameters
    ----------
    path : str or Path
        A rosbag2 bag: a directory with metadata.yaml, or one .mcap file.

    Returns
    -------
    RecordedRun
        What the bag holds.

    Raises
    ------
    BagError
        As above.
    """
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    p = Path(path)
    if not p.exists():
        raise BagError(f"{path}: no such file or directory (a rosbag2 bag: a directory with "
                       f"metadata.yaml, or one .mcap file)")
    run = RecordedRun(str(path))
    try:
        with AnyReader([p], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
            run.topics = {c.topic: c.msgtype for c in reader.connections}
            wanted = {"geometry_msgs/msg/PoseStamped", "wrenchcone_msgs/msg/TiltCommand",
                      "geometry_msgs/msg/PoseArray", "wrenchcone_msgs/msg/Fixels",
                      "wrenchcone_msgs/msg/ContactLetters",
                      "wrenchcone_msgs/msg/ControllerState"}
            conns = [c for c in reader.connections
                     if c.msgtype in wanted or (c.topic == SCENE_TOPIC
                                                and c.msgtype == "std_msgs/msg/String")]
            t0 = None
            for conn, t_ns, raw in reader.messages(connections=conns):
                t0 = t_ns if t0 is None else t0
                t = (t_ns - t0) * 1e-9
                msg = reader.deserialize(raw, conn.msgtype)
                kind = conn.msgtype
                if kind == "geometry_msgs/msg/PoseStamped":
                    q = msg.pose.orientation
                    run.poses.append(Stamped(t, _stamp(msg.header), (
                        float(msg.pose.position.x), float(msg.pose.position.y), _yaw(q))))
                elif kind == "wrenchcone_msgs/msg/TiltCommand":
                    run.commands.append(Stamped(t, _stamp(msg.header), (
                        float(msg.direction), float(msg.magnitude))))
                elif kind == "geometry_msgs/msg/PoseArray":
                    run.fixels.append(Stamped(t, _stamp(msg.header), tuple(
                        (float(q.position.x), float(q.position.y)) for q in msg.poses)))
                elif kind == "wrenchcone_msgs/msg/Fixels":
                    run.fixels.append(Stamped(t, _stamp(msg.header), tuple(
                        (float(f.position.x), float(f.position.y)) for f in msg.fixels)))
                elif kind == "wrenchcone_msgs/msg/ContactLetters":
                    run.letters.append(Stamped(t, _stamp(msg.header), (str(msg.letters),)))
                elif kind == "wrenchcone_msgs/msg/ControllerState":
                    run.states.append(Stamped(t, _stamp(msg.header), (
                        str(msg.state), str(msg.planned_mode), float(msg.direction),
                        float(msg.margin))))
                else:
                    run.scene_yaml = str(msg.data)
    except BagError:
        raise
    except Exception as exc:  # noqa: BLE001 - whatever rosbags raises for a bad file
        raise BagError(f"{path}: not a readable rosbag2 bag ({type(exc).__name__}: "
                       f"{' '.join(str(exc).split()) or 'no detail'})") from None
    missing = [what for what, rows in (("geometry_msgs/msg/PoseStamped (the workpiece pose)",
                                        run.poses),
                                       ("wrenchcone_msgs/msg/TiltCommand (the commands)",
                                        run.commands)) if not rows]
    if missing:
        have = ", ".join(f"{k} [{v}]" for k, v in sorted(run.topics.items())) or "none"
        raise BagError(f"{path}: no messages of {' and '.join(missing)}; the bag's topics: "
                       f"{have}")
    return run


__all__ = ["BagError", "RecordedRun", "SCENE_TOPIC", "Stamped", "read_run"]
