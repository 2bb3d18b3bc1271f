"""The publishing worker: one thread that publishes the newest snapshot, never once per
message, with a public timing hook.

:class:`PublishWorker` waits for a change (a pose waiting in the PoseInbox, or its guard
condition: a fixel message, parameters, a pose a request took), takes the newest
snapshot and publishes it on every per-snapshot publisher of the node, then repeats: it
runs at most as fast as the monitored cones can be computed (or ``max_publish_rate``
snapshots a second) and wakes periodically to notice inputs going stale. Before each
part of a step (the snapshot's cones, each publisher) it lets the fast-lane requests in
progress finish first (:meth:`PublishWorker.serving`, at most :data:`YIELD_MAX_S` each):
under the GIL a request would otherwise wait for the worker's time slices. It offers
each snapshot's monitored cones to the compiled lane (fastcheck.py), again when the lane
refused them (:meth:`PublishWorker.step`).

Timing hook: :attr:`PublishWorker.on_step`, when set, is called after every step with a
:class:`StepTiming` (in the worker's thread; keep it short). Benchmarks use it instead of
wrapping the worker's methods.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from wrenchcone_ros.node import fastcheck
from wrenchcone_ros.node.answers import Answer, monitored_answers
from wrenchcone_ros.node.freshness import Freshness
from wrenchcone_ros.node.store import Snapshot

#: The worker lets service requests in progress go first: before each part of a step it
#: waits until none is running, but never longer than this (s), so a constant stream of
#: requests cannot stop the publication.
YIELD_MAX_S = 0.02
#: The worker checks staleness at least this often (s) when a timeout is set.
STALENESS_POLL_MIN_S, STALENESS_POLL_MAX_S = 0.01, 0.5

#: What a step returns and the next one is given: (snapshot version, stale, offer taken).
StepState = tuple[int, bool, bool]


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
    modes: int  # monitored answers handed to the publishers / the lane (0 when stale)
    published: bool  # the snapshot was published (False: already published, or a re-offer)
    offered: bool  # the compiled lane took the cones (True without a compiled lane)
    stale: bool  # the snapshot's inputs were older than their timeout


class PublishWorker:
    """The node's publishing worker (a thread started by :meth:`start`).

    ``node`` provides what the worker reads at each step: ``snapshot``,
    ``freshness(snap)``, ``lane``, ``snapshot_publishers``, ``limits``,
    ``input_timeout``, ``fixels_timeout``, ``max_publish_rate`` and ``get_logger()``;
    ``inbox`` is the PoseInbox the worker sleeps on (``wait(timeout)``, ``wake()``).
    """

    def __init__(self, node: Any, inbox: Any,
                 on_step: Callable[[StepTiming], None] | None = None) -> None:
        self.node = node
        self.inbox = inbox
        #: Called after each step with its :class:`StepTiming` (None: nothing is called).
        self.on_step = on_step
        self._stop = threading.Event()
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
    def publish(self, snap: Snapshot, generation: int, fresh: Freshness | None = None
                ) -> tuple[Freshness, dict[str, Answer], bool]:
        """Publish one snapshot on every per-snapshot publisher, and offer its monitored
        cones to the compiled lane (``generation``: the lane's, read before ``snap`` was
        taken; none when the inputs are stale). ``fresh``: the snapshot's freshness, if
        the caller has it already. Returns the freshness, the monitored answers and
        whether the lane took the offer (False: an input changed since ``generation``)."""
        node = self.node
        if fresh is None:
            fresh = node.freshness(snap)
        pause = (self._let_requests_go_first
                 if threading.current_thread() is self.thread else None)
        answers = self.monitored_answers(snap, fresh, pause)
        # The cone topics first (what a controller waits for), then the lane's offer
        # (it builds each cone's margin geometry: about 0.2 ms for 16 cones), then the
        # other publishers (markers, diagnostics).
        offered = None
        for pub in node.snapshot_publishers:
            if pause is not None:
                pause()
            pub.publish(snap, answers, fresh)
            if offered is None:
                offered = fastcheck.offer(node.lane, generation, snap, answers)
        if offered is None:
            offered = fastcheck.offer(node.lane, generation, snap, answers)
        return fresh, answers, offered

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
        returned: version, stale, offer taken) says it is published already; offer its
        cones to the lane again if the lane refused them (an input changed between the
        lane's generation and the snapshot: the snapshot may still be the newest, and
        without a new offer the lane would stay empty). Calls :attr:`on_step`."""
        started, started_wall = time.perf_counter(), time.time()
        node = self.node
        generation = node.lane.generation()  # before the inputs are read
        snap = node.snapshot
        fresh = node.freshness(snap)
        stale = bool(fresh.stale)
        published = False
        if last is not None and last[:2] == (snap.version, stale):
            if last[2]:
                state, modes = last, 0
            else:
                answers = self.monitored_answers(snap, fresh)
                modes = len(answers)
                state = (snap.version, stale,
                         fastcheck.offer(node.lane, generation, snap, answers))
        else:
            fresh, answers, offered = self.publish(snap, generation, fresh)
            published, modes = True, len(answers)
            state = (snap.version, bool(fresh.stale), offered)
        hook = self.on_step
        if hook is not None:
            hook(StepTiming(started, started_wall, time.perf_counter() - started,
                            snap.version, modes, published, state[2], state[1]))
        return state

    # --- the loop -------------------------------------------------------------------
    def poll_period(self) -> float:
        """How long the worker sleeps at most without a change (s): often enough to
        notice an input going stale."""
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
            self._stop.wait(min(rest, self.poll_period()))

    def _loop(self) -> None:
        """Newest snapshot only, as fast as it can (or at most ``max_publish_rate`` per
        second), never once per message."""
        last: StepState | None = None
        started = 0.0
        while not self._stop.is_set():
            try:  # nothing may end this thread but the node's end
                if last is None or last[2]:  # (a refused offer: step again at once)
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
