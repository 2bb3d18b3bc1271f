# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``python -m wrenchcone_ros.cli``: the same as the ``wrenchcone`` command."""

import sys

from . import main

sys.exit(main())
