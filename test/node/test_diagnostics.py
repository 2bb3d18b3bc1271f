# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""/diagnostics over DDS: the levels the docs promise for the inputs, each monitored mode
and the request counts, following what the node is told."""

from __future__ import annotations

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rclpy.qos import QoSProfile

OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR


def _subscribe(h):
    return h.subscribe(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))


def _mine(h, pred):
    """A predicate on this node's statuses (name suffix -> DiagnosticStatus)."""
    name = h.node.get_fully_qualified_name()

    def test(msg):
        st = {s.name[len(name) + 2:]: s for s in msg.status if s.hardware_id == name}
        return bool(st) and pred(st)
    return test


def _values(status):
    return {kv.key: kv.value for kv in status.values}


def test_diagnostics_levels_follow_the_inputs(harness_factory):
    h = harness_factory(diagnostics_rate=20.0)
    col = _subscribe(h)
    msg = col.wait_for(_mine(h, lambda st: True), "diagnostics")
    name = h.node.get_fully_qualified_name()
    st = {s.name: s for s in msg.status if s.hardware_id == name}
    assert set(st) == {f"{name}: inputs", f"{name}: mode na", f"{name}: requests"}
    assert st[f"{name}: inputs"].level == OK
    inputs = _values(st[f"{name}: inputs"])
    assert inputs["pose age s"] == "none received"
    assert (inputs["pose source"], inputs["fixels source"]) == ("scene_file", "scene_file")
    # the interface version the node speaks, the one in wrenchcone_msgs' package.xml
    import xml.etree.ElementTree as ET
    from pathlib import Path

    xml = Path(__file__).resolve().parents[2] / "wrenchcone_msgs" / "package.xml"
    assert inputs["interfaces"] == "wrenchcone_msgs " + ET.parse(xml).findtext("version")
    mode = _values(st[f"{name}: mode na"])
    assert st[f"{name}: mode na"].level == OK
    assert mode["status"] == "OK" and mode["facets"] == "3" and float(mode["compute_ms"]) > 0

    h.publish_pose(0.0, 0.01, 0.0)  # lifts the disc off fixel 1: mode na not allowed
    col.wait_for(_mine(h, lambda st: st["mode na"].level == WARN
                       and _values(st["mode na"])["status"] == "MODE_NOT_ALLOWED"
                       and float(_values(st["inputs"])["pose age s"]) >= 0
                       and _values(st["inputs"])["pose source"] == "topic"),
                 "mode na WARN")
    h.publish_fixels([(0.0, -0.5), (1.001, 0.0)])  # inside the disc: no scene
    col.wait_for(_mine(h, lambda st: st["inputs"].level == ERROR
                       and "penetrates" in st["inputs"].message
                       and st["mode na"].level == ERROR), "inputs ERROR")
    h.publish_fixels([(0.0, -1.0), (1.001, 0.0)])
    h.publish_pose(0.0, 0.0, 0.0)
    col.wait_for(_mine(h, lambda st: st["inputs"].level == OK and st["mode na"].level == OK),
                 "OK again")
    [res] = h.set_parameters(input_timeout=0.05)  # the pose is older than that by now
    assert res.successful, res.reason
    col.wait_for(_mine(h, lambda st: st["inputs"].level == WARN
                       and "input_timeout 0.05 s" in st["inputs"].message
                       and st["mode na"].level == WARN
                       and _values(st["mode na"])["status"] == "STALE_INPUTS"),
                 "stale inputs")


def test_diagnostics_count_requests(harness_factory):
    h = harness_factory(diagnostics_rate=20.0)
    col = _subscribe(h)
    for _ in range(3):
        assert h.check("na", (0.1, -1.0, 0.0)).status == 0
    assert h.check("xx", (0.1, -1.0, 0.0)).status == 2  # INVALID_MODE
    h.get_cone("na")

    def counted(st):
        v = _values(st["requests"])
        return (v.get("check_wrench calls") == "4" and v.get("check_wrench OK") == "3"
                and v.get("check_wrench INVALID_MODE") == "1"
                and v.get("get_cone calls") == "1")

    msg = col.wait_for(_mine(h, counted), "the request counts")
    name = h.node.get_fully_qualified_name()
    (req,) = [s for s in msg.status if s.name == f"{name}: requests"]
    assert req.level == OK and req.message.startswith("5 call(s)")


def test_bad_rate_is_refused(harness):
    [res] = harness.set_parameters(diagnostics_rate=-1.0)
    assert not res.successful and "diagnostics_rate" in res.reason
