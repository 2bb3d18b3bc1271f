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

pytestmark = pytest.mark.slow  # the loop over DDS in real time
pytest.importorskip("pymunk")
pytest.importorskip("rosbags")

from geometry_msgs.msg import Pose2D  # noqa: E402
from wrenchcone_msgs.msg import TiltCommand  # noqa: E402
from wrenchcone_msgs.srv import ResetPose  # noqa: E402

from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.replay import read_run, replay  # noqa: E402
from wrenchcone_ros.replay.analysis import margin_at  # noqa: E402
from wrenchcone_ros.sim.loop import Loop, node_parameters  # noqa: E402
from wrenchcone_ros.sim.recorder import LOOP_TOPICS  # noqa: E402

from helpers.plain_recorder import PlainRecorder  # noqa: E402

PAWL = Path(__file__).resolve().parents[2] / "examples" / "pawl_seating.yaml"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """One seating run of the nominal pawl, recorded by both writers; then bad inputs
    sent to the live tray."""
    tmp = tmp_path_factory.mktemp("loop")
    # a quarter of real time: a loaded 2-core CI machine still gets several control steps
    # into the 0.3 s slide
    with Loop(PAWL, [1, 2, 3], real_time_factor=0.25) as loop:
        plain = PlainRecorder(loop.recorder_node, tmp / "plain.mcap", LOOP_TOPICS)
        result = loop.run(None, timeout=120.0, record=tmp / "run")
        plain.close()
        # bad input to the live tray: each refused with one line, the tray goes on
        pub = loop.recorder_node.create_publisher(TiltCommand, "tilt_command", 10)
        n0, clock0 = len(loop.tray.refusals), loop.physics.clock
        for direction, magnitude in ((math.nan, 1.0), (0.0, 1e6)):
            pub.publish(TiltCommand(direction=direction, magnitude=magnitude))
        cli = loop.recorder_node.create_client(ResetPose, "tray_sim/reset")
        assert cli.wait_for_service(timeout_sec=10.0)
        future = cli.call_async(ResetPose.Request(pose=Pose2D(x=0.096, y=0.195, theta=0.0)))
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
    assert "finite" in lines[0] and "outside" in lines[1]
    assert bad["clock_advanced"] and bad["alive"]
