# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A per-thread time budget for long computations.

The node answers its cheap services (check_wrench, get_cone) in one thread, the fast
lane, so one request must not hold that thread for long: it runs under
:func:`time_budget` (the node's ``max_request_time``, in seconds), and the loops whose
length the request decides (the reference cones of a batch, the mode search of a
classification) call :func:`check_time_budget`, which raises
:class:`TimeBudgetExceeded` once the budget is spent. The budget belongs to the
calling thread only: other threads (the node's publishing worker, its slow lane) are
never interrupted. Outside :func:`time_budget` the check costs one attribute lookup.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

_local = threading.local()


class TimeBudgetExceeded(RuntimeError):
    """The computation took longer than the time budget of the calling thread."""


@contextmanager
def time_budget(seconds: float | None) -> Iterator[None]:
    """Run the block under a budget of ``seconds`` (wall clock, monotonic); None or 0 =
    no budget. Nested budgets: the earlier deadline wins.

    Parameters
    ----------
    seconds : float or None
        The budget (s); None or 0: none.

    Yields
    ------
    None
        Inside the block, :func:`check_time_budget` raises once the budget is spent.
    """
    previous = getattr(_local, "deadline", None)
    if seconds:
        deadline = (time.monotonic() + float(seconds), float(seconds))
        if previous is None or deadline[0] < previous[0]:
            _local.deadline = deadline
    try:
        yield
    finally:
        _local.deadline = previous


def check_time_budget() -> None:
    """Raise :class:`TimeBudgetExceeded` if the calling thread's budget is spent.

    Raises
    ------
    TimeBudgetExceeded
        The budget of the calling thread is spent.
    """
    deadline = getattr(_local, "deadline", None)
    if deadline is not None and time.monotonic() > deadline[0]:
        raise TimeBudgetExceeded(f"the computation took longer than its time budget of "
                                 f"{deadline[1]:g} s")
