# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Pure-setuptools install of the wrenchcone_ros Python package (core + CLI).

`pip install .` works on a machine without ROS: the core needs only numpy, scipy,
pycddlib and PyYAML (and matplotlib for `wrenchcone plot`: `pip install .[plot]`). The
ROS node (wrenchcone_ros.node) additionally needs rclpy and the generated service
modules, which come from the colcon build (see docs/node.md).
"""

import re
from pathlib import Path

from setuptools import find_packages, setup

# One version source: wrenchcone_ros/_version.py (read, not imported).
VERSION = re.search(r'^__version__ = "([^"]+)"$',
                    (Path(__file__).parent / "wrenchcone_ros" / "_version.py").read_text(),
                    re.M).group(1)

setup(
    name="wrenchcone_ros",
    version=VERSION,
    description="Wrench cones for planar rigid-body contact tasks (core, CLI, ROS 2 node)",
    packages=find_packages(include=["wrenchcone_ros", "wrenchcone_ros.*"]),
    python_requires=">=3.10",
    install_requires=["numpy", "pycddlib>=3", "pyyaml", "scipy", "numba>=0.61"],
    extras_require={"plot": ["matplotlib"],  # `wrenchcone plot`, wrenchcone_ros.core.plot
                    "sim": ["pymunk"],  # `wrenchcone plan`, core.simulate, core.plan
                    # `wrenchcone replay` of recorded runs (rosbag2 MCAP), the recorder
                    "replay": ["rosbags", "matplotlib"],
                    # `wrenchcone design`, wrenchcone_ros.design
                    "design": ["pymunk", "dask[distributed]", "pyarrow", "tqdm",
                               "matplotlib"]},
    entry_points={
        "console_scripts": [
            "wrenchcone = wrenchcone_ros.cli:main",
            "wrenchcone_node = wrenchcone_ros.node:run",
            # the closed loop (docs/closed_loop.md): a simulated tray, a reference controller
            "tray_sim = wrenchcone_ros.sim.tray_sim:run",
            "tilt_controller = wrenchcone_ros.sim.tilt_controller:run",
        ],
        # the test kit for controller authors (docs/testing.md): pytest loads it in every
        # run of an environment where this distribution is installed; it imports no ROS
        # package until a test uses one of its fixtures
        "pytest11": ["wrenchcone = wrenchcone_ros.testing.plugin"],
    },
)
