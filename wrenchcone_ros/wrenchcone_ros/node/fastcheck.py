"""The compiled check_wrench lane: the node's side of ``_fastcheck`` (src/fastcheck.c).

A :class:`CompiledLane` owns two things of the node's: every take of a
``workpiece_pose`` message (:class:`~.inputs.PoseInbox` takes through it, so the lane
always knows when the newest pose was received) and the ``~/check_wrench`` service. Its
own thread answers a request without the GIL when the publishing worker has handed it
the cone of that mode for the current inputs (:func:`offer`); everything else is
queued for the Python handler of services.py, which answers it in a thread of its own
(:func:`serve`) exactly as before, while the lane goes on answering. What the lane
answers itself (all must hold, else Python):

* the request does not ask to classify;
* the mode is one of the monitored ``modes`` (concrete), and its answer was OK or
  MODE_INFEASIBLE for the snapshot the worker published last;
* the wrench is planar as sent (force.z, torque.x, torque.y exactly 0), finite, and its
  largest part within :data:`AS_SENT` (conversions.wrench_to_planar returns such a
  wrench unchanged: no rescaling, never refused);
* no pose was received after the newest one the snapshot may answer for
  (:func:`pose_until_ns`: ``pose_reuse_window``) and the node clock is not past the
  snapshot's :func:`fresh_until_ns` (``input_timeout``, ``fixels_timeout``).

Every rule is decided here, in Python, and handed to C as data: the margin geometry of
each cone (its lineality rows, and cones.margin_geometries: unit rays and face
projections, the very numbers the Python reference uses), the two deadlines, the bounds
of a wrench planar as sent, the tolerances and status codes. C does only the per-request arithmetic.

The lane forgets every cone when an input other than the pose changes (:func:`clear`:
fixels, parameters); a cone the worker computed from older inputs is then refused
(``generation``). Its replies carry the same fields as the Python handler's: the
snapshot's version, stamps and frame, the age of its inputs at the reply. At most
``max_queued_requests`` requests wait for the Python handler; one more is answered
LIMIT_EXCEEDED at once (the lane takes every request from the middleware at once, so
this queue, not the middleware's, is the one that must be bounded).

There is no compiled lane (:class:`NoLane`: check_wrench is an ordinary rclpy service
of the fast lane, the pose is taken in Python) when the extension is missing, when
rclpy is not the version it was written for (rclpy_boundary.py), or when parameter
``fast_check`` is false at start (its default: environment variable
``WRENCHCONE_FAST_CHECK``, parameters.py). The node logs which, once.
"""

from __future__ import annotations

import importlib
import math
import threading
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from rclpy.callback_groups import ReentrantCallbackGroup

from wrenchcone_msgs.srv import CheckWrench
from wrenchcone_ros.core.cones import margin_geometries
from wrenchcone_ros.core.tolerances import CONE_TOLERANCE, WRENCH_RESCALE_ABOVE
from wrenchcone_ros.node import rclpy_boundary
from wrenchcone_ros.node.answers import Answer
from wrenchcone_ros.node.freshness import freshness
from wrenchcone_ros.node.parameters import fast_check_default
from wrenchcone_ros.node.status import INTERNAL_ERROR, LIMIT_EXCEEDED, MODE_INFEASIBLE, OK
from wrenchcone_ros.node.store import Snapshot

try:
    # By name: the extension is a compiled leaf (it imports nothing of this package) that
    # exists only in a build, so an import checker reading the source tree would take
    # ``import wrenchcone_ros.node._fastcheck`` for an import of the package itself.
    _fastcheck = importlib.import_module("wrenchcone_ros.node._fastcheck")
except ImportError as exc:  # not built (a pure-Python install): the Python handler
    _fastcheck = None
    _IMPORT_ERROR = f"{type(exc).__name__}: {exc}"
else:
    _IMPORT_ERROR = ""

#: The largest part of a wrench planar as sent that conversions.wrench_to_planar keeps
#: as it is: (smallest, largest) magnitude (N or N m); 0 is kept too.
AS_SENT = (1.0 / WRENCH_RESCALE_ABOVE, WRENCH_RESCALE_ABOVE)
#: A deadline that never passes (int64 max, ns).
NEVER_NS = 2**63 - 1
_NO_ROWS = np.zeros((0, 3))


def unavailable(fast_check: bool) -> str | None:
    """Why the node has no compiled lane (one line), or None when it has one."""
    if not fast_check:
        return ("parameter fast_check is false: check_wrench is answered by the Python "
                "handler")
    if _fastcheck is None:
        return (f"the compiled check_wrench lane is not built ({_IMPORT_ERROR}): "
                "check_wrench is answered by the Python handler")
    return rclpy_boundary.refusal()


# --- the rules, decided in Python -----------------------------------------------------
def pose_until_ns(snap: Snapshot, window_ns: int) -> int:
    """The receive stamp (node clock, ns) of the newest pose ``snap``'s answers may
    still be given for: a pose received at most ``window_ns`` (``pose_reuse_window``)
    after its own (store.InputStore.current reuses the snapshot then); -1 when it has
    no received pose (any pose received makes it old)."""
    if snap.pose_received_ns is None:
        return -1
    return snap.pose_received_ns + max(0, window_ns)


