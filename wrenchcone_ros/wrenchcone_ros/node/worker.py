# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The publishing worker: one thread that publishes the newest snapshot, never once per
message, with a public timing hook.

:class:`PublishWorker` waits for a change (a pose waiting in the PoseInbox, or its guard
condition: a fixel message, parameters, a pose a request took), takes the newest
snapshot and publishes it on every per-snapshot publisher of the node, then repeats: it
runs at most as fast as the monitored cones can be computed (or ``max_publish_rate``
snapshots a second) and wakes periodically to notice inputs going stale. Before each
part of a step (the snapshot's cones, each publisher) it lets the fast-lane requests in
progress finish first (:meth:`PublishWorker.serving`, at most :data:`YIELD_MAX_S` each):
under the GIL a request would otherwise wait for the worker's time slices.

Timing hook: :attr:`PublishWorker.on_step`, when set, is called after every step with a
:class:`StepTiming` (in the worker's thread; keep it short). Benchmarks use it instead of
wrapping the worker's methods.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from wrenchcone_ros.node.answers import Answer, monitored_answers
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.store import Snapshot

#: The worker lets service requests in progress go first: before each part of a step it
#: waits until none is running, but never longer than this (s), so a constant stream of
#: requests cannot stop the publication.
YIELD_MAX_S = 0.02
#: The worker checks staleness at least this often (s) when a timeout is set and an
#: input it applies to is fresh; otherwise it sleeps until woken (an input, a parameter
#: change, the node's end): an idle node's worker never wakes up.
STALENESS_POLL_MIN_S, STALENESS_POLL_MAX_S = 0.01, 0.5

#: What a step returns and the next one is given: (snapshot version, stale).
StepState = tuple[int, bool]


@dataclass(frozen=True)
class StepTiming:
    """One step of the publishing worker, as :attr:`PublishWorker.on_step` receives it.

    ``started`` is ``time.perf_counter()`` (CLOCK_MONOTONIC on Linux: comparable across
    processes of one machine) and ``started_wall`` ``time.time()``, both in s, at the
    step's start; ``duration_s`` how long the step took (s)."""

    started: float
    started_wall: float
    duration_s: float
    version: int  # the snapshot's inputs version
    modes: int  # monitored answers handed to the publishers (0 when stale)
    published: bool  # the snapshot was published (False: it was published already)
    stale: bool  # the snapshot's inputs were older than their timeout


class PublishWorker:
    """The node's publishing worker (a thread started by :meth:`start`).

    ``node`` provides what the worker reads at each step: ``snapshot``,
    ``freshness(snap)``, ``snapshot_publishers``, ``limits``,
    ``input_timeout``, ``fixels_timeout``, ``max_publish_rate`` and ``get_logger()``;
    ``inbox`` is the PoseSlot the worker sleeps on (``wait(timeout)``, ``wake()``).
    """

    def __init__(self, node: Any, inbox: Any,
                 on_step: Callable[[StepTiming], None] | None = None) -> None:
        self.node = node
        self.inbox = inbox
        #: Called after each step with its :class:`StepTiming` (None: nothing is called).
        self.on_step = on_step
        self._stop = threading.Event()
        self._can_go_stale = True  # until the first step says
        self._requests = 0  # fast-lane requests in progress (see serving())
        self._idle = threading.Condition()
        self.thread = threading.Thread(target=self._loop, name="wrenchcone-publish",
                                       daemon=True)

    # --- lifecycle ------------------------------------------------------------------
    def start(self) -> None:
        self.thread.start()

    def stop(self, timeout: float | None = None) -> None:
        """End the thread (it finishes the step in progress) and wait for it."""
        self._stop.set()
        self.inbox.wake()
        if self.thread.is_alive() and self.thread is not threading.current_thread():
            self.thread.join(timeout)

    def wake(self) -> None:
        """Something changed (a fixel message, parameters, a pose a request took): the
        worker publishes the newest snapshot. A new pose waiting wakes it by itself."""
        if threading.current_thread() is not self.thread:
            self.inbox.wake()

    # --- requests go first ----------------------------------------------------------
    @contextmanager
    def serving(self) -> Iterator[None]:
        """Marks a fast-lane request in progress: the worker waits for it."""
        with self._idle:
            self._requests += 1
        try:
            yield
        finally:
            with self._idle:
                self._requests -= 1
                if self._requests == 0:
                    self._idle.notify_all()

    def _let_requests_go_first(self) -> None:
        with self._idle:
            self._idle.wait_for(lambda: self._requests == 0, YIELD_MAX_S)

    # --- one step -------------------------------------------------------------------
    def publish(self, snap: Snapshot, fresh: Freshness | None = None
                ) -> tuple[Freshness, dict[str, Answer]]:
        """Publish one snapshot on every per-snapshot publisher (the cone topics first:
        what a controller waits for). ``fresh``: the snapshot's freshness, if the caller
        has it already. Returns the freshness and the monitored answers."""
        node = self.node
        if fresh is None:
            fresh = node.freshness(snap)
        pause = (self._let_requests_go_first
                 if threading.current_thread() is self.thread else None)
        answers = self.monitored_answers(snap, fresh, pause)
        for pub in node.snapshot_publishers:
            if pause is not None:
                pause()
            pub.publish(snap, answers, fresh)
        return fresh, answers

    def monitored_answers(self, snap: Snapshot, fresh: Freshness,
                          pause: Callable[[], None] | None = None) -> dict[str, Answer]:
        """Every monitored mode's answer for ``snap`` (cached in it); none when stale."""
        if fresh.stale:
            return {}
        node = self.node
        modes = sorted(set().union(*(p.modes() for p in node.snapshot_publishers)))
        return monitored_answers(snap, modes, node.get_logger().error, node.limits, pause)

    def step(self, last: StepState | None) -> StepState:
        """One step: publish the newest snapshot unless ``last`` (what the previous step
        returned: version, stale) says it is published already. Calls :attr:`on_step`."""
        started, started_wall = time.perf_counter(), time.time()
        snap = self.node.snapshot
        fresh = self.node.freshness(snap)
        self._can_go_stale = can_go_stale(snap, fresh, self.node.input_timeout,
                                          self.node.fixels_timeout)
        state = (snap.version, bool(fresh.stale))
        published, modes = False, 0
        if last != state:
            fresh, answers = self.publish(snap, fresh)
            published, modes = True, len(answers)
            state = (snap.version, bool(fresh.stale))
        hook = self.on_step
        if hook is not None:
            hook(StepTiming(started, started_wall, time.perf_counter() - started,
                            snap.version, modes, published, state[1]))
        return state

    # --- the loop -------------------------------------------------------------------
    def poll_period(self) -> float | None:
        """How long the worker sleeps at most without a change (s): often enough to
        notice an input going stale; None (until woken) when no input can go stale (none
        received with a timeout set, or stale already: only a new input changes that)."""
        if not self._can_go_stale:
            return None
        node = self.node
        timeouts = [t for t in (node.input_timeout, node.fixels_timeout) if t > 0]
        if not timeouts:
            return STALENESS_POLL_MAX_S
        return min(max(min(timeouts) / 4, STALENESS_POLL_MIN_S), STALENESS_POLL_MAX_S)

    def _wait_for_rate(self, started: float) -> None:
        """At most ``max_publish_rate`` snapshots a second: wait until 1 / rate s after
        the last publication ``started`` (time.monotonic). The rate is read again at
        least every poll period, so a new value applies within that (a single wait of
        1 / rate s could not be cut short but by the node's end)."""
        while not self._stop.is_set() and self.node.max_publish_rate > 0:
            rest = started + 1.0 / self.node.max_publish_rate - time.monotonic()
            if rest <= 0:
                return
            self._stop.wait(min(rest, self.poll_period() or STALENESS_POLL_MAX_S))

    def _loop(self) -> None:
        """Newest snapshot only, as fast as it can (or at most ``max_publish_rate`` per
        second), never once per message."""
        last: StepState | None = None
        started = 0.0
        while not self._stop.is_set():
            try:  # nothing may end this thread but the node's end
                # until a pose is waiting, something else changed, or a poll is due
                self.inbox.wait(self.poll_period())
                self._wait_for_rate(started)
                started = time.monotonic()
                if self._stop.is_set():
                    return
                self._let_requests_go_first()
                last = self.step(last)
            except Exception as exc:  # noqa: BLE001 - the worker must keep running
                self.node.get_logger().error(f"publishing worker: {exc!r}",
                                             throttle_duration_sec=5.0)
                self._stop.wait(STALENESS_POLL_MIN_S)  # never a busy loop on an error


def can_go_stale(snap: Snapshot, fresh: Freshness, input_timeout: float,
                 fixels_timeout: float) -> bool:
    """Whether time alone can make ``snap`` stale: a received input has a timeout (s, 0 =
    none) and the snapshot is not stale yet.

    Parameters
    ----------
    snap : Snapshot
        The snapshot.
    fresh : Freshness
        Its freshness now.
    input_timeout, fixels_timeout : float
        The pose's and the fixels' timeouts (s; 0 = never stale).

    Returns
    -------
    bool
        True when the worker must check the snapshot's staleness again later.
    """
    if fresh.stale:
        return False
    return ((snap.pose_received_ns is not None and input_timeout > 0)
            or (snap.fixels_received_ns is not None and fixels_timeout > 0))


def lower_thread_priority(thread: threading.Thread, nice: int,
                          warn: Callable[[str], None]) -> int:
    """Give a started ``thread`` the scheduling niceness ``nice`` (0-19; Linux: per
    thread, so nothing else of the process changes) and return the niceness it has. The
    publishing worker is the node's one long CPU consumer (about a core under a 1 kHz
    pose stream with 16 modes); at a lower priority it yields the CPU to the service
    threads and to the other processes of the machine (parameter worker_nice). Where that
    is not allowed, ``warn`` says so once and the thread keeps its priority."""
    tid = thread.native_id
    try:
        if nice:
            os.setpriority(os.PRIO_PROCESS, tid, nice)
        return os.getpriority(os.PRIO_PROCESS, tid)
    except (OSError, AttributeError, TypeError) as exc:
        warn(f"worker_nice {nice}: the publishing worker's priority was not changed: {exc}")
        return 0
