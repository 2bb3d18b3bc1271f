# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The interfaces of wrenchcone_msgs hold no surprises: no deprecated type, the status
constants on every interface that carries a status (equal to Status.msg's), the
controller's states as constants (equal to the controller's own list), lists of small
messages where an answer has one entry per interval or mode, a source beside every input
stamp, one 1-based fixel numbering; checked on the generated types and, over real DDS, on
the live messages of a node."""

from __future__ import annotations

import importlib
import os
import re

import pytest

import wrenchcone_msgs
from wrenchcone_msgs.msg import ControllerState, Status
from wrenchcone_ros.core import consistent_modes, force_directions, load_scene
from wrenchcone_ros.sim.controller_states import STATES

from helpers.node_directions import PAWL, call

DISC = os.path.abspath("examples/paper_disc.yaml")


def _share() -> str:
    """The installed wrenchcone_msgs' share directory: the interface files the
    generated types were built from."""
    from ament_index_python.packages import get_package_share_directory

    return get_package_share_directory("wrenchcone_msgs")


def _interface_types() -> dict[str, type]:
    """Every generated type of wrenchcone_msgs, found from the package's own interface
    files (msg, srv Request/Response, action Goal/Result/Feedback), by name."""
    root = _share()
    out = {}
    for kind, parts in (("msg", ("",)), ("srv", ("Request", "Response")),
                        ("action", ("Goal", "Result", "Feedback"))):
        module = importlib.import_module(f"wrenchcone_msgs.{kind}")
        for name in sorted(os.listdir(os.path.join(root, kind))):
            if not name.endswith(f".{kind}"):
                continue  # the generated .idl files beside them
            base = name.rsplit(".", 1)[0]
            cls = getattr(module, base)
            for part in parts:
                out[f"{kind}/{base}{'.' + part if part else ''}"] = (
                    getattr(cls, part) if part else cls)
    return out


TYPES = _interface_types()
#: Status.msg's constants, read from the .msg file itself (not the generated class).
STATUS_FILE = os.path.join(_share(), "msg", "Status.msg")


def _file_constants(path: str) -> dict[str, object]:
    consts = {}
    for line in open(path):
        m = re.match(r"^\s*(uint8|string)\s+([A-Z_]+)\s*=\s*(\S+)", line)
        if m:
            kind, name, value = m.groups()
            consts[name] = int(value) if kind == "uint8" else value.strip('"')
    return consts


def test_the_types_were_found():
    # the discovery above is not vacuous: the interfaces users call are among them
    for name in ("msg/WrenchCone", "srv/CheckWrench.Response", "srv/ForceDirections.Response",
                 "action/PlanSeating.Result", "msg/ControllerState", "srv/ResetPose.Request"):
        assert name in TYPES
    assert len(TYPES) >= 25
    assert wrenchcone_msgs.__name__ == "wrenchcone_msgs"


def _all_field_types(cls: type, seen: set | None = None) -> set[str]:
    """Every field type name of ``cls``, nested messages included."""
    seen = set() if seen is None else seen
    for ftype in cls.get_fields_and_field_types().values():
        inner = re.sub(r"^sequence<(.*?)(, \d+)?>$", r"\1", ftype)
        if "/" in inner and inner not in seen:
            seen.add(inner)
            pkg, name = inner.split("/")
            _all_field_types(getattr(importlib.import_module(f"{pkg}.msg"), name), seen)
    return seen


def test_no_deprecated_type():
    for name, cls in TYPES.items():
        assert "geometry_msgs/Pose2D" not in _all_field_types(cls), name


def test_every_status_field_has_the_status_constants():
    expected = _file_constants(STATUS_FILE)
    expected.pop("INTERFACE_VERSION")  # Status.msg's own: the interfaces' version
    assert expected["OK"] == 0 and expected["UNAVAILABLE"] == 14
    assert expected["SOURCE_TOPIC"] == "topic"
    with_status = [n for n, cls in TYPES.items() if n != "msg/Status"
                   and cls.get_fields_and_field_types().get("status") == "uint8"]
    assert {"msg/WrenchCone", "srv/CheckWrench.Response", "srv/GetCone.Response",
            "srv/ClassifyWrench.Response", "srv/ForceDirections.Response",
            "action/PlanSeating.Result"} <= set(with_status)
    for name in with_status:
        cls = TYPES[name]
        for const, value in expected.items():
            assert getattr(cls, const, None) == value, (name, const)


def test_every_input_stamp_has_a_source():
    for name, cls in TYPES.items():
        fields = cls.get_fields_and_field_types()
        if "pose_stamp" in fields or name == "msg/WrenchCone":
            assert fields.get("pose_source") == "string", name
            assert fields.get("fixels_source") == "string", name
            assert cls.SOURCE_TOPIC == Status.SOURCE_TOPIC, name
            assert cls.SOURCE_SCENE_FILE == Status.SOURCE_SCENE_FILE, name


def test_controller_states_are_constants():
    consts = {k for k in dir(ControllerState) if k.isupper() and not k.startswith("_")
              and isinstance(getattr(ControllerState, k), str)}
    assert consts == set(STATES)
    assert all(getattr(ControllerState, k) == k for k in STATES)


def test_lists_of_messages_not_parallel_arrays():
    from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, ForceDirections

    f = ForceDirections.Response.get_fields_and_field_types()
    assert f["intervals"] == "sequence<wrenchcone_msgs/DirectionInterval>"
    assert not {"lo", "hi", "best", "margin"} & set(f)
    c = ClassifyWrench.Response.get_fields_and_field_types()
    assert c["matches"] == "sequence<wrenchcone_msgs/ModeMatch>"
    assert not {"modes", "margins", "certain", "margins_all"} & set(c)
    k = CheckWrench.Response.get_fields_and_field_types()
    assert k["others"] == "sequence<wrenchcone_msgs/ModeMatch>"
    assert not {"other_modes", "other_margins"} & set(k)


def test_fixel_numbering_is_stated_on_every_interface_with_fixels():
    # every interface file that speaks of fixels by number or letter says 1-based
    root = _share()
    for name in ("msg/Fixel.msg", "msg/Fixels.msg", "msg/WrenchCone.msg",
                 "msg/ContactLetters.msg", "msg/ModeMatch.msg", "msg/PlanSegment.msg",
                 "srv/CheckWrench.srv", "srv/GetCone.srv", "srv/ForceDirections.srv",
                 "action/PlanSeating.action"):
        text = open(os.path.join(root, name)).read()
        assert "1-based" in text, name
        assert "0-based" not in text.replace("(0-based array index)", ""), name


# --- live messages over DDS ------------------------------------------------------------
@pytest.fixture
def disc(harness_factory):
    return harness_factory(scene_file=DISC)


def test_live_cone_message_has_the_constants(disc):
    msg = disc.subscribe_cone("na").wait_for(lambda m: m.inputs_version >= 1, "a cone")
    assert msg.status == msg.OK  # docs/node.md's test, on the message itself
    assert msg.pose_source == msg.SOURCE_SCENE_FILE == msg.fixels_source
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (0, 0)


def test_replies_say_where_the_inputs_came_from(disc):
    r = disc.check("na", (1.0, 0.0, -0.5))
    assert r.status == r.OK, r.message
    assert (r.pose_source, r.fixels_source) == (r.SOURCE_SCENE_FILE, r.SOURCE_SCENE_FILE)
    assert (r.pose_stamp.sec, r.pose_stamp.nanosec) == (0, 0)
    version = r.inputs_version
    scene = load_scene(DISC)
    disc.publish_pose(*scene.pose, stamp=(7, 0))
    disc.wait_version_above(version)
    r = disc.check("na", (1.0, 0.0, -0.5))
    assert (r.pose_source, r.fixels_source) == (r.SOURCE_TOPIC, r.SOURCE_SCENE_FILE)
    assert r.pose_stamp.sec == 7


def test_force_directions_is_a_list_of_intervals(harness_factory):
    h = harness_factory(scene_file=os.path.abspath(PAWL))
    r = call(h, "arr")
    assert r.status == r.OK, r.message
    core = force_directions(load_scene(PAWL), "arr")
    assert core and [(i.lo, i.hi, i.best, i.margin) for i in r.intervals] == [
        (i.lo, i.hi, i.best, i.margin) for i in core]


def test_classify_and_check_answer_mode_matches(disc):
    g = (0.0, -1.0, 0.0)  # straight down on the disc's pin: rolling or separating
    expected = consistent_modes(load_scene(DISC), g)
    assert [m.mode for m in expected] == ["na", "ns"]
    r = disc.classify(g)
    assert r.status == r.OK, r.message
    assert [(m.mode, m.certain) for m in r.matches] == [(m.mode, True) for m in expected]
    assert [m.margin for m in r.matches] == pytest.approx([m.margin for m in expected],
                                                          abs=1e-12)
    assert [m.margin_all for m in r.matches] == [m.margin for m in r.matches]
    first = expected[0].mode
    c = disc.check(first, g, classify=True)
    assert c.status == c.OK and c.classified, c.message
    assert [m.mode for m in c.others] == [m.mode for m in expected[1:]]
    assert [m.margin for m in c.others] == pytest.approx([m.margin for m in expected[1:]],
                                                         abs=1e-12)


def test_goal_tilt_default_and_given():
    pytest.importorskip("pymunk")
    from wrenchcone_msgs.action import PlanSeating
    from wrenchcone_ros.core.simulate import DEFAULT_TILT
    from wrenchcone_ros.node.plan_action import goal_arguments

    default = goal_arguments(PlanSeating.Goal(target=[1]), 3)["actuator"]
    assert default.tilt == DEFAULT_TILT == pytest.approx(0.17453292519943295)
    given = goal_arguments(PlanSeating.Goal(target=[1], use_tilt=True, tilt=0.3), 3)
    assert given["actuator"].tilt == 0.3
    for goal in (PlanSeating.Goal(target=[1], use_tilt=True),  # 0 rad: a level tray
                 PlanSeating.Goal(target=[1], use_tilt=True, tilt=float("nan")),
                 PlanSeating.Goal(target=[1], tilt=0.3)):  # given but not used: refused
        with pytest.raises(ValueError, match="tilt"):
            goal_arguments(goal, 3)


def test_goal_start_region_in_si_units():
    """The goal's half-widths reach the planner as given (m, m, rad); none without
    use_start_region; all three 0 with it is the pose alone, a box of one pose."""
    pytest.importorskip("pymunk")
    from wrenchcone_msgs.action import PlanSeating
    from wrenchcone_ros.core.plan import StartRegion
    from wrenchcone_ros.node.plan_action import goal_arguments

    assert goal_arguments(PlanSeating.Goal(target=[1]), 3)["start_region"] is None
    got = goal_arguments(PlanSeating.Goal(
        target=[1], use_start_region=True, start_region_dx=0.002, start_region_dy=0.001,
        start_region_dtheta=0.0873), 3)["start_region"]
    assert got == StartRegion(0.002, 0.001, 0.0873)
    assert goal_arguments(PlanSeating.Goal(target=[1], use_start_region=True),
                          3)["start_region"] == StartRegion(0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="use_start_region is false"):
        goal_arguments(PlanSeating.Goal(target=[1], start_region_dtheta=float("nan")), 3)


def test_no_input_has_no_source(harness_factory):
    h = harness_factory(scene_file=DISC, wait_for_inputs=True)
    r = h.check("na", (1.0, 0.0, -0.5))
    assert r.status == r.NO_INPUTS, r.message
    assert (r.pose_source, r.fixels_source) == ("", "")
    h.publish_pose(*load_scene(DISC).pose, stamp=(3, 0))  # the pose, not yet the fixels
    h.wait_version_above(r.inputs_version)
    r = h.check("na", (1.0, 0.0, -0.5))
    assert r.status == r.NO_INPUTS and (r.pose_source, r.fixels_source) == (r.SOURCE_TOPIC, "")
