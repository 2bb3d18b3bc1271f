"""Inputs -> immutable snapshots -> cached answers.

Data flow (one way): messages / parameters -> :class:`InputStore` -> immutable
:class:`Snapshot` (a Scene and the stamps of the inputs it was built from, with a version
number) -> (snapshot, mode) -> :class:`Answer` (cached in the snapshot) -> service replies
and published cones. A snapshot is never modified (its cache only grows), so an answer
never mixes a pose from one update with fixels from another. No ROS here beyond plain
data: the store is usable (and testable) without a node.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

from wrenchcone_ros.core import (
    Cone,
    ConeUnion,
    ModeError,
    ModeSyntaxError,
    Scene,
    SceneError,
    wrench_cone,
    wrench_cones,
)
from wrenchcone_ros.core.budget import TimeBudgetExceeded
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.core.modes import WILDCARDS, count_concrete_modes
from wrenchcone_ros.node.parameters import build_scene
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    NO_INPUTS,
    OK,
    SCENE_ERROR,
)

#: At most this many answers are cached per snapshot (a client asking for many distinct
#: modes cannot grow the node's memory without bound).
CACHE_LIMIT = 1024

Stamp = tuple[int, int]  # (sec, nanosec) of a message header


@dataclass(frozen=True)
class Answer:
    """The outcome of one (snapshot, mode): a status, a message and the cone if any."""

    status: int
    message: str
    cone: Cone | None = None
    union: ConeUnion | None = None  # a mode with wildcards: the union of its modes' cones
    seconds: float = 0.0  # how long computing it took (reported in /diagnostics)


@dataclass(frozen=True)
class Snapshot:
    """One consistent, immutable version of the node's inputs."""

    version: int
    scene: Scene | None  # None when status != OK
    status: int  # OK, NO_INPUTS or SCENE_ERROR
    message: str
    frame_id: str
    pose_stamp: Stamp | None
    fixels_stamp: Stamp | None
    #: Node-clock times (ns) at which the pose / fixels used were received (None: the
    #: scene's own, never received); the age of an answer is measured from these.
    pose_received_ns: int | None = None
    fixels_received_ns: int | None = None
    answers: dict = field(default_factory=dict, compare=False, repr=False)


def compute_answer(snapshot: Snapshot, mode: str) -> Answer:
    """The answer of (snapshot, mode), without caching. Raises only TimeBudgetExceeded
    (when computed under a time budget, see core/budget.py)."""
    if snapshot.scene is None:
        return Answer(snapshot.status, snapshot.message)
    try:
        cone = wrench_cone(snapshot.scene, mode)  # a ConeUnion for a mode with wildcards
    except TimeBudgetExceeded:  # the request's own budget (services.py): not an answer
        raise
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return answer_of(mode, exc)
    return answer_of(mode, cone)


def answer_of(mode: str, cone: Cone | ConeUnion | Exception, seconds: float = 0.0
              ) -> Answer:
    """The answer for what the core gave for ``mode``: a cone, a union of cones, or the
    exception it raised (ModeSyntaxError, ModeError, SceneError, anything else);
    ``seconds``: how long computing it took."""
    if type(cone) is Cone:  # the common case first (a Cone has no subclasses)
        if cone.feasible:
            return Answer(OK, "", cone, None, seconds)
        return Answer(MODE_INFEASIBLE, _infeasible_message(mode), cone, None, seconds)
    return replace(_answer_of(mode, cone), seconds=seconds) if seconds else _answer_of(
        mode, cone)


def _infeasible_message(mode: str) -> str:
    return (f"mode {mode!r} is infeasible: no wrench realises it (no rigid-body "
            "acceleration meets its strict conditions), so no wrench is consistent with it")


def _answer_of(mode: str, cone: Cone | ConeUnion | Exception) -> Answer:
    if isinstance(cone, ModeSyntaxError):
        return Answer(INVALID_MODE, str(cone))
    if isinstance(cone, ModeError):
        return Answer(MODE_NOT_ALLOWED, str(cone))
    if isinstance(cone, SceneError):
        return Answer(SCENE_ERROR, str(cone))
    if isinstance(cone, Exception):
        return Answer(INTERNAL_ERROR,
                      f"cone computation failed: {type(cone).__name__}: {cone}")
    if isinstance(cone, ConeUnion):
        if not cone.feasible:
            return Answer(MODE_INFEASIBLE,
                          f"mode {mode!r} is infeasible: none of its modes "
                          f"{list(cone.impossible)} is realised by any wrench", union=cone)
        return Answer(OK, "", union=cone)
    if not cone.feasible:
        return Answer(MODE_INFEASIBLE, _infeasible_message(mode), cone)
    return Answer(OK, "", cone)