def fresh_until_ns(snap: Snapshot, input_timeout: float, fixels_timeout: float) -> int:
    """The last node-clock instant (ns) at which :func:`freshness.freshness` calls
    ``snap``'s inputs fresh (:data:`NEVER_NS` when no timeout applies): found from that
    function itself, so the lane's verdict is the Python handler's to the nanosecond."""
    limits = [received + math.floor(timeout * 1e9)
              for received, timeout in ((snap.pose_received_ns, input_timeout),
                                        (snap.fixels_received_ns, fixels_timeout))
              if received is not None and timeout > 0]
    if not limits:
        return NEVER_NS

    def stale(t: int) -> bool:
        return bool(freshness(snap, t, input_timeout, fixels_timeout).stale)

    t = min(limits)
    while stale(t):  # float rounding of age > timeout: at most a step or two either way
        t -= 1
    while not stale(t + 1):
        t += 1
    return t


def _rows(a: Any) -> np.ndarray:
    """``a`` as the C-contiguous float64 (k, 3) array the lane copies (a cone's arrays
    are already: passed as they are, half the cost of a conversion per array)."""
    if isinstance(a, np.ndarray) and a.ndim == 2 and a.dtype == np.float64 \
            and a.flags.c_contiguous:
        return a
    return np.ascontiguousarray(a, dtype=np.float64).reshape(-1, 3)


def entries(answers: Mapping[str, Answer]) -> list[tuple]:
    """The lane's entries for the monitored answers it can answer itself (not another
    status, not a wildcard mode): (mode, status, message, feasible, 1 / length scale, F,
    E, L, rays, projections): each cone's unit rows and its margin geometry
    (cones.margin_geometries, the Python reference's own, for all cones in one pass)."""
    out: list[tuple] = []
    cones = []
    for mode, ans in answers.items():
        if ans.status not in (OK, MODE_INFEASIBLE) or ans.union is not None:
            continue
        cone = ans.cone
        if cone is None:
            if ans.status != OK:
                out.append((mode, ans.status, ans.message, False, 1.0) + (_NO_ROWS,) * 5)
        elif not cone.feasible:
            out.append((mode, ans.status, ans.message, False,
                        1.0 / float(cone.length_scale)) + (_NO_ROWS,) * 5)
        else:
            cones.append((mode, ans, cone))
    hats = [(c.F_hat, c.E_hat, c.G_hat, c.L_hat) for _, _, c in cones]
    for (mode, ans, cone), (rays, planes) in zip(cones, margin_geometries(hats)):
        out.append((mode, ans.status, ans.message, True, 1.0 / float(cone.length_scale),
                    _rows(cone.F_hat), _rows(cone.E_hat), _rows(cone.L_hat), _rows(rays),
                    _rows(planes.reshape(-1, 3))))
    return out


def entry(mode: str, ans: Answer) -> tuple | None:
    """The lane's entry for one monitored answer (:func:`entries`), or None when the lane
    cannot answer that mode itself."""
    got = entries({mode: ans})
    return got[0] if got else None


