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
* ``rclpy.impl.implementation_singleton.rclpy_implementation.WaitSet`` and
  ``Subscription.handle.take_message`` (:class:`SubscriptionWait`,
  :func:`take_serialized`): the pulled pose (inputs.py). The publishing worker waits for a
  pose message without an executor, as ``rclpy.wait_for_message`` does, and takes the
  newest one when it needs it, so a 1 kHz stream costs no executor wake-up per message.
  :func:`pull_available` says whether this rclpy has them; without, inputs.py takes the
  pose with an ordinary subscription callback.
* ``rclpy_implementation.WaitSet`` with ``add_service``, and
  ``Service.handle.service_take_request`` (:class:`ServiceWait`, :func:`take_request`):
  the request lane (lane.py) waits for the fast services' requests in a thread of its
  own, with a wait set made once, and takes them as rclpy's executor does
  (``Executor._take_service``); the reply goes out through the public
  ``Service.send_response``. :func:`lane_available` says whether this rclpy has them;
  without, the services run on the executor that spins the node.
* ``ActionServer._execute_goal_request`` (:func:`goal_id_server`,
  :func:`current_goal_id`): rclpy passes a goal callback the goal's fields, not its id;
  the plan action reports a rejected goal's reason under the goal's id. Without the
  method the id is reported as unknown (empty).
"""

from __future__ import annotations

import threading
from typing import Any

#: The rclpy series whose internals the pulled pose was written for and tested with
#: (ROS 2 Jazzy: rclpy 7.1).
WRITTEN_FOR_SERIES = (7, 1)


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


def _rclpy_series() -> tuple[int, ...] | None:
    try:
        import importlib.metadata

        version = importlib.metadata.version("rclpy")
    except Exception:  # noqa: BLE001 - not installed as a distribution: unknown
        return None
    try:
        return tuple(int(v) for v in version.split(".")[:2])
    except ValueError:
        return None


def _internals_present(*paths: str) -> bool:
    """Whether this rclpy is the series the internals were written for and has every
    dotted name of ``paths`` under its C extension (``"Service.service_take_request"``)."""
    if _rclpy_series() != WRITTEN_FOR_SERIES:
        return False
    try:
        from rclpy.impl.implementation_singleton import rclpy_implementation
    except ImportError:
        return False
    for path in paths:
        obj = rclpy_implementation
        for name in path.split("."):
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
    return True


def pull_available() -> bool:
    """Whether the pulled pose may use this rclpy's internals: the series it was written
    for, with the names it uses present."""
    return _internals_present("WaitSet", "Subscription.take_message")


class SubscriptionWait:
    """Wait (without the GIL) until a message is waiting on ``subscription`` or ``guard``
    was triggered: a wait set of the two, as ``rclpy.wait_for_message`` makes."""

    def __init__(self, context: Any, subscription: Any, guard: Any) -> None:
        from rclpy.impl.implementation_singleton import rclpy_implementation

        self._context, self._sub, self._guard = context, subscription, guard
        self._wait_set = rclpy_implementation.WaitSet(1, 1, 0, 0, 0, 0, context.handle)

    def wait(self, timeout_s: float | None) -> None:
        """Wait at most ``timeout_s`` (s; None: until a message or the guard)."""
        sub, guard, ws = self._sub.handle, self._guard.handle, self._wait_set
        with self._context.handle, sub, guard:
            ws.clear_entities()  # rcl_wait leaves only ready entities: add all each time
            ws.add_subscription(sub)
            ws.add_guard_condition(guard)
            ws.wait(-1 if timeout_s is None else max(0, round(timeout_s * 1e9)))


def lane_available() -> bool:
    """Whether the request lane may use this rclpy's internals: the series it was written
    for, with the names it uses present."""
    return _internals_present("WaitSet.add_service", "Service.service_take_request")


class ServiceWait:
    """Wait (without the GIL) until a request is waiting on one of ``services`` or
    ``guard`` was triggered: one wait set of them, made once."""

    def __init__(self, context: Any, services: list[Any], guard: Any) -> None:
        from rclpy.impl.implementation_singleton import rclpy_implementation

        self._context, self._services, self._guard = context, list(services), guard
        self._wait_set = rclpy_implementation.WaitSet(0, 1, 0, 0, len(self._services), 0,
                                                      context.handle)

    def wait(self) -> None:
        """Wait until a request or the guard (no timeout)."""
        ws, handles = self._wait_set, [s.handle for s in self._services]
        with self._context.handle, self._guard.handle:
            for h in handles:
                h.__enter__()
            try:
                ws.clear_entities()  # rcl_wait leaves only ready entities: add all each time
                for h in handles:
                    ws.add_service(h)
                ws.add_guard_condition(self._guard.handle)
                ws.wait(-1)
            finally:
                for h in handles:
                    h.__exit__(None, None, None)


def take_request(service: Any) -> tuple[Any, Any] | None:
    """The next request waiting on ``service`` and its header, or None: what rclpy's
    executor takes before it calls the service's callback."""
    handle = service.handle
    with handle:
        taken = handle.service_take_request(service.srv_type.Request)
    if taken is None or taken[1] is None:
        return None
    return taken[0], taken[1]


def take_serialized(subscription: Any) -> bytes | None:
    """The next serialized message waiting on a raw ``subscription``, or None."""
    handle = subscription.handle
    with handle:
        taken = handle.take_message(subscription.msg_type, True)
    return None if taken is None else taken[0]


_goal_ids = threading.local()


def goal_id_server(action_server_class: Any) -> Any:
    """``action_server_class`` (rclpy's ``ActionServer``) whose goal callback can read the
    id of the goal it is asked about (:func:`current_goal_id`): rclpy passes only the
    goal's fields to the callback, and a rejected goal's reason is reported under its
    id. Uses rclpy's ``_execute_goal_request`` (the request carries the id); without it
    the id is unknown (None), nothing else changes.

    Parameters
    ----------
    action_server_class : type
        rclpy's ``ActionServer``.

    Returns
    -------
    type
        A subclass.
    """
    parent = getattr(action_server_class, "_execute_goal_request", None)
    if parent is None:
        return action_server_class

    class GoalIdActionServer(action_server_class):
        async def _execute_goal_request(self, request_header_and_message: Any) -> Any:
            try:
                _goal_ids.value = bytes(request_header_and_message[1].goal_id.uuid)
            except Exception:  # noqa: BLE001 - another shape: the id stays unknown
                _goal_ids.value = None
            try:
                return await parent(self, request_header_and_message)
            finally:
                _goal_ids.value = None

    return GoalIdActionServer


def current_goal_id() -> bytes | None:
    """The id (16 bytes) of the goal whose goal callback runs in this thread, or None.

    Returns
    -------
    bytes or None
        The goal's UUID.
    """
    return getattr(_goal_ids, "value", None)
