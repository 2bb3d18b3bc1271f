# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""pytest fixtures for testing a controller against the real wrenchcone node, in-process.

Registered as the pytest plugin ``wrenchcone`` (entry point ``pytest11``): installed with
the package, the fixtures are available in every pytest run; ``-p no:wrenchcone``
turns them off. They need a sourced ROS workspace only when a test uses them: this
module imports no ROS package, and a fixture used without ROS fails the test with one
line saying what to source.

Fixtures (function scope: every test gets its own):

``wrenchcone_domain_id``
    A ROS domain id leased for this test alone (:mod:`wrenchcone_ros.testing.domains`:
    no other test of any run on the machine that leases through the kit holds it
    meanwhile). Given back after the test.
``wrenchcone_context``
    An initialised rclpy ``Context`` on that domain, with localhost-only discovery: the
    context of the test's own nodes (the controller's side). Shut down after the test.
``wrenchcone_scene``
    The scene of ``wrenchcone_node``: None by default (no ``scene_file``: the node waits
    for pose and fixels). Override it in a test module or conftest.py with a fixture
    returning a scene YAML path or a :class:`wrenchcone_ros.core.Scene`.
``wrenchcone_parameters``
    Further parameters of ``wrenchcone_node`` (a dict, empty by default). Override it
    like ``wrenchcone_scene``.
