# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The ROS side of the package, beside the node: message conversions (:mod:`.conversions`)
and a service client for controllers (:mod:`.client`, ``python -m wrenchcone_ros.ros.client``);
what the node, the closed loop (``wrenchcone_ros.sim``) and the test kit
(``wrenchcone_ros.testing``) share: the input topics' QoS (:mod:`.qos`), a context of
its own on a leased ROS domain (:mod:`.contexts`, :mod:`.domains`), an executor spinning
in a thread (:mod:`.spinning`).

The pure core (``wrenchcone_ros.core``) never imports this package. Importing it checks
the ROS environment first (:func:`.environment.require_ros`): without ``source
install/setup.bash`` a program ends with one line saying what to source (exit status 2),
not with chained ImportError tracebacks.
"""

from wrenchcone_ros.ros.environment import require_ros

require_ros()
