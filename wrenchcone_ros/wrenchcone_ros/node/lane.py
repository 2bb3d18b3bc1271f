# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The request lane: the fast services (check_wrench, get_cone) served from a thread of
their own, beside whatever executor spins the node.

Why. An rclpy executor, on every wake-up, rebuilds in Python a wait set of every entity
of every node it spins, then runs or hands over the ready callback; a check_wrench whose
answer is cached computes for about 15 microseconds, and that machinery is most of its
round trip (docs/node.md has the figures). The lane waits on the fast services alone,
in one wait set made once (GIL released while waiting), takes each request as rclpy's
executor takes it, runs the same service callback (services.py: the snapshot, the
stamps, the limits, the timing hook) and sends the reply with rclpy's
``Service.send_response``.

What runs where. A request the lane can answer with bounded work
(:func:`answers_at_once`: its answer is cached in the snapshot it is answered from, or it
is one concrete mode, without classification, under a model set whose cones are linear
in the parameters) is answered in the lane's thread; any other (a wildcard mode, a
classification, a robust cone over a sampled model set not computed yet) goes to the
lane's pool of :data:`LANE_POOL_THREADS` threads, so a request that computes long never
holds up the cheap ones behind it. Replies may then leave out of order (each carries
its request's id, as with any rclpy service).

The services stay the node's own entities: listed under the node, remappable as
``~/check_wrench`` and ``~/get_cone``, introspectable; they are in a :class:`LaneGroup`,
a callback group from which no executor runs them. Parameter ``request_lane`` (default
true) turns the lane off: the services are then in a ``ReentrantCallbackGroup`` and run
on the executor like every other callback. On an rclpy whose internals the lane was not
written for (rclpy_boundary.lane_available) the services run on the executor too.

The lane lives from configure to cleanup (an inactive node's services answer
NOT_ACTIVE, so they must be served), idle in its wait when no request comes (no timer,
no polling); :meth:`RequestLane.stop` ends it, its pool finishing the requests it holds.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

from rclpy.callback_groups import CallbackGroup
from rclpy.exceptions import InvalidHandle
from rclpy.guard_condition import GuardCondition

from wrenchcone_ros.core.modes import is_wildcard
from wrenchcone_ros.node import rclpy_boundary

#: Threads of the lane's pool: requests that compute long, at once (a wildcard check,
#: a check with classification, a robust cone over a sampled model set).
LANE_POOL_THREADS = 2

#: Seconds :meth:`RequestLane.stop` waits for the lane's thread to end.
LANE_STOP_TIMEOUT_S = 5.0


class LaneGroup(CallbackGroup):
    """A callback group from which no executor runs a callback: its services are served
    by a :class:`RequestLane`."""

    def can_execute(self, entity: Any) -> bool:
        return False

    def beginning_execution(self, entity: Any) -> bool:
        return False

    def ending_execution(self, entity: Any) -> None:
        return None


def answers_at_once(node: Any, request: Any) -> bool:
    """Whether the lane answers ``request`` in its own thread: its work is bounded.

    True when the node is not active (NOT_ACTIVE at once), when the answer of the
    request's mode is cached in the snapshot the request is answered from, or when the
    request is one concrete mode (no wildcard), without classification, and the
    snapshot's model set needs no scenario sample (its cones are linear in the
    parameters: one cone per mode). Everything else goes to the lane's pool.

    Parameters
    ----------
    node : WrenchConeNode
        The node.
    request : CheckWrench.Request or GetCone.Request
        The request.

    Returns
    -------
    bool
        Whether to answer it in the lane's thread.
    """
    if not node.active or node.store is None:
        return True
    if getattr(request, "classify", False):
        return False
    mode = request.mode
    if not isinstance(mode, str) or is_wildcard(mode):
        return False
    snap = node.request_snapshot()
    if mode in snap.answers or snap.scene is None:
        return True
    return not snap.uncertainty.nonlinear(snap.scene)


class RequestLane:
    """Serves ``services`` from a thread of its own (module docstring).

    Parameters
    ----------
    context : rclpy.context.Context
        The node's context.
    services : sequence of rclpy.service.Service
        The services, each created in a :class:`LaneGroup`.
    at_once : callable
        ``at_once(request) -> bool``: answer in the lane's thread (True) or on its pool.
    on_error : callable
        Gets one line for an unexpected exception (a reply that could not be sent).
    name : str, optional
        The thread's name.
    """

    def __init__(self, context: Any, services: Sequence[Any],
                 at_once: Callable[[Any], bool], on_error: Callable[[str], None],
                 name: str = "wrenchcone-lane") -> None:
        self._services = list(services)
        self._at_once, self._on_error = at_once, on_error
        self._guard = GuardCondition(None, None, context=context)
        self._wait = rclpy_boundary.ServiceWait(context, self._services, self._guard)
        self._pool = ThreadPoolExecutor(LANE_POOL_THREADS, thread_name_prefix=f"{name}-pool")
        self._running = True
        self._context = context
        # a context shut down (Ctrl-C, rclpy.shutdown) ends the lane too (rclpy keeps a
        # bound method weakly: the context does not keep a stopped lane alive)
        context.on_shutdown(self._context_shut_down)
        self.thread = threading.Thread(target=self._run, name=name, daemon=True)
        self.thread.start()

    def _context_shut_down(self) -> None:
        self.stop(join=False)

    @property
    def running(self) -> bool:
        """Whether the lane still serves."""
        return self._running

    def _run(self) -> None:
        while self._running:
            try:
                self._wait.wait()
            except InvalidHandle:
                return  # a service or the context went away under the wait
            except Exception as exc:  # noqa: BLE001 - the lane must not end silently
                if not self._running:
                    return
                self._on_error(f"request lane: wait failed: {type(exc).__name__}: {exc}")
                return
            for service in self._services:
                while self._running:
                    try:
                        taken = rclpy_boundary.take_request(service)
                    except InvalidHandle:
                        return
                    if taken is None:
                        break
                    request, header = taken
                    if self._decide(request):
                        self._serve(service, request, header)
                    else:
                        self._pool.submit(self._serve, service, request, header)

    def _decide(self, request: Any) -> bool:
        try:
            return bool(self._at_once(request))
        except Exception:  # noqa: BLE001 - undecided: the pool (never holds the lane up)
            return False

    def _serve(self, service: Any, request: Any, header: Any) -> None:
        try:
            response = service.callback(request, service.srv_type.Response())
            service.send_response(response, header)
        except InvalidHandle:
            return  # the service was destroyed while the request was answered
        except Exception as exc:  # noqa: BLE001 - one reply lost, the lane goes on
            self._on_error(f"request lane: reply not sent: {type(exc).__name__}: {exc}")

    def stop(self, join: bool = True) -> None:
        """End the lane: no request is taken any more; with ``join``, wait for its thread
        and for the pool's requests to finish (their replies are sent)."""
        self._running = False
        try:
            self._guard.trigger()
        except Exception:  # noqa: BLE001 - destroyed, or its context gone: nothing waits
            pass
        if not join:
            return
        if self.thread is not threading.current_thread():
            self.thread.join(LANE_STOP_TIMEOUT_S)
        self._pool.shutdown(wait=True)
        if not self.thread.is_alive():
            try:
                self._guard.destroy()
            except Exception:  # noqa: BLE001 - its context already gone with it
                pass
