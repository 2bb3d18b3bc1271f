# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""pytest fixtures for testing a controller against the real wrenchcone node, in-process.

Registered as the pytest plugin ``wrenchcone`` (entry point ``pytest11``, also in a
colcon install tree, whose ``wrenchcone_ros-<version>.dist-info`` holds it): installed
with the package, the fixtures are available in every pytest run; ``-p no:wrenchcone``
turns them off. They need a sourced ROS workspace only when a test uses them: this
module imports no ROS package, and a fixture used without ROS fails the test with one
line saying what to source. A test module that imports a ROS package itself
(``from wrenchcone_msgs.msg import Status``) in an unsourced shell gets that line too,
as its collection error, instead of the import's traceback.

Function scope (every test gets its own):

``wrenchcone_domain_id``
    A ROS domain id leased for this test alone (:mod:`wrenchcone_ros.testing.domains`:
    no other test of any run on the machine that leases through the kit holds it
    meanwhile). Given back after the test.
``wrenchcone_context``
    An initialised rclpy ``Context`` on that domain, with localhost-only discovery: the
    context of the test's own nodes (the controller's side). Shut down after the test.
``wrenchcone_node_factory``
    ``wrenchcone_node_factory(scene=None, *, parameters=None, node_name="wrenchcone",
    namespace="", executor=None)``: a :class:`wrenchcone_ros.node.WrenchConeNode` in
    this process, in a context of its own on the test's domain (another DDS participant:
    the test's nodes reach it through DDS discovery, as a controller in another process
    does), spun by its own executor (default ``SingleThreadedExecutor``) in a background
    thread. After the test each executor is shut down and its thread joined, each node
    destroyed (which joins the node's own threads), then the context shut down; an
    exception that ended an executor's thread early fails the test at teardown.
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
``wrenchcone_spin``
    ``wrenchcone_spin(node, *, executor=None)``: spins the test's own node (the
    controller under test, made in one of the kit's contexts) in a background thread;
    after the test its executor is stopped and the node destroyed
    (:class:`wrenchcone_ros.testing.harness.Spinner`).

Module and session scope (one per test module, one per run): ``wrenchcone_node_module``,
``wrenchcone_client_module``, ``wrenchcone_inputs_module``, ``wrenchcone_context_module``,
``wrenchcone_test_node_module``, ``wrenchcone_domain_id_module`` and the same names with
``_session``: the same objects, made once for the module (the run) and shared by its
tests, on a domain of their own.

Overridable, session scope: ``wrenchcone_scene`` (None: no ``scene_file``, the node
waits for pose and fixels; or a scene YAML path or a :class:`wrenchcone_ros.core.Scene`)
and ``wrenchcone_parameters`` (a dict, empty), the scene and parameters of every node
fixture. Override them in a test module or conftest.py; with the module variants, the
override must have module or session scope, with the session variants session scope.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import Any

import pytest

_HINT = ("source the ROS workspace first: `source install/setup.bash` (after `make build` "
         "or `colcon build`)")


#: Top-level modules that come from a sourced ROS workspace (besides ``*_msgs``,
#: ``*_srvs``, ``*_interfaces``): a test module that fails to import one of them gets
#: :data:`_HINT` as its collection error.
_ROS_MODULES = frozenset({"rclpy", "rcl_interfaces", "ament_index_python", "launch",
                          "launch_ros", "launch_testing", "rosidl_runtime_py",
                          "rosidl_parser", "rosbag2_py", "tf2_ros", "wrenchcone_msgs"})
_MISSING = re.compile(r"No module named '([\w.]+)'")


def _is_ros_module(name: str) -> bool:
    top = name.split(".")[0]
    return top in _ROS_MODULES or top.endswith(("_msgs", "_srvs", "_interfaces"))


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector: pytest.Collector) -> Iterator[None]:
    """A test module that cannot import a ROS package: one line saying what to source.

    Parameters
    ----------
    collector : pytest.Collector
        The collector (a test module) whose report this may rewrite.

    Yields
    ------
    None
        To pytest, which makes the report.
    """
    outcome = yield
    report = outcome.get_result()
    if not (report.failed and isinstance(collector, pytest.Module)):
        return
    missing = _MISSING.findall(str(report.longrepr))
    if missing and _is_ros_module(missing[-1]):
        report.longrepr = (f"{collector.nodeid}: No module named '{missing[-1]}': {_HINT}")


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


@pytest.fixture(scope="session")
def wrenchcone_scene() -> Any:
    """The scene ``wrenchcone_node`` loads (override this fixture to set it).

    Returns
    -------
    str, os.PathLike, wrenchcone_ros.core.Scene or None
        None here: no ``scene_file``, the node waits for its input topics.
    """
    return None