@dataclass(frozen=True)
class Limits:
    """Bounds on the work of one request (node parameters max_*; docs/node.md)."""

    max_mode_length: int = 64
    max_concrete_modes: int = 64
    max_classify_nodes: int = 2000
    #: Seconds a fast-lane request (check_wrench, get_cone) may compute; 0 = no limit.
    max_request_time: float = 0.05


def over_limit(snapshot: Snapshot, mode: str, limits: Limits) -> Answer | None:
    """LIMIT_EXCEEDED if ``mode`` is over a limit, counted before any expansion; else
    None. Cheap: the length first, then the count of a wildcard's concrete modes."""
    if not isinstance(mode, str) or snapshot.scene is None:
        return None
    if len(mode) > limits.max_mode_length:
        return Answer(LIMIT_EXCEEDED,
                      f"mode string of {len(mode)} characters is longer than max_mode_length "
                      f"({limits.max_mode_length}); give one letter per fixel")
    if has_wildcards(mode):
        scene = snapshot.scene
        try:
            n = count_concrete_modes(mode, scene.in_contact)
        except ModeError:
            return None  # the computation reports the mode error itself
        if n > limits.max_concrete_modes:
            return Answer(LIMIT_EXCEEDED,
                          f"mode {mode!r} expands to {n} concrete modes, more than "
                          f"max_concrete_modes ({limits.max_concrete_modes}); use fewer "
                          "wildcards or raise the parameter")
    return None


@lru_cache(maxsize=4096)
def has_wildcards(mode: str) -> bool:
    """Whether a mode string holds a wildcard (cached: the same monitored modes are
    asked about for every pose)."""
    return any(ch in WILDCARDS for ch in mode)


def cached_answer(snapshot: Snapshot, mode: str,
                  on_error: Callable[[str], None] | None = None,
                  limits: Limits | None = None) -> Answer:
    """Cached answer of (snapshot, mode): each is computed at most once per snapshot.
    ``on_error`` gets the log line of an INTERNAL_ERROR answer; a mode over ``limits``
    gets LIMIT_EXCEEDED without any computation."""
    ans = snapshot.answers.get(mode) if isinstance(mode, str) else None
    if ans is None:
        start = time.perf_counter()
        ans = over_limit(snapshot, mode, limits or Limits()) or compute_answer(snapshot, mode)
        ans = replace(ans, seconds=time.perf_counter() - start)
        if ans.status == INTERNAL_ERROR and on_error is not None:
            on_error(f"mode {mode!r}: {ans.message}")
        if isinstance(mode, str) and len(snapshot.answers) < CACHE_LIMIT:
            snapshot.answers[mode] = ans
    return ans


def monitored_answers(snapshot: Snapshot, modes: Iterable[str],
                      on_error: Callable[[str], None] | None = None,
                      limits: Limits | None = None,
                      pause: Callable[[], None] | None = None) -> dict[str, Answer]:
    """The answers of every monitored mode for one snapshot (mode -> Answer), cached.

    The one place where the per-snapshot work of the published cones is done: every
    publisher receives this dict. The modes not cached yet and within ``limits`` are
    computed in ONE call of the core's batched engine (:func:`wrench_cones`: the pose's
    arrays once, every mode in one kernel pass); each answer's ``seconds`` is its share
    of that call. Should the batch itself fail, each mode is computed on its own, so
    one bad mode never costs the others their answer. ``pause()`` runs before the batch
    and before each mode computed on its own: the node uses it to let service requests
    in progress go first.
    """
    modes = list(modes)
    limits = limits or Limits()
    todo = [m for m in dict.fromkeys(modes) if isinstance(m, str)
            and m not in snapshot.answers and snapshot.scene is not None
            and over_limit(snapshot, m, limits) is None]
    if todo:
        if pause is not None:
            pause()
        start = time.perf_counter()
        try:
            cones = wrench_cones(snapshot.scene, todo, errors="return")
        except Exception:  # noqa: BLE001 - fall back to one mode at a time below
            cones = None
        if cones is not None:
            share = (time.perf_counter() - start) / len(todo)
            for mode, cone in zip(todo, cones):
                ans = answer_of(mode, cone, share)
                if ans.status == INTERNAL_ERROR and on_error is not None:
                    on_error(f"mode {mode!r}: {ans.message}")
                if len(snapshot.answers) < CACHE_LIMIT:
                    snapshot.answers[mode] = ans
    out = {}
    for mode in modes:
        if pause is not None and mode not in snapshot.answers:
            pause()
        out[mode] = cached_answer(snapshot, mode, on_error, limits)
    return out