# --- the lanes ------------------------------------------------------------------------
class CompiledLane:
    """The compiled lane (``_fastcheck.Lane``) on ``clock`` (the node's: respects
    use_sim_time) and the Python-side rules it is handed (the parameter values of
    :func:`configure`). Made by :func:`new_lane` for a node."""

    def __init__(self, clock: Any) -> None:
        self._clock = clock
        self._c = _fastcheck.Lane(rclpy_boundary.handle_pointer(self._clock), CONE_TOLERANCE,
                                  AS_SENT[0], AS_SENT[1], OK, MODE_INFEASIBLE,
                                  INTERNAL_ERROR, LIMIT_EXCEEDED)
        self._window_ns = 0
        self._timeouts = (0.0, 0.0)
        self._keep: tuple = ()  # the rclpy objects whose rcl structs the lane points to
        self.generation = self._c.generation
        self.clear = self._c.clear
        self.check = self._c.check
        self.take_pose = self._c.take_pose
        self.usable = self._c.usable
        self.stats = self._c.stats
        self.set_entries = self._c.set_entries

    def __bool__(self) -> bool:
        return True

    def attach_poses(self, subscription: Any, guard: Any) -> None:
        """Take the poses from ``subscription`` (raw); trigger ``guard`` when the
        service thread took one (it wakes the publishing worker)."""
        self._keep += (subscription, guard)
        self._c.attach_poses(rclpy_boundary.handle_pointer(subscription),
                             rclpy_boundary.handle_pointer(guard))

    def configure(self, values: Mapping[str, Any]) -> None:
        self._window_ns = round(values["pose_reuse_window"] * 1e9)
        self._timeouts = (float(values["input_timeout"]), float(values["fixels_timeout"]))
        self._c.set_config(int(values["max_queued_requests"]))

    def offer(self, generation: int, snap: Snapshot, answers: Mapping[str, Answer]) -> bool:
        received = [t for t in (snap.pose_received_ns, snap.fixels_received_ns)
                    if t is not None]
        snapshot = (snap.version, snap.frame_id, snap.pose_stamp or (0, 0),
                    snap.fixels_stamp or (0, 0), min(received, default=-1),
                    pose_until_ns(snap, self._window_ns),
                    fresh_until_ns(snap, *self._timeouts))
        return self._c.set_entries(generation, snapshot, entries(answers))

    def serve(self, node: Any, name: str,
              callback: Callable[[CheckWrench.Request, CheckWrench.Response], Any]
              ) -> threading.Thread:
        def answer(mode: str, wrench: tuple[float, ...], classify: bool) -> Any:
            req = CheckWrench.Request(mode=mode, classify=classify)
            f, t = req.wrench.force, req.wrench.torque
            f.x, f.y, f.z, t.x, t.y, t.z = wrench
            return callback(req, CheckWrench.Response())

        def forwarded_requests() -> None:
            while (item := self._c.next_forwarded(FORWARD_WAIT_S)) is not False:
                if item is None:
                    continue
                token, mode, wrench, classify = item
                try:  # the callback never raises; this thread must outlive anything else
                    resp = answer(mode, wrench, classify)
                except Exception as exc:  # noqa: BLE001 - a request must get a reply
                    resp = CheckWrench.Response(status=INTERNAL_ERROR, margin=-1.0,
                                                message=f"check_wrench failed: {exc!r}"[:1000])
                    node.get_logger().error(resp.message)
                self._c.respond(token, resp)

        self._keep += (node,)
        self._c.serve(rclpy_boundary.handle_pointer(node), name,
                      rclpy_boundary.convert_from_py(CheckWrench.Response))
        thread = threading.Thread(target=forwarded_requests,
                                  name="wrenchcone-check-python", daemon=True)
        thread.start()
        return thread

    def close(self) -> None:
        self._c.close()


class NoLane:
    """No compiled lane: check_wrench is an ordinary rclpy service of the node's fast
    lane (:meth:`serve`), the pose is taken by the pose inbox itself; every method of
    :class:`CompiledLane` the node calls does nothing here. False in a boolean context."""

    def __init__(self, why: str) -> None:
        self.why = why

    def __bool__(self) -> bool:
        return False

    def generation(self) -> int:
        return 0

    def clear(self) -> None:
        pass

    def check(self, *_args: Any) -> None:
        return None

    def configure(self, values: Mapping[str, Any]) -> None:
        pass

    def offer(self, generation: int, snap: Snapshot, answers: Mapping[str, Answer]) -> bool:
        return True  # nothing to hand over: never offered again

    def serve(self, node: Any, name: str, callback: Callable[[Any, Any], Any]) -> None:
        node.create_service(CheckWrench, name, callback,
                            callback_group=ReentrantCallbackGroup())

    def close(self) -> None:
        pass


Lane = CompiledLane | NoLane


def new_lane(owner: Any) -> Lane:
    """The compiled lane of ``owner`` (on its clock: respects use_sim_time; it serves
    nothing until :func:`serve` and takes no pose until ``attach_poses``), or a
    :class:`NoLane` saying why there is none (logged once, at info level when
    ``fast_check`` is false, else as a warning). ``fast_check``: the owner's parameter,
    or its default when the owner has none (a node that only hosts a pose inbox)."""
    fast_check = (bool(owner.get_parameter("fast_check").value)
                  if owner.has_parameter("fast_check") else fast_check_default())
    why = unavailable(fast_check)
    if why is None:
        return CompiledLane(owner.get_clock())
    log = owner.get_logger()
    (log.info if not fast_check else log.warning)(why)
    return NoLane(why)


#: The Python handler's thread waits at most this long (s) per wait for a forwarded
#: request (it ends at once when the lane closes; this only bounds a wait).
FORWARD_WAIT_S = 0.5


def serve(lane: Lane, node: Any, name: str,
          callback: Callable[[CheckWrench.Request, CheckWrench.Response], Any]) -> Any:
    """Create the service ``name`` (e.g. ``~/check_wrench``) on ``node``: answered in the
    compiled lane's thread, and what it forwards by ``callback(request, response) ->
    response`` (the node's Python service callback, which never raises) in a thread of
    its own (returned), one request at a time, until the lane closes; without a compiled
    lane, an ordinary rclpy service calling ``callback`` in the node's fast lane."""
    return lane.serve(node, name, callback)


def configure(lane: Lane, values: Mapping[str, Any]) -> None:
    """The parameters the lane's rules use: pose_reuse_window, the timeouts,
    max_queued_requests (the lane forgets its cones on every parameter change, so the
    next offer carries the new rules)."""
    lane.configure(values)


def offer(lane: Lane, generation: int, snap: Snapshot, answers: Mapping[str, Answer]) -> bool:
    """Hand the lane the monitored answers of ``snap``, computed after the lane's
    ``generation()`` was read, with the snapshot's deadlines; False (nothing changed) if
    a :func:`clear` came since."""
    return lane.offer(generation, snap, answers)
