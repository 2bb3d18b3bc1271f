"""Is the ROS environment set up? One line saying what to source when it is not.

rclpy, the ROS message packages and this package's generated ``wrenchcone_ros.msg`` /
``wrenchcone_ros.srv`` modules come from a sourced ROS workspace (``source
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
    """Import the generated msg and srv modules, wherever the package runs from.

    They exist only in the colcon install tree. When the source tree shadows it on
    sys.path (``python -m ...`` from the repository root), extend the package's search
    path to the other ``wrenchcone_ros`` directories on sys.path (the install tree, via
    PYTHONPATH from install/setup.bash) and try again."""
    try:
        from wrenchcone_ros import msg, srv  # noqa: F401
    except ImportError:
        import pkgutil

        import wrenchcone_ros

        wrenchcone_ros.__path__ = pkgutil.extend_path(wrenchcone_ros.__path__,
                                                      "wrenchcone_ros")
        from wrenchcone_ros import msg, srv  # noqa: F401


def problem() -> str | None:
    """One line saying what is missing and what to source, or None when ROS is usable."""
    try:
        import geometry_msgs.msg  # noqa: F401
        import rclpy  # noqa: F401
    except ImportError as exc:
        return f"ROS 2 is not available ({exc}); {_HINT}"
    try:
        _import_generated()
    except ImportError:
        return ("the generated wrenchcone_ros.msg / wrenchcone_ros.srv modules are not on "
                f"the Python path; {_HINT}")
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
    line on stderr and exit status 2."""
    why = problem()
    if why is None:
        return
    if sys.excepthook is not _exit_on_ros_environment_error:
        _exit_on_ros_environment_error.__defaults__ = (sys.excepthook,)
        sys.excepthook = _exit_on_ros_environment_error
    raise RosEnvironmentError(why) from None
