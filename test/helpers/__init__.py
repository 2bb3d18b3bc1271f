# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Helper modules of the test suite and the benchmarks: no tests here.

Test modules are the ``test_*.py`` files under test/core, test/cli, test/ros, test/node,
test/design (one directory per subpackage of wrenchcone_ros) and test/packaging; they
import what they share from this package (``from helpers.strategies import
random_scene``), never from another test module. test/conftest.py puts test/ on
``sys.path`` so that ``helpers`` is importable; the benchmarks do the same
(benchmarks/harness).

* strategies: random scenes, modes and wrenches (seeded, and as hypothesis strategies)
* families: scene families at the edges of the model, and exact membership
* cone3d_cases: random 3-D cones and their exact reference
* seating_family, arrival_family: seeded families of seating tasks
* paper_example: the paper's worked example as data
* cones: equality of two cones as sets
* cli: the ``wrenchcone`` command in a subprocess
* docs_examples, tutorial: the docs' examples, extracted and run
* tilt_scan: the constant-tilt scan of docs/planning.md
* design_reference: the independent reference of the fixture enumeration
* ros_session, node_harness, node_directions, node_fuzz: the node in-process over DDS
"""
