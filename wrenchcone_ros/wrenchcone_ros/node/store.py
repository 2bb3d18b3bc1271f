# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The input store: the node's newest inputs -> immutable snapshots, coalesced.

Data flow (one way): messages / parameters -> :class:`InputStore` -> immutable
:class:`Snapshot` (a Scene and the stamps of the inputs it was built from, with a version
number) -> answers (answers.py, cached in the snapshot) -> service replies and published
cones. A snapshot is never modified (its answer cache only grows), so an answer never
mixes a pose from one update with fixels from another. No ROS here beyond plain data:
the store is usable (and testable) without a node.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from wrenchcone_ros.core import Fixel, Scene, SceneError
from wrenchcone_ros.core.uncertainty import NOMINAL, Uncertainty
from wrenchcone_ros.node.parameters import (
    FixelPositions,
    build_scene,
    fixture_agrees,
    uncertainty_from_values,
)
from wrenchcone_ros.node.status import (
    NO_INPUTS,
    OK,
    SCENE_ERROR,
    SOURCE_SCENE_FILE,
    SOURCE_TOPIC,
)

Stamp = tuple[int, int]  # (sec, nanosec) of a message header


@dataclass(frozen=True)
class Snapshot:
    """One consistent, immutable version of the node's inputs.

    Parameters
    ----------
    version : int
        Increases by one with every new snapshot.
    scene : Scene or None
        The scene; None when ``status`` is not OK.
    status : int
        OK, NO_INPUTS or SCENE_ERROR.
    message : str
        Why there is no scene (empty when OK).
    frame_id : str
        The fixture frame of the inputs.
    pose_stamp : Stamp or None
        The header stamp of the pose used.
    fixels_stamp : Stamp or None
        The header stamp of the fixels used.
    pose_received_ns : int or None, optional
        The node-clock time (ns) the pose used was received (None: the scene's own).
    fixels_received_ns : int or None, optional
        The node-clock time (ns) the fixels used were received (None: the scene's own).
    answers : dict, optional
        The answers computed for this snapshot, by mode (a cache).
    uncertainty : Uncertainty or None, optional
        The uncertainty set of the parameters (None: the nominal model).
    fixture : str, optional
        The fixture in use, in words (count, radii, friction, where it came from).
    fixture_changes : int, optional
        How many times the fixture's fixel count or radii changed since the node started.
    pose_source, fixels_source : str, optional
        Where the pose and the fixels used came from: ``SOURCE_TOPIC`` (their stamps are
        the messages' header stamps), ``SOURCE_SCENE_FILE`` (the scene file's own, stamp
        None) or "" (no such input: NO_INPUTS).
    """

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
    #: The uncertainty set of the parameters it was built from (NOMINAL, the zero-width
    #: uncertainty, when none is set); its answers are computed for it (answers.py).
    uncertainty: Uncertainty = NOMINAL
    fixture: str = ""
    fixture_changes: int = 0
    pose_source: str = ""
    fixels_source: str = ""


def fixture_text(scene: Scene, source: str) -> str:
    """The fixture of ``scene`` in words: count, radii (m), friction, source."""
    radii = ", ".join(f"{f.radius:g}" for f in scene.fixels)
    mus = ", ".join(f"{scene.mu(i):g}" for i in range(scene.n_fixels))
    return (f"{scene.n_fixels} fixel(s), radii [{radii}] m, friction [{mus}] "
            f"(from {source})")


class StampOrderError(ValueError):
    """A message stamped earlier than the one in use (latest wins)."""


@dataclass
class _Input:
    """One input topic's newest accepted value. A message stamped earlier than the one
    in use is refused, unless it is earlier by more than the reset threshold: then the
    stamps jumped back (a recorded run played in a loop, a simulation reset) and the
    input's history starts again from it. A zero stamp (an unstamped message) carries no
    order and is always accepted."""

    value: Any = None
    stamp: Stamp | None = None
    received_ns: int | None = None

    def accept(self, value: Any, stamp: Stamp, received_ns: int, what: str,
               reset_threshold_ns: int | None = None) -> str | None:
        """Store the value; StampOrderError if it is older than the one in use by at most
        ``reset_threshold_ns`` (None: any older stamp is refused). Returns a line saying
        that the history was reset, or None."""
        reset = None
        if self.stamp is not None and stamp != (0, 0) and stamp < self.stamp:
            back_ns = _ns(self.stamp) - _ns(stamp)
            if reset_threshold_ns is None or back_ns <= reset_threshold_ns:
                raise StampOrderError(
                    f"stamp {stamp[0]}.{stamp[1]:09d} is older than the {what} in use "
                    f"({self.stamp[0]}.{self.stamp[1]:09d}); the newest message wins")
            reset = (f"stamps jumped back by {back_ns * 1e-9:.3f} s (more than "
                     f"stamp_reset_threshold): history reset, stamp "
                     f"{stamp[0]}.{stamp[1]:09d} accepted")
        self.value, self.stamp, self.received_ns = value, stamp, received_ns
        return reset


