# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""ros/spinning.py: rclpy's own shutdown race is told apart from a node's error."""

import rclpy.executors

from wrenchcone_ros.ros.spinning import is_rclpy_shutdown_race


def _raised_in(filename: str, code: str) -> BaseException:
    try:
        exec(compile(code, filename, "exec"), {})
    except BaseException as exc:  # noqa: BLE001 - the exception is the subject
        return exc
    raise AssertionError("nothing raised")


def test_the_executors_none_guard_condition_at_shutdown_is_the_race():
    # the line rclpy's handler runs on that path: gc.trigger() with gc None
    exc = _raised_in(rclpy.executors.__file__, "gc = None\ngc.trigger()\n")
    assert is_rclpy_shutdown_race(exc)


def test_a_nodes_own_error_is_not():
    assert not is_rclpy_shutdown_race(_raised_in("/somewhere/my_node.py",
                                                 "gc = None\ngc.trigger()\n"))
    assert not is_rclpy_shutdown_race(_raised_in(rclpy.executors.__file__,
                                                 "raise ValueError('x')\n"))
