# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""A ``~/force_directions`` request to a harnessed node, and the pawl scene the
direction tests use."""

from wrenchcone_msgs.msg import Status
from wrenchcone_msgs.srv import ForceDirections

S = Status
PAWL = "examples/pawl_polygon.yaml"


def call(h, mode, point=None, exclusive=False):
    req = ForceDirections.Request(mode=mode, exclusive=exclusive, use_point=point is not None)
    if point is not None:
        req.point.x, req.point.y = (float(v) for v in point)
    cli = getattr(h, "_directions_cli", None)
    if cli is None:
        cli = h._directions_cli = h.tester.create_client(
            ForceDirections, f"{h.ns}/wrenchcone/force_directions")
        assert cli.wait_for_service(timeout_sec=30.0)
    return h._call(cli, req)