def classifier(snapshot: Snapshot) -> ModeClassifier:
    """The snapshot's mode classifier (created once, caches its cones)."""
    key = ("classifier",)
    clf = snapshot.answers.get(key)
    if clf is None:
        clf = snapshot.answers.setdefault(key, ModeClassifier(snapshot.scene))
    return clf


class StampOrderError(ValueError):
    """A message stamped earlier than the one in use (latest wins)."""


@dataclass
class _Input:
    """One input topic's newest accepted value. A message stamped earlier than the one
    in use is refused; a zero stamp (an unstamped message) carries no order and is
    always accepted."""

    value: Any = None
    stamp: Stamp | None = None
    received_ns: int | None = None

    def accept(self, value: Any, stamp: Stamp, received_ns: int, what: str) -> None:
        if self.stamp is not None and stamp != (0, 0) and stamp < self.stamp:
            raise StampOrderError(
                f"stamp {stamp[0]}.{stamp[1]:09d} is older than the {what} in use "
                f"({self.stamp[0]}.{self.stamp[1]:09d}); the newest message wins")
        self.value, self.stamp, self.received_ns = value, stamp, received_ns


class InputStore:
    """The node's newest inputs and the snapshot made from them, coalesced.

    Subscriptions only store (:meth:`set_pose`, :meth:`set_fixels`: cheap, under
    :attr:`lock`); a snapshot is built only when someone needs one (:meth:`current`,
    from a service or the publishing worker), from whatever is newest then. So a burst
    of messages costs one scene build, and nothing queues behind it.
    """

    def __init__(self, base_scene: Scene, values: dict[str, Any]) -> None:
        self.lock = threading.Lock()
        self.base_scene = base_scene
        self.values = values  # parameter values (read_values), replaced on change
        self.pose = _Input(base_scene.pose)
        self.fixels = _Input()  # value None: the scene's own fixels
        self.radius_overridden = False
        self.version = 0
        self._dirty = True
        self._snapshot = Snapshot(0, None, NO_INPUTS, "starting", "", None, None)
        #: The newest pose message, not decoded yet: (serialized bytes, received_ns)
        self._raw_pose: tuple[bytes, int] | None = None
        #: Takes the newest pose message waiting in the middleware, if any, into
        #: :meth:`set_raw_pose` (inputs.py: the pose is pulled when a snapshot is needed)
        self.pull_pose: Callable[[], None] | None = None
        #: bytes -> (pose, stamp), or None when refused (inputs.py; logs the refusal)
        self.decode_pose: Callable[[bytes], tuple[Any, Stamp] | None] | None = None
        #: Logs a refused pose (inputs.py)
        self.refuse_pose: Callable[[str], None] = lambda why: None
        #: ((values, fixels value, radius_overridden), Scene) of the last scene built
        self._last_scene: tuple[tuple, Scene] | None = None
        #: Called after an input other than a pulled pose changed (the node: the
        #: compiled lane forgets its cones, fastcheck.py)
        self.on_inputs_changed: Callable[[], None] = lambda: None

    def set_pose(self, pose: tuple[float, float, float], stamp: Stamp,
                 received_ns: int) -> None:
        """Store the newest pose; StampOrderError if it is older than the one in use."""
        with self.lock:
            self.pose.accept(pose, stamp, received_ns, "pose")
            self._dirty = True
        self.on_inputs_changed()

    def set_raw_pose(self, data: bytes, received_ns: int) -> None:
        """Keep the newest pose message undecoded: it is decoded and checked (frame,
        values, stamp order) only when a snapshot is taken, so a burst costs one decode
        (at 1 kHz, decoding every message into Python objects cost a tenth of a core).
        Called by :attr:`pull_pose` (the node) or directly (tests).
        Only the newest message of a burst is examined; if it is refused, the inputs stay
        as they were."""
        self._raw_pose = (data, received_ns)  # one reference assignment: atomic

    def set_fixels(self, positions: list[tuple[float, float]], stamp: Stamp,
                   received_ns: int) -> None:
        with self.lock:
            self.fixels.accept(positions, stamp, received_ns, "fixels")
            self._dirty = True
        self.on_inputs_changed()

    def set_values(self, values: dict[str, Any], radius_overridden: bool = False) -> None:
        """New parameter values (already validated)."""
        with self.lock:
            self.values = values
            self.radius_overridden = self.radius_overridden or radius_overridden
            self._dirty = True
        self.on_inputs_changed()

    @property
    def snapshot(self) -> Snapshot:
        """The newest snapshot (built now if the inputs changed since the last one)."""
        return self.current()

    def current(self, reuse_window_ns: int = 0) -> Snapshot:
        """The newest snapshot, built now if the inputs changed. With ``reuse_window_ns``
        > 0, a pose that arrived at most that long after the current snapshot's pose is
        left for later and the current snapshot is returned (no decode, no scene build,
        its cached cones): node parameter ``pose_reuse_window``. Any other change (a
        fixel message, parameters) always builds a new snapshot."""
        if self.pull_pose is not None:
            self.pull_pose()
        raw = self._raw_pose
        if not self._dirty and (raw is None or self._reusable(raw[1], reuse_window_ns)):
            return self._snapshot
        with self.lock:
            raw, self._raw_pose = self._raw_pose, None
            if raw is not None and self.decode_pose is not None:
                self._take_raw_pose(*raw)
            if self._dirty:
                self._snapshot = self._build()
                self._dirty = False
            return self._snapshot

    def _reusable(self, received_ns: int, window_ns: int) -> bool:
        """Whether a pose received at ``received_ns`` is within ``window_ns`` of the
        current snapshot's pose (never for a snapshot without a received pose)."""
        used = self._snapshot.pose_received_ns
        return window_ns > 0 and used is not None and received_ns - used <= window_ns

    def _take_raw_pose(self, data: bytes, received_ns: int) -> None:
        """Decode and store the newest pose message (lock held); never raises."""
        decoded = self.decode_pose(data)
        if decoded is None:
            return
        try:
            self.pose.accept(decoded[0], decoded[1], received_ns, "pose")
        except StampOrderError as exc:
            self.refuse_pose(str(exc))
            return
        self._dirty = True

    def _scene(self, values: dict[str, Any]) -> Scene:
        """The Scene of the current inputs (lock held). When only the pose changed since
        the last scene (the same parameter values, fixels and radius rule: compared by
        identity, every change replaces them), that scene moved to the new pose: the
        same Scene as :func:`build_scene` makes, without rebuilding and revalidating the
        workpiece and fixels (a third of a scene build at a pose stream)."""
        key = (values, self.fixels.value, self.radius_overridden)
        last = self._last_scene
        if last is not None and all(a is b for a, b in zip(key, last[0])):
            return last[1].with_pose(*self.pose.value)
        scene = build_scene(self.base_scene, values, self.pose.value, self.fixels.value,
                            self.radius_overridden)
        self._last_scene = (key, scene)
        return scene

    def _build(self) -> Snapshot:
        """A new snapshot from the current inputs and parameter values (lock held)."""
        values = self.values
        self.version += 1
        status, message, scene = OK, "", None
        missing = [name for name, have in (
            ("workpiece_pose", self.pose.stamp is not None),
            ("fixels", self.fixels.value is not None)) if not have]
        if values["wait_for_inputs"] and missing:
            status = NO_INPUTS
            message = ("no input yet on " + " and ".join(missing) + " (parameter "
                       "wait_for_inputs is true)")
        else:
            try:
                scene = self._scene(values)
            except (SceneError, ValueError) as exc:
                status, message = SCENE_ERROR, f"current inputs make no valid scene: {exc}"
            except Exception as exc:  # noqa: BLE001 - an input must never kill the node
                status, message = SCENE_ERROR, ("current inputs make no valid scene: "
                                                f"{type(exc).__name__}: {exc}")
        return Snapshot(self.version, scene, status, message, values["fixture_frame"],
                        self.pose.stamp, self.fixels.stamp, self.pose.received_ns,
                        self.fixels.received_ns)


@dataclass(frozen=True)
class Freshness:
    """How old a snapshot's received inputs are, at one instant of the node clock."""

    age_s: float  # of the oldest received input used (0 when none was received)
    stale: str = ""  # empty when fresh; else says which input is how old


def freshness(snap: Snapshot, now_ns: int, input_timeout: float,
              fixels_timeout: float) -> Freshness:
    """Compare the ages of the snapshot's pose and fixels with their timeouts (s; 0 =
    never stale). An input never received (the scene's own) is never stale."""
    ages, stale = [], []
    for what, received, timeout, param in (
            ("workpiece_pose", snap.pose_received_ns, input_timeout, "input_timeout"),
            ("fixels", snap.fixels_received_ns, fixels_timeout, "fixels_timeout")):
        if received is None:
            continue
        age = max(0.0, (now_ns - received) * 1e-9)
        ages.append(age)
        if timeout > 0 and age > timeout:
            stale.append(f"{what} last received {age:.3f} s ago ({param} {timeout:g} s)")
    return Freshness(max(ages, default=0.0),
                     "inputs are stale: " + "; ".join(stale) if stale else "")