@pytest.fixture(scope="session")
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
        ``wrenchcone_node_factory(scene=None, *, parameters=None, node_name="wrenchcone",
        namespace="", executor=None)`` (the bound method
        :meth:`wrenchcone_ros.node.inprocess.NodeFactory.make`) returning the started
        node. ``scene``: a scene YAML path
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


@pytest.fixture
def wrenchcone_spin() -> Iterator[Callable[..., Any]]:
    """Spin the test's own nodes in background threads, for this test.

    Yields
    ------
    callable
        ``wrenchcone_spin(node, *, executor=None)`` (the call of
        :class:`wrenchcone_ros.testing.harness.Spinner`): spins ``node`` (made in one of
        the kit's contexts, e.g. ``wrenchcone_context``) in an executor of its own
        (default ``SingleThreadedExecutor``) on a thread, and returns it. After the test
        each executor is stopped and its node destroyed; an exception that escaped a
        callback into an executor fails the test at teardown.
    """
    spinner = _harness().Spinner()
    try:
        yield spinner
    finally:
        spinner.close()


# --- module and session scope: the same chain, made once and shared ---------------------
def _scoped_fixtures(scope: str) -> dict[str, Any]:
    """The fixtures ``wrenchcone_<name>_<scope>``, each one object for the scope."""
    what = {"module": "test module", "session": "pytest run"}[scope]
    overrides = {"module": "module or session", "session": "session"}[scope]

    def domain_id() -> Iterator[int]:
        _require_ros()
        from wrenchcone_ros.testing.domains import lease_domain

        with lease_domain() as lease:
            yield lease.domain_id

    def context(request: pytest.FixtureRequest) -> Iterator[Any]:
        domain = request.getfixturevalue(f"wrenchcone_domain_id_{scope}")
        with _harness().isolated_context(domain) as ctx:
            yield ctx

    def node(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory,
             wrenchcone_scene: Any, wrenchcone_parameters: dict[str, Any]) -> Iterator[Any]:
        domain = request.getfixturevalue(f"wrenchcone_domain_id_{scope}")
        factory = _harness().NodeFactory(domain, tmp_path_factory.mktemp("wrenchcone_scene"))
        try:
            yield factory.make(wrenchcone_scene, parameters=wrenchcone_parameters)
        finally:
            factory.close()

    def test_node(request: pytest.FixtureRequest) -> Iterator[Any]:
        made = _harness().make_test_node(request.getfixturevalue(f"wrenchcone_context_{scope}"))
        yield made
        made.destroy_node()

    def client(request: pytest.FixtureRequest) -> Iterator[Any]:
        made = _harness().make_client(request.getfixturevalue(f"wrenchcone_test_node_{scope}"),
                                      request.getfixturevalue(f"wrenchcone_node_{scope}"))
        yield made
        made.destroy()

    def inputs(request: pytest.FixtureRequest) -> Iterator[Any]:
        made = _harness().InputPublishers(
            request.getfixturevalue(f"wrenchcone_test_node_{scope}"))
        yield made
        made.destroy()

    docs = {
        domain_id: f"A ROS domain id held by this {what} alone (``wrenchcone_domain_id`` "
                   f"for a {scope}).",
        context: f"The rclpy context of the {what}'s own nodes, on "
                 f"``wrenchcone_domain_id_{scope}`` (``wrenchcone_context`` for a {scope}).",
        node: f"One wrenchcone node for the {what}, on ``wrenchcone_scene`` with "
              f"``wrenchcone_parameters`` (override them with {overrides} scope); "
              f"its state (inputs published) carries over from test to test.",
        test_node: f"A plain node ``wrenchcone_test`` in ``wrenchcone_context_{scope}``, "
                   f"spun by nobody, for the {what}.",
        client: f"A client of ``wrenchcone_node_{scope}`` on "
                f"``wrenchcone_test_node_{scope}``, for the {what}.",
        inputs: f"Publishers of the node's inputs on ``wrenchcone_test_node_{scope}``, "
                f"for the {what} (as ``wrenchcone_inputs``).",
    }
    out = {}
    for function, doc in docs.items():
        name = f"wrenchcone_{function.__name__}_{scope}"
        function.__doc__ = doc
        function.__name__ = function.__qualname__ = name
        out[name] = pytest.fixture(scope=scope, name=name)(function)
    return out


globals().update(_scoped_fixtures("module"))
globals().update(_scoped_fixtures("session"))
