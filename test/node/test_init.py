# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node package's docstring (node/__init__.py) lists the node's endpoints: every
service, action, subscription and publication the running node shows in the ROS graph
(ROS 2's own parameter, lifecycle and logging endpoints aside), and every service and
action it names exists."""

from __future__ import annotations

import re
import time

import wrenchcone_ros.node as node_package
from helpers.node_harness import DEADLINE_S

#: Endpoints every ROS 2 node, lifecycle node or action server has: not the node's own.
STANDARD = re.compile(r"(/describe_parameters|/get_parameters|/get_parameter_types|"
                      r"/list_parameters|/set_parameters(_atomically)?|/get_type_description|"
                      r"/change_state|/get_state|/get_available_states|"
                      r"/get_available_transitions|/get_transition_graph|/transition_event|"
                      r"/_action/|^/rosout$|^/parameter_events$)")


def documented(name: str, ns: str) -> str:
    """A graph name as the docstring writes it: ``~/x`` for the node's private names,
    ``<mode>`` for a mode, relative names without the namespace."""
    base = f"{ns}/wrenchcone/"
    if name.startswith(base):
        name = "~/" + name[len(base):]
    elif name.startswith(ns + "/"):
        name = name[len(ns) + 1:]
    return re.sub(r"^~/cone/[a-z]+$", "~/cone/<mode>", name)


def graph(h) -> dict[str, set[str]]:
    me, ns = "wrenchcone", h.ns
    from rclpy.action.graph import get_action_server_names_and_types_by_node

    probe = h.tester
    return {
        "service": {n for n, _ in probe.get_service_names_and_types_by_node(me, ns)},
        "action": {n for n, _ in get_action_server_names_and_types_by_node(probe, me, ns)},
        "subscription": {n for n, _ in probe.get_subscriber_names_and_types_by_node(me, ns)},
        "publication": {n for n, _ in probe.get_publisher_names_and_types_by_node(me, ns)},
    }


def test_the_docstring_lists_every_endpoint_of_the_node(harness):
    doc = node_package.__doc__
    deadline = time.monotonic() + DEADLINE_S
    while True:  # discovery: wait until the node's services and cone topic are listed
        seen = graph(harness)
        if len(seen["service"]) > 4 and seen["action"] and any(
                "/cone/" in n for n in seen["publication"]):
            break
        assert time.monotonic() < deadline, seen
        time.sleep(0.05)
    own = {kind: {documented(n, harness.ns) for n in names if not STANDARD.search(n)}
           for kind, names in seen.items()}
    missing = {kind: sorted(n for n in names if f"``{n}``" not in doc)
               for kind, names in own.items()}
    assert not any(missing.values()), f"not in node/__init__.py's docstring: {missing}"
    named = {n for n in re.findall(r"``(~/[\w/<>]+)``", doc) if not STANDARD.search(n[1:])}
    assert named <= set().union(*own.values()), named - set().union(*own.values())
    assert {"~/check_wrench", "~/get_cone", "~/classify_wrench", "~/force_directions",
            "~/plan_seating"} <= own["service"] | own["action"]
