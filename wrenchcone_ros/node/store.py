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
from typing import Any

from wrenchcone_ros.core import (
    Cone,
    ConeUnion,
    ModeError,
    ModeSyntaxError,
    Scene,
    SceneError,
    wrench_cone,
)
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.node.parameters import build_scene
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
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
    answers: dict = field(default_factory=dict, compare=False, repr=False)


def compute_answer(snapshot: Snapshot, mode: str) -> Answer:
    """The answer of (snapshot, mode), without caching. Never raises."""
    if snapshot.scene is None:
        return Answer(snapshot.status, snapshot.message)
    scene = snapshot.scene
    try:
        cone = wrench_cone(scene, mode)  # a ConeUnion for a mode with wildcards
    except ModeSyntaxError as exc:
        return Answer(INVALID_MODE, str(exc))
    except ModeError as exc:
        return Answer(MODE_NOT_ALLOWED, str(exc))
    except SceneError as exc:
        return Answer(SCENE_ERROR, str(exc))
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return Answer(INTERNAL_ERROR, f"cone computation failed: {type(exc).__name__}: {exc}")
    if isinstance(cone, ConeUnion):
        if not cone.feasible:
            return Answer(MODE_INFEASIBLE,
                          f"mode {mode!r} is infeasible: none of its modes "
                          f"{list(cone.impossible)} is realised by any wrench", union=cone)
        return Answer(OK, "", union=cone)
    if not cone.feasible:
        return Answer(MODE_INFEASIBLE,
                      f"mode {mode!r} is infeasible: no wrench realises it (no rigid-body "
                      "acceleration meets its strict conditions), so no wrench is "
                      "consistent with it", cone)
    return Answer(OK, "", cone)


def cached_answer(snapshot: Snapshot, mode: str,
                  on_error: Callable[[str], None] | None = None) -> Answer:
    """Cached answer of (snapshot, mode): each is computed at most once per snapshot.
    ``on_error`` gets the log line of an INTERNAL_ERROR answer."""
    ans = snapshot.answers.get(mode) if isinstance(mode, str) else None
    if ans is None:
        start = time.perf_counter()
        ans = compute_answer(snapshot, mode)
        ans = replace(ans, seconds=time.perf_counter() - start)
        if ans.status == INTERNAL_ERROR and on_error is not None:
            on_error(f"mode {mode!r}: {ans.message}")
        if isinstance(mode, str) and len(snapshot.answers) < CACHE_LIMIT:
            snapshot.answers[mode] = ans
    return ans


def monitored_answers(snapshot: Snapshot, modes: Iterable[str],
                      on_error: Callable[[str], None] | None = None) -> dict[str, Answer]:
    """The answers of every monitored mode for one snapshot (mode -> Answer), cached.

    The one place where the per-snapshot work of the published cones is done: every
    publisher receives this dict, so a batched engine (all modes of one scene at once)
    replaces this function body and nothing else.
    """
    return {mode: cached_answer(snapshot, mode, on_error) for mode in modes}


def classifier(snapshot: Snapshot) -> ModeClassifier:
    """The snapshot's mode classifier (created once, caches its cones)."""
    key = ("classifier",)
    clf = snapshot.answers.get(key)
    if clf is None:
        clf = snapshot.answers.setdefault(key, ModeClassifier(snapshot.scene))
    return clf


class InputStore:
    """The node's current inputs (pose, fixels, their stamps) and the snapshot made from
    them. Writers and :meth:`rebuild` hold :attr:`lock`; readers take :attr:`snapshot`
    (one attribute read, so always a whole snapshot)."""

    def __init__(self, base_scene: Scene) -> None:
        self.lock = threading.Lock()
        self.base_scene = base_scene
        self.pose: tuple[float, float, float] = base_scene.pose
        self.pose_stamp: Stamp | None = None
        self.fixel_positions: list[tuple[float, float]] | None = None  # None: the scene's
        self.fixels_stamp: Stamp | None = None
        #: time.monotonic() when the last pose / fixels message was stored (None: never)
        self.pose_received: float | None = None
        self.fixels_received: float | None = None
        self.radius_overridden = False
        self.version = 0
        self.snapshot = Snapshot(0, None, NO_INPUTS, "starting", "", None, None)

    def set_pose(self, pose: tuple[float, float, float], stamp: Stamp) -> None:
        with self.lock:
            self.pose, self.pose_stamp = pose, stamp
            self.pose_received = time.monotonic()

    def set_fixels(self, positions: list[tuple[float, float]], stamp: Stamp) -> None:
        with self.lock:
            self.fixel_positions, self.fixels_stamp = positions, stamp
            self.fixels_received = time.monotonic()

    def rebuild(self, values: dict[str, Any]) -> Snapshot:
        """Make (and keep) a new snapshot from the current inputs and parameter values."""
        with self.lock:
            self.version += 1
            status, message, scene = OK, "", None
            missing = [name for name, have in (
                ("workpiece_pose", self.pose_stamp is not None),
                ("fixels", self.fixel_positions is not None)) if not have]
            if values["wait_for_inputs"] and missing:
                status = NO_INPUTS
                message = ("no input yet on " + " and ".join(missing) + " (parameter "
                           "wait_for_inputs is true)")
            else:
                try:
                    scene = build_scene(self.base_scene, values, self.pose,
                                        self.fixel_positions, self.radius_overridden)
                except (SceneError, ValueError) as exc:
                    status, message = SCENE_ERROR, f"current inputs make no valid scene: {exc}"
            snap = Snapshot(self.version, scene, status, message, values["fixture_frame"],
                            self.pose_stamp, self.fixels_stamp)
            self.snapshot = snap
        return snap