``wrenchcone_node_factory``
    ``make(scene=None, *, parameters=None, node_name="wrenchcone", namespace="",
    executor=None)``: a :class:`wrenchcone_ros.node.WrenchConeNode` in this process, in
    a context of its own on the test's domain (another DDS participant: the test's nodes
    reach it through DDS discovery, as a controller in another process does), spun by
    its own executor (default ``SingleThreadedExecutor``) in a background thread. After
    the test each executor is shut down and its thread joined, each node destroyed
    (which joins the node's own threads), then the context shut down; an exception that
    ended an executor's thread early fails the test at teardown.
``wrenchcone_node``
    ``wrenchcone_node_factory(wrenchcone_scene, parameters=wrenchcone_parameters)``.
``wrenchcone_test_node``
    A plain rclpy node ``wrenchcone_test`` in the test's context, spun by nobody: the
    controller's stand-in that owns the client and the publishers.
``wrenchcone_client``
    A :class:`wrenchcone_ros.ros.client.WrenchConeClient` of ``wrenchcone_node`` on
    ``wrenchcone_test_node``. Each call waits for its service within its own timeout.
``wrenchcone_inputs``
    :class:`wrenchcone_ros.testing.harness.InputPublishers` on ``wrenchcone_test_node``:
    ``publish_pose(x, y, theta)`` on ``workpiece_pose`` and ``publish_fixels(points)``
    on ``fixels`` (reliable, transient local).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import pytest

_HINT = ("source the ROS workspace first: `source install/setup.bash` (after `make build` "
         "or `colcon build`)")


def _require_ros() -> None:
    """Fail the test with one line saying what to source when ROS is missing."""
    try:
        import geometry_msgs.msg  # noqa: F401
        import rclpy  # noqa: F401
        import wrenchcone_msgs.srv  # noqa: F401
        missing = None
    except ImportError as exc:
        missing = str(exc)
    if missing is not None:  # outside the except block: one line, no chained traceback
        pytest.fail(f"wrenchcone fixtures need ROS 2 and the built wrenchcone_msgs "
                    f"({missing}); {_HINT}", pytrace=False)


def _harness() -> Any:
    """The ROS side of the kit, imported at first use; one line when ROS is missing."""
    _require_ros()
    from wrenchcone_ros.testing import harness

    return harness


@pytest.fixture
def wrenchcone_domain_id() -> Iterator[int]:
    """A ROS domain id held by this test alone, across the machine's test runs.

    Yields
    ------
    int
        The leased id (see :func:`wrenchcone_ros.testing.domains.lease_domain`); given
        back after the test.
    """
    _require_ros()  # the leases are the ROS adapters' (wrenchcone_ros.ros.domains)
    from wrenchcone_ros.testing.domains import lease_domain

    with lease_domain() as lease:
        yield lease.domain_id


@pytest.fixture
def wrenchcone_context(wrenchcone_domain_id: int) -> Iterator[Any]:
    """The rclpy context of the test's own nodes, on the test's domain.

    Yields
    ------
    rclpy.context.Context
        Initialised, localhost-only discovery, no signal handlers; shut down after the
        test.
    """
    with _harness().isolated_context(wrenchcone_domain_id) as context:
        yield context


@pytest.fixture
def wrenchcone_scene() -> Any:
    """The scene ``wrenchcone_node`` loads (override this fixture to set it).

    Returns
    -------
    str, os.PathLike, wrenchcone_ros.core.Scene or None
        None here: no ``scene_file``, the node waits for its input topics.
    """
    return None


@pytest.fixture
def wrenchcone_parameters() -> dict[str, Any]:
    """Further parameters of ``wrenchcone_node`` (override this fixture to set them).

    Returns
    -------
    dict
        Parameter name to value; empty here (the node's defaults).
    """
    return {}


@pytest.fixture
def wrenchcone_node_factory(wrenchcone_domain_id: int,
                            tmp_path_factory: pytest.TempPathFactory
                            ) -> Iterator[Callable[..., Any]]:
    """Make wrenchcone nodes in this process, each spun in a background thread.

    Yields
    ------
    callable
        ``make(scene=None, *, parameters=None, node_name="wrenchcone", namespace="",
        executor=None)`` returning the started node. ``scene``: a scene YAML path
        (relative to the working directory) or a ``wrenchcone_ros.core.Scene``, passed
        as parameter ``scene_file``; None: none. ``parameters``: a dict of further
        parameter overrides. ``executor``: the executor class spinning the node
        (default ``rclpy.executors.SingleThreadedExecutor``). The nodes share one
        context (DDS participant) on the test's domain, not the test's own.
    """
    factory = _harness().NodeFactory(wrenchcone_domain_id,
                                     tmp_path_factory.mktemp("wrenchcone_scene"))
    try:
        yield factory.make
    finally:
        factory.close()


@pytest.fixture
def wrenchcone_node(wrenchcone_node_factory: Callable[..., Any], wrenchcone_scene: Any,
                    wrenchcone_parameters: dict[str, Any]) -> Any:
    """The wrenchcone node on ``wrenchcone_scene`` with ``wrenchcone_parameters``.

    Returns
    -------
    wrenchcone_ros.node.WrenchConeNode
        Named ``wrenchcone`` in the root namespace of the test's own domain, spun in a
        background thread; destroyed after the test.
    """
    return wrenchcone_node_factory(wrenchcone_scene, parameters=wrenchcone_parameters)


@pytest.fixture
def wrenchcone_test_node(wrenchcone_context: Any) -> Iterator[Any]:
    """A plain node ``wrenchcone_test`` in the test's context, spun by nobody.

    Yields
    ------
    rclpy.node.Node
        Destroyed after the test.
    """
    node = _harness().make_test_node(wrenchcone_context)
    yield node
    node.destroy_node()


@pytest.fixture
def wrenchcone_client(wrenchcone_node: Any, wrenchcone_test_node: Any) -> Iterator[Any]:
    """A client of ``wrenchcone_node``'s services, owned by ``wrenchcone_test_node``.

    Yields
    ------
    wrenchcone_ros.ros.client.WrenchConeClient
        Blocking calls (``check_wrench``, ``get_cone``, ``classify_wrench``,
        ``force_directions``); destroyed after the test.
    """
    client = _harness().make_client(wrenchcone_test_node, wrenchcone_node)
    yield client
    client.destroy()


@pytest.fixture
def wrenchcone_inputs(wrenchcone_test_node: Any) -> Iterator[Any]:
    """Publishers of the node's input topics, owned by ``wrenchcone_test_node``.

    Yields
    ------
    wrenchcone_ros.testing.harness.InputPublishers
        ``publish_pose(x, y, theta)`` (``workpiece_pose``; waits until the node's
        subscription is matched) and ``publish_fixels(points)`` (``fixels``, latched),
        frame ``world``. Use ``InputPublishers(wrenchcone_test_node, frame=...)`` for
        another ``fixture_frame``.
    """
    publishers = _harness().InputPublishers(wrenchcone_test_node)
    yield publishers
    publishers.destroy()
