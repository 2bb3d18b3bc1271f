# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The closed loop, launch-free: tray_sim, the wrenchcone node and tilt_controller in this
process, over real DDS (wrenchcone_ros.sim.loop), seat the pawl of
examples/pawl_seating.yaml. The run is recorded twice, by the loop's recorder (rosbags)
and by a plain rclpy recorder writing with the mcap library; the replay of both is
checked against the node's own answers. This is the pattern docs/closed_loop.md shows for
testing a controller of one's own."""

import math
import time
from dataclasses import replace
from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.slow  # the loop over DDS in real time
pytest.importorskip("pymunk")
pytest.importorskip("rosbags")

from wrenchcone_msgs.msg import PlanarPose, TiltCommand  # noqa: E402
from wrenchcone_msgs.srv import ResetPose  # noqa: E402

from wrenchcone_ros.core import Uncertainty, load_scene  # noqa: E402
from wrenchcone_ros.replay import read_run, replay  # noqa: E402
from wrenchcone_ros.replay.analysis import RECORDED, margin_at  # noqa: E402
from wrenchcone_ros.sim.loop import Loop, node_parameters  # noqa: E402
from wrenchcone_ros.sim.recorder import LOOP_TOPICS  # noqa: E402

from helpers.plain_recorder import PlainRecorder  # noqa: E402

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One seating run of the nominal pawl, recorded by both writers; then bad inputs
    sent to the live tray."""
    tmp = tmp_path_factory.mktemp("loop")
    # in lockstep (the Loop's default): a loaded 2-core CI machine gets every control step
    # of the 0.3 s slide
    with Loop(PAWL, [1, 2, 3]) as loop:
        plain = PlainRecorder(loop.recorder_node, tmp / "plain.mcap", LOOP_TOPICS)
        result = loop.run(None, timeout=120.0, record=tmp / "run")
        plain.close()
        # bad input to the live tray: each refused with one line, the tray goes on (the
        # lockstep tray, parked between runs, let go: with no controller to answer, it
        # steps after each lockstep_timeout)
        loop.tray.lockstep_timeout = 0.02
        loop.tray.resume()
        pub = loop.recorder_node.create_publisher(TiltCommand, "tilt_command", 10)
        n0, clock0 = len(loop.tray.refusals), loop.physics.clock
        for direction, magnitude in ((math.nan, 1.0), (0.0, 1e6)):
            pub.publish(TiltCommand(direction=direction, magnitude=magnitude))
        cli = loop.recorder_node.create_client(ResetPose, "tray_sim/reset")
        assert cli.wait_for_service(timeout_sec=10.0)
        future = cli.call_async(ResetPose.Request(pose=PlanarPose(x=0.096, y=0.195,
                                                                  theta=0.0)))
        deadline = time.monotonic() + 10.0
        while not future.done() and time.monotonic() < deadline:
            time.sleep(0.05)
        while ((len(loop.tray.refusals) < n0 + 3 or loop.physics.clock < clock0 + 0.1)
               and time.monotonic() < deadline):
            time.sleep(0.05)
        bad = {"refusals": loop.tray.refusals[n0:], "reset": future.result(),
               "clock_advanced": loop.physics.clock > clock0 + 0.1,
               "alive": loop.tray.thread.is_alive()}
    return result, tmp, bad


def test_the_loop_seats_the_pawl_in_the_planned_contact_sequence(run):
    result, _, _ = run
    assert result.state == "SEATED", result.reason
    assert result.seated  # the tray's truth, not the controller's word
    assert result.modes == ["arr", "nnn"] and len(result.events) == 1
    letters = result.letters
    # the engine's letters: sliding right on pins 2 and 3 towards the stop, then every
    # contact rolling (stuck) at the end
    assert "arr" in letters and "nnn" in letters[letters.index("arr"):]
    assert letters.index("arr") < len(letters) - 1
    assert all(x[0] in "as" for x in letters[:letters.index("arr") + 1])
    assert result.latencies  # commands arrived stamped with the pose they came from


def test_the_replay_margins_are_the_nodes(run):
    """Each margin the controller got from the node (classify_wrench, ControllerState at
    the pose the node used) is the replay's for the same recorded pose and command."""
    _, tmp, _ = run
    rec = read_run(tmp / "run")
    scene = load_scene(PAWL)
    scene = replace(scene, contact_tolerance=node_parameters(scene, None)["contact_tolerance"])
    poses = {p.stamp: p.value for p in rec.poses}
    checked = 0
    for s in rec.states:
        state, mode, direction, margin = s.value
        if mode != "arr" or math.isnan(margin) or s.stamp not in poses:
            continue
        ok, m = margin_at(scene, poses[s.stamp], mode, direction)
        assert m == pytest.approx(margin, abs=1e-9) and ok == (margin > 0)
        checked += 1
    assert checked >= 3


def test_another_writers_bag_replays_the_same(run):
    _, tmp, _ = run
    ours, theirs = read_run(tmp / "run"), read_run(tmp / "plain.mcap")
    assert theirs.scene_yaml is None and ours.scene_yaml
    scene = load_scene(PAWL)
    a = {r.stamp: r for r in replay(ours, scene, "arr", classify=False).rows}
    b = {r.stamp: r for r in replay(theirs, scene, "arr", classify=False).rows}
    common = [k for k in a if k in b and not math.isnan(a[k].margin)]
    assert len(common) >= 3
    for k in common:
        assert (b[k].margin, b[k].consistent, b[k].pose) == (a[k].margin, a[k].consistent,
                                                            a[k].pose)


