# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""ROS domain ids leased to one test at a time, across every process of the machine.

Two test runs on one machine (two developers, a CI job and a developer, ``pytest -n``
workers) that use the same ROS domain hear each other: a client of one run can be
answered by the node of the other. A test that takes its domain id from the process id
(``1 + pid % 100``) collides as soon as two process ids are equal modulo 100.

Here a domain id is *leased*: :func:`lease_domain` takes an exclusive ``fcntl.flock`` on
the file ``<temp dir>/wrenchcone_ros_domains/<id>.lock`` and holds it until
:meth:`DomainLease.release` (or until the process ends: the kernel drops the lock of a
dead process, so a crashed run never leaves a domain taken). Every process that leases
through this module therefore gets a domain id no other such process holds at the same
time. No ROS import in this module (the package ``wrenchcone_ros.ros`` checks the ROS
environment when it is imported).
"""

from __future__ import annotations

import errno
import fcntl
import os
import random
import re
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

#: The domain ids leased by default: 1 to 101. 0 is ROS's default domain (a node
#: started by hand, ``make run``); on Linux, ids above 101 make DDS use ports in the
#: kernel's ephemeral range (the ROS 2 documentation's advice: 0 to 101).
DEFAULT_DOMAIN_IDS = tuple(range(1, 102))
#: Environment variable narrowing the leased ids, e.g. ``"40-60"`` (inclusive) or
#: ``"7,8,9"``: for a machine where other programs use some domains of the default range.
DOMAIN_IDS_ENV = "WRENCHCONE_TEST_DOMAIN_IDS"
#: The directory of the lock files (one per domain id), shared by every user.
LOCK_DIR = Path(tempfile.gettempdir()) / "wrenchcone_ros_domains"


class NoFreeDomain(RuntimeError):
    """Every candidate domain id is leased by another test right now."""


@dataclass
class DomainLease:
    """An exclusive claim on one ROS domain id, held until :meth:`release`.

    Parameters
    ----------
    domain_id : int
        The leased ROS domain id.
    path : pathlib.Path
        The lock file that holds the claim.
    _fd : int or None, optional
        The open descriptor of the locked file, set by the function that leases the id
        (not for callers).
    """

    domain_id: int
    path: Path
    _fd: int | None = field(default=None, repr=False)

    @property
    def held(self) -> bool:
        """True until :meth:`release`."""
        return self._fd is not None

    def release(self) -> None:
        """Give the domain id back (idempotent)."""
        if self._fd is not None:
            fd, self._fd = self._fd, None
            fcntl.flock(fd, fcntl.LOCK_UN)
            os.close(fd)

    def __enter__(self) -> DomainLease:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.release()


def candidate_domain_ids(spec: str | None = None) -> tuple[int, ...]:
    """The domain ids a lease may take.

    Parameters
    ----------
    spec : str, optional
        ``"lo-hi"`` (inclusive) or comma-separated ids, or a mix (``"3,10-20"``);
        default: the environment variable :data:`DOMAIN_IDS_ENV`, else
        :data:`DEFAULT_DOMAIN_IDS`.

    Returns
    -------
    tuple of int
        The ids, in increasing order, without repetition.

    Raises
    ------
    ValueError
        The spec is not of that form, or names an id outside 0-232 (the ids DDS can
        map to ports).
    """
    spec = os.environ.get(DOMAIN_IDS_ENV) if spec is None else spec
    if spec is None or not spec.strip():
        return DEFAULT_DOMAIN_IDS
    ids: set[int] = set()
    for part in spec.split(","):
        match = re.fullmatch(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?", part)
        if match is None:
            raise ValueError(f"{DOMAIN_IDS_ENV}={spec!r}: expected ids or ranges such as "
                             "'40-60' or '7,8,9'")
        lo, hi = match.group(1), match.group(2) or match.group(1)
        ids.update(range(int(lo), int(hi) + 1))
    if not ids or min(ids) < 0 or max(ids) > 232:
        raise ValueError(f"{DOMAIN_IDS_ENV}={spec!r}: domain ids must lie in 0-232 "
                         "(and not be empty)")
    return tuple(sorted(ids))


def _open_lock_dir() -> Path:
    LOCK_DIR.mkdir(mode=0o777, exist_ok=True)
    try:  # shared by every user of the machine: world-writable, sticky like /tmp
        os.chmod(LOCK_DIR, 0o1777)
    except PermissionError:  # another user's directory, already set up by them
        pass
    return LOCK_DIR


def lease_domain(candidates: Sequence[int] | None = None,
                 rng: random.Random | None = None) -> DomainLease:
    """Lease a ROS domain id that no other process leasing through this module holds.

    The candidates are tried from a random starting point (so that processes starting
    at once rarely contend for the same lock file), each with a non-blocking exclusive
    ``flock``; the first one obtained is returned.

    Parameters
    ----------
    candidates : sequence of int, optional
        The ids to choose from; default :func:`candidate_domain_ids`.
    rng : random.Random, optional
        The source of the starting point (default: a fresh, OS-seeded generator).

    Returns
    -------
    DomainLease
        The lease; call :meth:`DomainLease.release` (or use it as a context manager)
        when the domain is no longer used.

    Raises
    ------
    NoFreeDomain
        Every candidate is held by another lease.
    ValueError
        ``candidates`` is empty.
    """
    ids = list(candidate_domain_ids() if candidates is None else candidates)
    if not ids:
        raise ValueError("no candidate domain ids")
    start = (rng or random.Random()).randrange(len(ids))
    directory = _open_lock_dir()
    for domain_id in ids[start:] + ids[:start]:
        path = directory / f"{domain_id}.lock"
        fd = os.open(path, os.O_RDONLY | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                continue
            raise
        return DomainLease(domain_id, path, fd)
    raise NoFreeDomain(f"all {len(ids)} candidate ROS domain ids ({ids[0]}-{ids[-1]}) are "
                       f"leased by other tests right now (lock files in {directory}); "
                       f"wait, or widen {DOMAIN_IDS_ENV}")
