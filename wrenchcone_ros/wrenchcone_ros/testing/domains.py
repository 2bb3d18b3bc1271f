# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""ROS domain ids leased to one test at a time: the kit's name for
:mod:`wrenchcone_ros.ros.domains`, where the leases are made (the closed loop of
:mod:`wrenchcone_ros.sim` leases its domain there too).
"""

from wrenchcone_ros.ros.domains import (  # noqa: F401 - the kit's documented names
    DEFAULT_DOMAIN_IDS,
    DOMAIN_IDS_ENV,
    LOCK_DIR,
    DomainLease,
    NoFreeDomain,
    candidate_domain_ids,
    lease_domain,
)
