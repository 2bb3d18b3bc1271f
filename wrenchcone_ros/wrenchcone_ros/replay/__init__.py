# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Recorded runs, replayed offline without ROS: ``wrenchcone replay RUN.mcap --mode MODE``.

* :mod:`.bag`: a rosbag2 bag (MCAP or SQLite, a directory or one ``.mcap`` file) read with
  ``rosbags`` into a :class:`~.bag.RecordedRun` (poses, fixels, tilt commands, contact
  letters, controller states, the scene if recorded); :class:`~.bag.BagError` for a bag
  that cannot be used, with one line saying why;
* :mod:`.analysis`: at every command, the cone of the mode at the recorded pose, the
  command's margin, when it left the cone, the recorded letters and the modes the core
  classifies the command as (:func:`~.analysis.replay`), and a plot over time.

No module here imports ROS (an import contract in pyproject.toml says so).
"""

from .analysis import Replay, ReplayRow, margin_at, replay
from .bag import BagError, RecordedRun, read_run

__all__ = ["BagError", "RecordedRun", "Replay", "ReplayRow", "margin_at", "read_run",
           "replay"]
