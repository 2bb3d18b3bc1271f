# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Importing this module makes ``import wrenchcone_ros`` find this checkout's package
first, whatever else is installed: the core benchmarks measure the code beside them.
(Node benchmarks do not import it: they need the install tree's generated message and
service modules, ``source install/setup.bash``.)"""

import sys

from harness import ROOT

# The package's directory (ROOT/wrenchcone_ros holds the package wrenchcone_ros/): ROOT
# itself would only make wrenchcone_ros/ a namespace candidate, and an installed
# package (an editable install of another checkout) would win over it.
PACKAGE_DIR = str(ROOT / "wrenchcone_ros")
if PACKAGE_DIR not in sys.path:
    sys.path.insert(0, PACKAGE_DIR)
