# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Shared test set-up: make ``test/`` importable (``import strategies``)."""

from __future__ import annotations

import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
