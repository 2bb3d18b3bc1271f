# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Is the ROS environment set up? One line saying what to source when it is not.

rclpy, the ROS message packages and the generated interfaces (``wrenchcone_msgs``) come from a sourced ROS workspace (``source
install/setup.bash`` after ``make build`` or ``colcon build``). Without it, importing
them fails deep inside the package with chained ImportError tracebacks.
:func:`require_ros` tries them once, and on failure raises :class:`RosEnvironmentError`
(an ImportError, so a library caller can still catch it) whose message is the one line
to act on; if nothing catches it, the program prints that line and exits with status 2
(:data:`EXIT_STATUS`) instead of a traceback. No ROS import at module level here.
"""

from __future__ import annotations

import os
import sys
from types import TracebackType

#: The exit status of a program ended by a missing ROS environment (a usage error).
EXIT_STATUS = 2
_HINT = ("source the workspace first: `source install/setup.bash` (after `make build` or "
         "`colcon build`), or run through `make run`")


class RosEnvironmentError(ImportError):
    """The ROS environment is not set up; the message says what to source."""


def _import_generated() -> None:
    """Import the generated interfaces (the wrenchcone_msgs package of the workspace)."""
    from wrenchcone_msgs import action, msg, srv  # noqa: F401


def problem() -> str | None:
    """One line saying what is missing and what to source, or None when ROS is usable.

    Returns
    -------
    str or None
        The line, or None.
    """
    try:
        import geometry_msgs.msg  # noqa: F401
        import rclpy  # noqa: F401
    except ImportError as exc:
        return f"ROS 2 is not available ({exc}); {_HINT}"
    try:
        _import_generated()
    except ImportError:
        return ("the interfaces package wrenchcone_msgs is not on the Python path; "
                f"{_HINT}")
    return None


def _exit_on_ros_environment_error(kind: type[BaseException], value: BaseException,
                                   tb: TracebackType | None,
                                   previous=sys.excepthook) -> None:
    if isinstance(value, RosEnvironmentError):
        print(f"wrenchcone_ros: {value}", file=sys.stderr, flush=True)
        sys.stdout.flush()
        os._exit(EXIT_STATUS)
    previous(kind, value, tb)


def require_ros() -> None:
    """Raise :class:`RosEnvironmentError` (one-line message) unless rclpy, the message
    packages and the generated modules import; uncaught, it ends the program with that
    line on stderr and exit status 2.

    Raises
    ------
    RosEnvironmentError
        ROS is not usable: the message says what is missing and what to source.
    """
    why = problem()
    if why is None:
        return
    if sys.excepthook is not _exit_on_ros_environment_error:
        _exit_on_ros_environment_error.__defaults__ = (sys.excepthook,)
        sys.excepthook = _exit_on_ros_environment_error
    raise RosEnvironmentError(why) from None
