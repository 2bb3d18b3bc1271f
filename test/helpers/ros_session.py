# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Node-test isolation: own ROS domain, localhost-only discovery, one context per run;
the fixtures of the tests that run the node in-process (imported by test/node/conftest.py
and test/ros/conftest.py).

The environment is set before any rclpy context is initialised, so that parallel test
runs on one machine (another engineer's, CI's) never hear each other.
"""

from __future__ import annotations

import os

from wrenchcone_ros.testing.domains import lease_domain  # noqa: E402 - initialises no ROS

#: This process's ROS domain, leased for the session (a lock file per domain id): no
#: other run on the machine, nor another pytest-xdist worker, gets it meanwhile.
_LEASE = lease_domain()
os.environ["ROS_DOMAIN_ID"] = str(_LEASE.domain_id)
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ.setdefault("RCUTILS_LOGGING_BUFFERED_STREAM", "1")

import pytest  # noqa: E402

try:  # the generated service modules come from the colcon install (make test sources it)
    import rclpy  # noqa: E402
    from wrenchcone_msgs.srv import CheckWrench  # noqa: E402, F401
except ImportError as exc:  # pragma: no cover - a set-up problem, not a test failure
    raise pytest.UsageError(
        f"node tests need rclpy and the built srv modules ({exc}); run `make test`, or "
        "`colcon build` then `source install/setup.bash`") from exc


def session_context():
    """The body of ``ros_context``: an initialised context, shut down at the end."""
    context = rclpy.context.Context()
    rclpy.init(context=context)
    yield context
    rclpy.shutdown(context=context)


def harness_maker(ros_context):
    """The body of ``harness_factory``: ``make(cli_args=None, **parameters)``."""
    from helpers.node_harness import Harness

    made = []

    def make(cli_args=None, **parameters):
        h = Harness(ros_context, {k.replace("__", "."): v for k, v in parameters.items()},
                    cli_args=cli_args)
        made.append(h)
        return h

    yield make
    for h in made:
        h.close()


# A conftest imports these fixtures, or, when another conftest of a directory whose path
# has as many characters imports them already (test/ros and test/sim), defines its own
# around the bodies above: `pytest --fixtures` sorts the fixtures by (path length,
# module, file, name) and fails with an INTERNALERROR on two equal keys.
@pytest.fixture(scope="session")
def ros_context():
    yield from session_context()


@pytest.fixture
def harness_factory(ros_context):
    yield from harness_maker(ros_context)


@pytest.fixture
def harness(harness_factory):
    return harness_factory()