def _ns(stamp: Stamp) -> int:
    return stamp[0] * 1_000_000_000 + stamp[1]


#: Default of the stamp jump that resets an input's history (s): parameter
#: stamp_reset_threshold when the values do not give it.
DEFAULT_STAMP_RESET_THRESHOLD_S = 1.0


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
        #: value None: the scene's own fixels; else a tuple of Fixel (topic fixels) or
        #: FixelPositions (topic fixel_poses, radii from parameter fixel_radius)
        self.fixels = _Input()
        #: The topic the fixels in use came from (scene_file before any arrived)
        self.fixels_source = "scene_file"
        #: (count, radii) of the fixture of the last valid scene, and how often it changed
        self._fixture_key: tuple | None = None
        self.fixture_changes = 0
        self._fixture = ""
        self._noted: tuple | None = None
        #: Called with one line when the fixture's fixel count or radii change (and with
        #: the first fixture): the node logs it
        self.on_fixture: Callable[[str], None] = lambda line: None
        #: Called with one line when the inputs disagree (the uncertainty parameters name
        #: another number of fixels than the fixture has): the node warns
        self.on_refusal: Callable[[str], None] = lambda line: None
        self._disagreement: str | None = None
        #: Why the last fixture message was refused (inputs.py), named in NO_INPUTS
        #: while no fixture was accepted
        self.fixture_refusal = ""
        #: Whether the user gave the workpiece (a scene file, or workpiece.* parameters at
        #: start or since): without, nothing is answered (the node's own defaults are the
        #: paper's disc, never the user's part)
        self.workpiece_given = True
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
        #: ((values, fixels value), Scene) of the last scene built
        self._last_scene: tuple[tuple, Scene] | None = None
        #: Called with a workpiece's numerics caveat (``Workpiece.numerics_caveat``: its
        #: I/(m L^2) outside the verified range) when a scene with a new one is built.
        self.on_caveat: Callable[[str], None] | None = None
        self._caveat: str | None = None
        #: Called after an input other than a pulled pose changed (the node: the
        #: compiled lane forgets its cones, fastcheck.py)
        self.on_inputs_changed: Callable[[], None] = lambda: None
        #: Called (what, why) when an input's history was reset by a stamp jump back
        self.on_reset: Callable[[str, str], None] = lambda what, why: None

    def _reset_threshold_ns(self) -> int | None:
        threshold = self.values.get("stamp_reset_threshold", DEFAULT_STAMP_RESET_THRESHOLD_S)
        return None if threshold <= 0 else round(threshold * 1e9)

    def _accept(self, which: _Input, value: Any, stamp: Stamp, received_ns: int,
                what: str) -> None:
        reset = which.accept(value, stamp, received_ns, what, self._reset_threshold_ns())
        if reset is not None:
            self.on_reset(what, reset)

    def set_pose(self, pose: tuple[float, float, float], stamp: Stamp,
                 received_ns: int) -> None:
        """Store the newest pose; StampOrderError if it is older than the one in use."""
        with self.lock:
            self._accept(self.pose, pose, stamp, received_ns, "workpiece_pose")
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

    def set_fixels(self, fixels: tuple[Fixel, ...] | FixelPositions, stamp: Stamp,
                   received_ns: int, source: str = "fixels") -> bool:
        """Store the newest fixture (fixels with radii, or positions whose radii are
        fixel_radius's); StampOrderError if it is older than the one in use. The same
        fixture with the same stamp again (a latched message heard by both subscriptions
        of a topic) changes nothing: returns False."""
        with self.lock:
            if (stamp == self.fixels.stamp and fixels == self.fixels.value
                    and source == self.fixels_source):
                return False
            self._accept(self.fixels, fixels, stamp, received_ns, "fixels")
            self.fixels_source = source
            self._dirty = True
        self.on_inputs_changed()
        return True

    def touch(self) -> None:
        """Build the next snapshot anew (a refusal changed what NO_INPUTS says)."""
        with self.lock:
            self._dirty = True

    def set_values(self, values: dict[str, Any]) -> None:
        """New parameter values (already validated)."""
        with self.lock:
            self.values = values
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
            self._accept(self.pose, decoded[0], decoded[1], received_ns, "workpiece_pose")
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
        key = (values, self.fixels.value)
        last = self._last_scene
        if last is not None and all(a is b for a, b in zip(key, last[0])):
            return last[1].with_pose(*self.pose.value)
        scene = build_scene(self.base_scene, values, self.pose.value, self.fixels.value)
        self._last_scene = (key, scene)
        caveat = scene.workpiece.numerics_caveat
        if caveat != self._caveat and self.on_caveat is not None:
            self._caveat = caveat
            if caveat is not None:
                self.on_caveat(caveat)
        return scene

    def _build(self) -> Snapshot:
        """A new snapshot from the current inputs and parameter values (lock held)."""
        values = self.values
        self.version += 1
        status, message, scene, uncertainty = OK, "", None, NOMINAL
        missing = [name for name, have in (
            ("workpiece_pose", self.pose.stamp is not None),
            ("fixels", self.fixels.value is not None)) if not have]
        scene_file = values.get("scene_file", "")
        if not scene_file and not self.workpiece_given:
            status = NO_INPUTS
            message = ("no workpiece: without scene_file, set the workpiece parameters "
                       "(workpiece.shape, workpiece.vertices or workpiece.radius, "
                       "workpiece.mass, workpiece.inertia, workpiece.com)")
        elif missing and (values["wait_for_inputs"] or not scene_file):
            status = NO_INPUTS
            why = ("parameter wait_for_inputs is true" if scene_file else
                   "no scene_file: the node answers only for the user's pose and fixels")
            message = "no input yet on " + " and ".join(missing) + f" ({why})"
            if "fixels" in missing and self.fixture_refusal:
                message += f"; the last fixture message was refused: {self.fixture_refusal}"
        else:
            try:
                # values without uncertainty.* (a store used without a node): nominal
                uncertainty = (uncertainty_from_values(values)
                               if "uncertainty.friction" in values else NOMINAL)
                scene = self._scene(values)
                self._agrees(uncertainty, scene)
                self._note_fixture(scene)
            except (SceneError, ValueError) as exc:
                scene = None
                status, message = SCENE_ERROR, f"current inputs make no valid scene: {exc}"
            except Exception as exc:  # noqa: BLE001 - an input must never kill the node
                scene = None
                status, message = SCENE_ERROR, ("current inputs make no valid scene: "
                                                f"{type(exc).__name__}: {exc}")
        # where each input used came from: its topic, or (when the inputs were used:
        # not NO_INPUTS) the scene file's own
        own = "" if status == NO_INPUTS else SOURCE_SCENE_FILE
        return Snapshot(self.version, scene, status, message, values["fixture_frame"],
                        self.pose.stamp, self.fixels.stamp, self.pose.received_ns,
                        self.fixels.received_ns, uncertainty=uncertainty,
                        fixture=self._fixture, fixture_changes=self.fixture_changes,
                        pose_source=SOURCE_TOPIC if self.pose.stamp is not None else own,
                        fixels_source=(SOURCE_TOPIC if self.fixels.value is not None
                                       else own))

    def _agrees(self, uncertainty: Uncertainty, scene: Scene) -> None:
        """:func:`fixture_agrees`, its refusal said once (:attr:`on_refusal`) until it
        changes (lock held); SceneError when they disagree."""
        try:
            fixture_agrees(uncertainty, scene)
        except SceneError as exc:
            if str(exc) != self._disagreement:
                self._disagreement = str(exc)
                self.on_refusal(f"no answers for this fixture: {exc}")
            raise
        self._disagreement = None

    def _note_fixture(self, scene: Scene) -> None:
        """Remember the fixture of a valid scene; a fixel count or radius that differs
        from the last one's is a new fixture: counted and said once (:attr:`on_fixture`)
        (lock held)."""
        noted = (scene.fixels, scene.friction, self.fixels_source)
        if self._noted is not None and all(x is y for x, y in zip(noted, self._noted)):
            return  # the same fixture (a pose stream: the scene moved, nothing else)
        self._noted = noted
        self._fixture = fixture_text(scene, self.fixels_source)
        key = (scene.n_fixels, tuple(f.radius for f in scene.fixels))
        if key == self._fixture_key:
            return
        before, self._fixture_key = self._fixture_key, key
        if before is None:
            self.on_fixture(f"fixture: {self._fixture}")
            return
        self.fixture_changes += 1
        self.on_fixture(f"new fixture ({before[0]} -> {key[0]} fixel(s)"
                        f"{'' if before[1] == key[1] else ', radii changed'}): "
                        f"{self._fixture}")
