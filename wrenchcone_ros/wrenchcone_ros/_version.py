# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The package version: the one place it is written.

setup.py reads this file (without importing the package), ``wrenchcone_ros.__version__``
and ``wrenchcone --version`` import it; package.xml and CHANGELOG.rst must carry the same
number (test/packaging/test_packaging.py checks both).
"""

__version__ = "0.2.0"
