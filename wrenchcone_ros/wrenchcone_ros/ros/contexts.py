# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""An rclpy context of its own on a leased ROS domain: for tests, and for the closed
loop of :mod:`wrenchcone_ros.sim` run in one process.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager

from rclpy.context import Context

from wrenchcone_ros.ros.domains import DomainLease, lease_domain

#: Discovery settings for a test context: DDS discovery stays on this machine
#: (``ROS_AUTOMATIC_DISCOVERY_RANGE``) and contacts no configured peer
#: (``ROS_STATIC_PEERS``). Applied while the context is initialised, then restored.
ISOLATED_DISCOVERY = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_STATIC_PEERS": ""}


@contextmanager
def isolated_context(domain_id: int | None = None) -> Iterator[Context]:
    """An initialised rclpy context (one DDS participant) on a ROS domain of its own.

    Parameters
    ----------
    domain_id : int, optional
        The domain to join (one leased with :func:`~.domains.lease_domain`); default: a
        new lease, given back when the context is shut down.

    Yields
    ------
    rclpy.context.Context
        The context (``context.get_domain_id()`` is the domain id), with
        localhost-only discovery (:data:`ISOLATED_DISCOVERY`). It installs no signal
        handler (it is initialised with ``Context.init``, not ``rclpy.init``).

    Notes
    -----
    The context is shut down on exit; destroy the nodes made in it first. Two contexts
    on one domain are two DDS participants: their nodes meet through DDS discovery,
    as in two processes.
    """
    lease: DomainLease | None = lease_domain() if domain_id is None else None
    saved = {k: os.environ.get(k) for k in ISOLATED_DISCOVERY}
    context = Context()
    try:
        os.environ.update(ISOLATED_DISCOVERY)
        try:
            context.init(domain_id=lease.domain_id if lease else domain_id)
        finally:
            for key, value in saved.items():
                if value is None:
                    os.environ.pop(key, None)
                else:
                    os.environ[key] = value
        yield context
    finally:
        context.try_shutdown()
        if lease is not None:
            lease.release()
