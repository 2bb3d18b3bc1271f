# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Every use of rclpy internals in wrenchcone_ros, in one module.

The node needs one thing rclpy's documented Python API does not offer, and it is here
and nowhere else in the package (test/node/test_rclpy_boundary.py checks that by AST):

* ``Node._parameter_overrides`` (read only: :func:`parameter_overrides`): the values
  given at start, for the parameters to take an integer given for a double, to report
  names the node does not declare, and to know whether the user gave a workpiece.
  rclpy (7.1, ROS 2 Jazzy) has no public getter for them; on an rclpy without the
  attribute the function returns an empty dict and those three checks see nothing.
* ``LifecycleNode._state_machine.destroy_when_not_in_use()``
  (:func:`release_lifecycle_state_machine`): rclpy 7.1's lifecycle state machine holds
  the node's handle, so a destroyed LifecycleNode stayed in the ROS graph (its DDS
  participant alive) until the process ended; released before the node is destroyed.
"""

from __future__ import annotations

from typing import Any


def parameter_overrides(node: Any) -> dict[str, Any]:
    """The parameter values given to ``node`` at start (``--params-file``, ``-p
    name:=value``, the constructor's ``parameter_overrides``): name -> rclpy Parameter, a
    copy. rclpy keeps them in ``Node._parameter_overrides`` and has no public getter.
    Read on any rclpy version (a plain attribute, checked to be a dict of Parameters);
    empty when it is not there."""
    from rclpy.parameter import Parameter

    given = getattr(node, "_parameter_overrides", None)
    if not isinstance(given, dict):
        return {}
    return {name: p for name, p in given.items() if isinstance(p, Parameter)}


def release_lifecycle_state_machine(node: Any) -> None:
    """Let a LifecycleNode's state machine release the node's handle (see the module
    docstring); nothing on an rclpy without it."""
    machine = getattr(node, "_state_machine", None)
    release = getattr(machine, "destroy_when_not_in_use", None)
    if callable(release):
        release()
