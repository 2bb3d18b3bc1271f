# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Importing this module makes ``import wrenchcone_ros`` find this checkout's package
first, whatever else is installed: the core benchmarks measure the code beside them.
(Node benchmarks do not import it: they need the install tree's generated message and
service modules, ``source install/setup.bash``.)"""

import sys

from harness import ROOT

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
