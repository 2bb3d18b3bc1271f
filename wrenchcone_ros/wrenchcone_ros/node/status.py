# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Status codes of every reply (wrenchcone_msgs/msg/Status, one table) and their names, and
the input sources a reply names (``pose_source``, ``fixels_source``)."""

from __future__ import annotations

from wrenchcone_msgs.msg import Status

__all__ = ["OK", "MODE_INFEASIBLE", "INVALID_MODE", "MODE_NOT_ALLOWED", "INVALID_WRENCH",
           "NO_INPUTS", "SCENE_ERROR", "INTERNAL_ERROR", "STALE_INPUTS", "LIMIT_EXCEEDED",
           "NOT_ACTIVE", "NO_PLAN", "INVALID_GOAL", "CANCELED", "UNAVAILABLE",
           "STATUS_NAMES", "SOURCE_TOPIC", "SOURCE_SCENE_FILE"]

OK = Status.OK
MODE_INFEASIBLE = Status.MODE_INFEASIBLE
INVALID_MODE = Status.INVALID_MODE
MODE_NOT_ALLOWED = Status.MODE_NOT_ALLOWED
INVALID_WRENCH = Status.INVALID_WRENCH
NO_INPUTS = Status.NO_INPUTS
SCENE_ERROR = Status.SCENE_ERROR
INTERNAL_ERROR = Status.INTERNAL_ERROR
STALE_INPUTS = Status.STALE_INPUTS
LIMIT_EXCEEDED = Status.LIMIT_EXCEEDED
NOT_ACTIVE = Status.NOT_ACTIVE
NO_PLAN = Status.NO_PLAN
INVALID_GOAL = Status.INVALID_GOAL
CANCELED = Status.CANCELED
UNAVAILABLE = Status.UNAVAILABLE
#: Every code's name, read from the message definition (one source).
STATUS_NAMES = {getattr(Status, name): name for name in __all__[:__all__.index("STATUS_NAMES")]}
#: An input came from its topic (its stamp is the message's header stamp).
SOURCE_TOPIC = Status.SOURCE_TOPIC
#: An input is the scene file's own (its stamp is zero).
SOURCE_SCENE_FILE = Status.SOURCE_SCENE_FILE
