"""The compiled check_wrench lane: the node's side of ``_fastcheck`` (src/fastcheck.c).

A :class:`_fastcheck.Lane` owns two things of the node's: every take of a
``workpiece_pose`` message (:class:`~.inputs.PoseInbox` takes through it, so the lane
always knows when the newest pose was received) and the ``~/check_wrench`` service. Its
own thread answers a request without the GIL when the publishing worker has handed it
the cone of that mode for the current inputs (:func:`offer`); everything else is
queued for the Python handler of services.py, which answers it in a thread of its own
(:func:`serve`) exactly as before, while the lane goes on answering. What the lane answers itself (all must hold, else Python):

* parameter ``fast_check`` is true and the request does not ask to classify;
* the mode is one of the monitored ``modes`` (concrete), and its answer was OK or
  MODE_INFEASIBLE for the snapshot the worker published last;
* the wrench is planar as sent (force.z, torque.x, torque.y exactly 0) and finite, and
  needs no rescaling (conversions.WRENCH_RESCALE_ABOVE);
* no pose was received more than ``pose_reuse_window`` after that snapshot's pose
  (0: none newer at all), and no input is older than its timeout.

The lane forgets every cone when an input other than the pose changes (:func:`clear`:
fixels, parameters); a cone the worker computed from older inputs is then refused
(``generation``). Its replies carry the same fields as the Python handler's: the
snapshot's version, stamps and frame, the age of its inputs at the reply. At most
``max_queued_requests`` requests wait for the Python handler; one more is answered
LIMIT_EXCEEDED at once (the lane takes every request from the middleware at once, so
this queue, not the middleware's, is the one that must be bounded).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from wrenchcone_ros.conversions import WRENCH_RESCALE_ABOVE, CheckWrench
from wrenchcone_ros.core.tolerances import CONE_TOLERANCE, RANK_TOLERANCE
from wrenchcone_ros.node import _fastcheck
from wrenchcone_ros.node.status import INTERNAL_ERROR, LIMIT_EXCEEDED, MODE_INFEASIBLE, OK
from wrenchcone_ros.node.store import Answer, Snapshot

Lane = _fastcheck.Lane
_NO_ROWS = np.zeros((0, 3))


def new_lane(node: Any) -> Lane:
    """A lane on ``node``'s clock (the node clock: respects use_sim_time); it serves
    nothing until :func:`serve` and takes no pose until ``attach_poses``."""
    return Lane(node.get_clock().handle.pointer, CONE_TOLERANCE, RANK_TOLERANCE,
                WRENCH_RESCALE_ABOVE, OK, MODE_INFEASIBLE, INTERNAL_ERROR, LIMIT_EXCEEDED)


#: The Python handler's thread waits at most this long (s) per wait for a forwarded
#: request (it ends at once when the lane closes; this only bounds a wait).
FORWARD_WAIT_S = 0.5


def serve(lane: Lane, node: Any, name: str,
          callback: Callable[[CheckWrench.Request, CheckWrench.Response], Any]
          ) -> threading.Thread:
    """Create the service ``name`` (e.g. ``~/check_wrench``) on ``node``, answered in the
    lane's thread; start (and return) the thread that answers what the lane forwards
    with ``callback(request, response) -> response`` (the node's Python service
    callback, which never raises), one request at a time, until the lane closes."""
    def answer(mode: str, wrench: tuple[float, ...], classify: bool) -> Any:
        req = CheckWrench.Request(mode=mode, classify=classify)
        f, t = req.wrench.force, req.wrench.torque
        f.x, f.y, f.z, t.x, t.y, t.z = wrench
        return callback(req, CheckWrench.Response())

    def forwarded_requests() -> None:
        while (item := lane.next_forwarded(FORWARD_WAIT_S)) is not False:
            if item is None:
                continue
            token, mode, wrench, classify = item
            try:  # the callback never raises; this thread must outlive anything else
                resp = answer(mode, wrench, classify)
            except Exception as exc:  # noqa: BLE001 - a request must get a reply
                resp = CheckWrench.Response(status=INTERNAL_ERROR, margin=-1.0,
                                            message=f"check_wrench failed: {exc!r}"[:1000])
                node.get_logger().error(resp.message)
            lane.respond(token, resp)

    CheckWrench.Response.__class__.__import_type_support__()
    lane.serve(node.handle.pointer, name, CheckWrench.Response.__class__._CONVERT_FROM_PY)
    thread = threading.Thread(target=forwarded_requests, name="wrenchcone-check-python",
                              daemon=True)
    thread.start()
    return thread


def configure(lane: Lane, values: Mapping[str, Any]) -> None:
    """The parameters the lane applies: fast_check, pose_reuse_window, the timeouts,
    max_queued_requests."""
    lane.set_config(bool(values["fast_check"]), round(values["pose_reuse_window"] * 1e9),
                    float(values["input_timeout"]), float(values["fixels_timeout"]),
                    int(values["max_queued_requests"]))


def _rows(a: np.ndarray) -> np.ndarray:
    """``a`` as the C-contiguous float64 (k, 3) array the lane copies (the cone's arrays
    are already: passed as they are, half the cost of a conversion per array)."""
    if a.ndim == 2 and a.dtype == np.float64 and a.flags.c_contiguous:
        return a
    return np.ascontiguousarray(a, dtype=np.float64).reshape(-1, 3)


def entry(mode: str, ans: Answer) -> tuple | None:
    """The lane's entry for one monitored answer, or None when the lane cannot answer
    that mode itself (another status, a wildcard mode)."""
    if ans.status not in (OK, MODE_INFEASIBLE) or ans.union is not None:
        return None
    cone = ans.cone
    if cone is None:
        if ans.status == OK:
            return None
        return (mode, ans.status, ans.message, False, 1.0, _NO_ROWS, _NO_ROWS, _NO_ROWS,
                _NO_ROWS)
    return (mode, ans.status, ans.message, bool(cone.feasible), 1.0 / float(cone.length_scale),
            _rows(cone.F_hat), _rows(cone.E_hat), _rows(cone.G_hat), _rows(cone.L_hat))


def offer(lane: Lane, generation: int, snap: Snapshot, answers: Mapping[str, Answer]) -> bool:
    """Hand the lane the monitored answers of ``snap``, computed after the lane's
    ``generation()`` was read; False (nothing changed) if a :func:`clear` came since."""
    snapshot = (snap.version, snap.frame_id, snap.pose_stamp or (0, 0),
                snap.fixels_stamp or (0, 0),
                -1 if snap.pose_received_ns is None else snap.pose_received_ns,
                -1 if snap.fixels_received_ns is None else snap.fixels_received_ns)
    entries = [e for mode, ans in answers.items() if (e := entry(mode, ans)) is not None]
    return lane.set_entries(generation, snapshot, entries)
