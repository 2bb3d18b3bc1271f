# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A test kit for controller authors: the real wrenchcone node in a pytest test.

* :mod:`.plugin`   the pytest plugin ``wrenchcone`` (registered by the ``pytest11`` entry
  point of this distribution): fixtures ``wrenchcone_context``, ``wrenchcone_node``
  (and ``wrenchcone_node_factory``, ``wrenchcone_scene``, ``wrenchcone_parameters``),
  ``wrenchcone_client``, ``wrenchcone_inputs``, ``wrenchcone_test_node``,
  ``wrenchcone_spin`` (the test's own node spun beside the node), and module- and
  session-scoped variants (``wrenchcone_node_module``, ``wrenchcone_client_session``, ...);
* :mod:`.harness`  what the fixtures are made of, usable without pytest: an isolated
  context, the node spun in a background thread, input publishers (needs ROS);
* :mod:`.domains`  ROS domain ids leased to one test at a time across the machine's
  processes (no ROS).

See docs/testing.md for a worked example. Importing this package imports no ROS
package.
"""
