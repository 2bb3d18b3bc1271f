# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
