"""Every use of rclpy internals in wrenchcone_ros, in one module, checked against the
rclpy version it was written for.

The node needs a few things rclpy's documented Python API does not offer. They are all
here, and nowhere else in the package:

* Raw handle pointers (``<object>.handle.pointer``: the address of the rcl struct behind
  an rclpy object) of the node (``rcl_node_t``), a clock (``rcl_clock_t``), a
  subscription (``rcl_subscription_t``) and a guard condition
  (``rcl_guard_condition_t``): the compiled check_wrench lane (src/fastcheck.c, through
  fastcheck.py) creates its service on the node, reads the node clock, takes the poses
  from the subscription and wakes the publishing worker with the guard condition.
* The ``_CONVERT_FROM_PY`` capsule of a generated message class (rosidl_generator_py,
  after ``__import_type_support__()``): the lane turns the Python handler's
  CheckWrench.Response into the C struct it sends.
* ``rclpy.impl.implementation_singleton.rclpy_implementation``: its ``WaitSet`` (the
  pulled pose: the publishing worker waits for a pose message without an executor, as
  ``rclpy.wait_for_message`` does) and ``Subscription.take_message`` (a pose taken when
  no compiled lane takes it).
* ``Node._parameter_overrides`` (read only, any rclpy version: :func:`parameter_overrides`):
  the values given at start, for the parameters to take an integer given for a double
  and to report names the node does not declare.
* ``rclpy.qos_overriding_options._declare_qos_parameters``: the pose subscription lives
  on a helper node, and its QoS override parameters are declared on the node itself, as
  ``Node.create_subscription`` does.

Version: written for and tested with rclpy 7.1.5 (ROS 2 Jazzy). Any rclpy of the
Jazzy series 7.1 is accepted (a distribution keeps rclpy's ABI within its series), and
only when every name above is present. On any other version (or none known) the package
touches none of these: :func:`refusal` says why in one line, the node logs it once, and
it runs on public API only -- check_wrench answered by the Python handler in an
ordinary rclpy service, the pose taken by a subscription callback on its own thread, its
QoS override parameters declared by a short-lived subscription on the node.
"""

from __future__ import annotations

import importlib.metadata
import threading
from collections.abc import Callable
from typing import Any

#: The rclpy release this module (and src/fastcheck.c) was written for and tested with.
WRITTEN_FOR = "7.1.5"
#: Accepted rclpy versions: this major.minor series (ROS 2 Jazzy).
ACCEPTED_SERIES = (7, 1)


def installed_version() -> str | None:
    """The version of the installed ``rclpy`` distribution, or None when unknown."""
    try:
        return importlib.metadata.version("rclpy")
    except importlib.metadata.PackageNotFoundError:
        return None


#: The rclpy version found at import (tests replace it to fake another version).
INSTALLED = installed_version()


def _series(version: str) -> tuple[int, ...] | None:
    try:
        return tuple(int(part) for part in version.split(".")[:2])
    except ValueError:
        return None


def _missing_names() -> list[str]:
    """The private names this module uses that the installed rclpy lacks."""
    missing = []
    try:
        from rclpy.impl.implementation_singleton import rclpy_implementation as impl
    except ImportError:
        return ["rclpy.impl.implementation_singleton.rclpy_implementation"]
    for cls in ("Node", "Clock", "Subscription", "GuardCondition"):
        if not hasattr(getattr(impl, cls, None), "pointer"):
            missing.append(f"_rclpy.{cls}.pointer")
    if not hasattr(getattr(impl, "Subscription", None), "take_message"):
        missing.append("_rclpy.Subscription.take_message")
    if not hasattr(impl, "WaitSet"):
        missing.append("_rclpy.WaitSet")
    try:
        from rclpy.qos_overriding_options import _declare_qos_parameters  # noqa: F401
    except ImportError:
        missing.append("rclpy.qos_overriding_options._declare_qos_parameters")
    return missing


def refusal() -> str | None:
    """None when the installed rclpy is one this module was written for; else one line
    saying why its internals are not used (and what the node does instead)."""
    fallback = ("the node uses public rclpy API only: check_wrench is answered by the "
                "Python handler (no compiled lane)")
    if INSTALLED is None:
        return f"rclpy's version is unknown (no 'rclpy' distribution found); {fallback}"
    if _series(INSTALLED) != ACCEPTED_SERIES:
        series = ".".join(map(str, ACCEPTED_SERIES))
        return (f"rclpy {INSTALLED} is not the version the compiled check_wrench lane was "
                f"written for (rclpy {WRITTEN_FOR}; accepted {series}.*, ROS 2 Jazzy); "
                f"{fallback}")
    missing = _missing_names()
    if missing:
        return f"rclpy {INSTALLED} lacks {', '.join(missing)}; {fallback}"
    return None