def test_bad_input_to_the_tray_gets_one_line_each_and_it_goes_on(run):
    _, _, bad = run
    assert not bad["reset"].success and "penetrates" in bad["reset"].message
    lines = bad["refusals"]
    assert len(lines) == 3 and all("\n" not in x for x in lines)
    # the two commands (a topic) and the reset (a service) may arrive in either order
    assert sorted(("finite" in x, "is outside [" in x, "penetrates" in x) for x in lines) == [
        (False, False, True), (False, True, False), (True, False, False)], lines
    assert bad["clock_advanced"] and bad["alive"]


def test_the_replay_with_the_recorded_plan_follows_its_segments(run):
    """``plan=RECORDED``: each command in the mode the controller's state of that step
    names; the plan's segment modes followed offline (the controller's switching rule,
    by the core) give the same sequence, switching within a few commands of it."""
    _, tmp, _ = run
    rec = read_run(tmp / "run")
    scene = load_scene(PAWL)
    scene = replace(scene, contact_tolerance=node_parameters(scene, None)["contact_tolerance"])
    recorded = replay(rec, scene, plan=RECORDED, classify=False)
    offline = replay(rec, scene, plan=["arr", "nnn"], classify=False)
    a, b = [r.mode for r in recorded.rows], [r.mode for r in offline.rows]
    assert [m for i, m in enumerate(a) if i == 0 or m != a[i - 1]] == ["arr", "nnn"]
    assert [m for i, m in enumerate(b) if i == 0 or m != b[i - 1]] == ["arr", "nnn"]
    assert abs(a.index("nnn") - b.index("nnn")) <= 3
    # a row's margin is the one of its own segment's mode
    single = {m: {r.stamp: r.margin for r in replay(rec, scene, m, classify=False).rows}
              for m in ("arr", "nnn")}
    for r in recorded.rows:
        assert r.margin == single[r.mode][r.stamp] or math.isnan(r.margin)


def test_the_replays_robust_margins_are_the_nodes(run, harness_factory):
    """The robust margins of the replay (friction [0.2, 0.4]) against check_wrench of a
    wrenchcone node with that uncertainty, given the same recorded pose and fixels and
    asked the same commanded wrench."""
    _, tmp, _ = run
    rec = read_run(tmp / "run")
    scene = load_scene(PAWL)
    tol = node_parameters(scene, None)["contact_tolerance"]
    scene = replace(scene, contact_tolerance=tol)
    rep = replay(rec, scene, plan=RECORDED, classify=False,
                 uncertainty=Uncertainty(friction=(0.2, 0.4)))
    rows = [r for r in rep.rows if not math.isnan(r.robust_margin)]
    picked = {r.mode: [] for r in rows}
    for r in rows:
        picked[r.mode].append(r)
    picked = [r for rs in picked.values() for r in rs[::max(1, len(rs) // 3)][:3]]
    assert len(picked) >= 4
    h = harness_factory(scene_file=str(PAWL), contact_tolerance=tol,
                        **{"uncertainty.friction": [0.2, 0.4]})
    h.publish_fixels([f.position for f in scene.fixels], radii=[f.radius for f in scene.fixels])
    for r in picked:
        version = h.get_cone("").inputs_version
        h.publish_pose(*r.pose)
        h.wait_version_above(version)
        m = scene.workpiece.mass * r.magnitude
        answer = h.check(r.mode, (m * math.cos(r.direction), m * math.sin(r.direction), 0.0))
        assert answer.margin == pytest.approx(r.robust_margin, abs=1e-9), (r, answer.message)
        assert answer.consistent == r.robust_consistent
        assert r.robust_margin <= r.margin + 1e-12  # every model's cone within the nominal's


def test_the_bag_is_what_ros2_bag_play_opens(run):
    """What ``ros2 bag play`` and Foxglove need, checked with readers other than the
    replay's: a rosbag2 directory whose metadata.yaml rosbags' rosbag2 Reader opens
    (storage mcap, every topic with its type, serialization cdr); one .mcap file of
    profile ros2 whose every channel has a ros2msg schema and cdr messages, and whose
    every message the mcap library's own ROS 2 decoder (mcap-ros2-support) decodes."""
    mcap_reader = pytest.importorskip("mcap.reader")
    mcap_ros2 = pytest.importorskip("mcap_ros2.decoder")
    from rosbags.rosbag2 import Reader

    _, tmp, _ = run
    bag = tmp / "run"
    meta = yaml.safe_load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert meta["storage_identifier"] == "mcap"
    files = meta["relative_file_paths"]
    assert len(files) == 1 and (bag / files[0]).is_file()
    with Reader(bag) as reader:
        topics = {c.topic: c.msgtype for c in reader.connections}
        assert {c.msgcount > 0 for c in reader.connections} == {True}
        assert all(c.ext.serialization_format == "cdr" for c in reader.connections)
    for topic, kind in LOOP_TOPICS:
        assert topics[topic] == kind
    with open(bag / files[0], "rb") as f:
        reader = mcap_reader.make_reader(f, decoder_factories=[mcap_ros2.DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        decoded = {}
        for _schema, channel, _message, msg in reader.iter_decoded_messages():
            decoded[channel.topic] = decoded.get(channel.topic, 0) + 1
            if channel.topic == "/workpiece_pose":
                assert math.isfinite(msg.pose.position.x)
    assert set(decoded) == set(topics)
    with Reader(bag) as reader:
        assert decoded == {c.topic: c.msgcount for c in reader.connections}