def accepted() -> bool:
    """Whether rclpy's internals may be used (:func:`refusal` is None)."""
    return refusal() is None


def _require() -> None:
    why = refusal()
    if why is not None:
        raise RuntimeError(why)


# --- for the compiled lane (fastcheck.py) -------------------------------------------------
def handle_pointer(entity: Any) -> int:
    """Address of the rcl struct behind an rclpy entity: the ``rcl_node_t`` of a Node,
    the ``rcl_clock_t`` of a Clock (``node.get_clock()``), the ``rcl_subscription_t`` of
    a Subscription, the ``rcl_guard_condition_t`` of a GuardCondition
    (``entity.handle.pointer``)."""
    _require()
    return entity.handle.pointer


def convert_from_py(msg_class: Any) -> Any:
    """The PyCapsule of ``msg_class``'s Python -> C conversion (rosidl_generator_py's
    ``_CONVERT_FROM_PY``), its type support imported first."""
    _require()
    meta = msg_class.__class__
    meta.__import_type_support__()
    return meta._CONVERT_FROM_PY


# --- for the parameters (parameters.py) ---------------------------------------------------
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


# --- for the pose inbox (inputs.py) -------------------------------------------------------
def declare_qos_parameters(owner: Any, topic_name: str, msg_type: Any, qos: Any,
                           overrides: Any) -> None:
    """Declare on ``owner`` the QoS override parameters of a subscription to
    ``topic_name`` (resolved) and apply them to ``qos`` in place, as
    ``owner.create_subscription(..., qos_overriding_options=overrides)`` does. Public
    fallback: exactly that subscription, destroyed at once (its parameters stay)."""
    if accepted():
        from rclpy.qos_overriding_options import _declare_qos_parameters
        from rclpy.subscription import Subscription

        _declare_qos_parameters(Subscription, owner, topic_name, qos, overrides)
        return
    sub = owner.create_subscription(msg_type, topic_name, lambda _msg: None, qos,
                                    qos_overriding_options=overrides, raw=True)
    owner.destroy_subscription(sub)


class SubscriptionWait:
    """Wait (without the GIL) until a message is waiting on ``subscription`` or
    ``guard`` was triggered: a wait set of the two, as ``rclpy.wait_for_message`` makes.
    Only when :func:`accepted`."""

    def __init__(self, context: Any, subscription: Any, guard: Any) -> None:
        _require()
        from rclpy.impl.implementation_singleton import rclpy_implementation

        self._context, self._sub, self._guard = context, subscription, guard
        self._wait_set = rclpy_implementation.WaitSet(1, 1, 0, 0, 0, 0, context.handle)

    def wait(self, timeout_s: float) -> None:
        sub, guard, ws = self._sub.handle, self._guard.handle, self._wait_set
        with self._context.handle, sub, guard:
            ws.clear_entities()  # rcl_wait leaves only ready entities: add all each time
            ws.add_subscription(sub)
            ws.add_guard_condition(guard)
            ws.wait(max(0, round(timeout_s * 1e9)))


def take_serialized(subscription: Any) -> bytes | None:
    """The next serialized message waiting on a raw ``subscription``, or None. Only when
    :func:`accepted`."""
    _require()
    handle = subscription.handle
    with handle:
        taken = handle.take_message(subscription.msg_type, True)
    return None if taken is None else taken[0]


class PushedMessages:
    """Public-API fallback of :class:`SubscriptionWait` and :func:`take_serialized`: a raw
    subscription to ``topic_name`` on ``node`` (a helper node no other executor spins)
    whose callback, in a thread of its own, keeps the newest message and ``on_message()``.
    """

    def __init__(self, node: Any, msg_type: Any, topic_name: str, qos: Any,
                 on_message: Callable[[], None]) -> None:
        from rclpy.executors import SingleThreadedExecutor

        self._lock = threading.Lock()
        self._newest: bytes | None = None
        self._on_message = on_message
        self.subscription = node.create_subscription(msg_type, topic_name, self._keep, qos,
                                                     raw=True)
        self._executor = SingleThreadedExecutor(context=node.context)
        self._executor.add_node(node)
        self._thread = threading.Thread(target=self._spin, name="wrenchcone-pose-pushed",
                                        daemon=True)
        self._thread.start()

    def _spin(self) -> None:
        try:
            self._executor.spin()
        except Exception:  # noqa: BLE001 - shut down or destroyed: stop taking
            pass

    def _keep(self, data: bytes) -> None:
        with self._lock:
            self._newest = data
        self._on_message()

    def take(self) -> bytes | None:
        """The newest message not taken yet, or None."""
        with self._lock:
            data, self._newest = self._newest, None
        return data

    def destroy(self) -> None:
        self._executor.shutdown(timeout_sec=1.0)
        self._thread.join(1.0)
