# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone replay``, offline and without ROS: bags written here with rosbags (the
scene, poses, tilt commands), checked against Coulomb's law; bad bags get one line."""

import math
import subprocess
import sys
from pathlib import Path

import pytest

import yaml

pytestmark = pytest.mark.slow  # bags written and replayed, a subprocess

pytest.importorskip("rosbags")

from rosbags.rosbag2 import StoragePlugin, Writer  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

from wrenchcone_ros.cli import main  # noqa: E402
from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.tilt import STANDARD_GRAVITY  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
PAWL = ROOT / "examples" / "pawl_seating.yaml"
A10 = STANDARD_GRAVITY * math.sin(math.radians(10.0))


def _store():
    store = get_typestore(Stores.ROS2_JAZZY)
    for name in ("TiltCommand", "ContactLetters"):
        text = (ROOT / "wrenchcone_msgs" / "msg" / f"{name}.msg").read_text()
        store.register(get_types_from_msg(text, f"wrenchcone_msgs/msg/{name}"))
    return store


def write_bag(path: Path, commands, *, scene=True, poses=True, letters=None) -> Path:
    """A bag of the pawl at rest at its start pose: one pose and one command (degrees,
    m/s^2) every 10 ms, stamps 0.01 k s; the scene on /scene_yaml."""
    store = _store()
    T = store.types
    Time, Header = T["builtin_interfaces/msg/Time"], T["std_msgs/msg/Header"]
    x, y, th = load_scene(PAWL).pose
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        if scene:
            c = w.add_connection("/scene_yaml", "std_msgs/msg/String", typestore=store)
            text = yaml.safe_dump(load_scene(PAWL).to_dict())
            w.write(c, 0, store.serialize_cdr(T["std_msgs/msg/String"](data=text),
                                              "std_msgs/msg/String"))
        cp = w.add_connection("/workpiece_pose", "geometry_msgs/msg/PoseStamped", typestore=store)
        cc = w.add_connection("/tilt_command", "wrenchcone_msgs/msg/TiltCommand", typestore=store)
        cl = w.add_connection("/contact_letters", "wrenchcone_msgs/msg/ContactLetters",
                              typestore=store)
        for k, (deg, mag) in enumerate(commands):
            t_ns = 10_000_000 * (k + 1)
            stamp = Time(sec=t_ns // 1_000_000_000, nanosec=t_ns % 1_000_000_000)
            if poses:
                pose = T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=x, y=y, z=0.0),
                    orientation=T["geometry_msgs/msg/Quaternion"](
                        x=0.0, y=0.0, z=math.sin(th / 2), w=math.cos(th / 2)))
                msg = T["geometry_msgs/msg/PoseStamped"](header=Header(stamp, "world"), pose=pose)
                w.write(cp, t_ns, store.serialize_cdr(msg, "geometry_msgs/msg/PoseStamped"))
            if letters:
                msg = T["wrenchcone_msgs/msg/ContactLetters"](
                    header=Header(stamp, "world"), letters=letters[k],
                    gaps=__import__("numpy").zeros(3), speed=0.0)
                w.write(cl, t_ns + 1, store.serialize_cdr(msg, "wrenchcone_msgs/msg/ContactLetters"))
            cmd = T["wrenchcone_msgs/msg/TiltCommand"](
                header=Header(stamp, "world"), direction=math.radians(deg), magnitude=mag)
            w.write(cc, t_ns + 2, store.serialize_cdr(cmd, "wrenchcone_msgs/msg/TiltCommand"))
    return path


def test_the_margins_follow_coulombs_law_and_it_says_when_the_command_left(tmp_path, capsys):
    """Sliding right on pins 2 and 3 (mode arr, mu = 0.3) needs a pull right of straight
    down by more than the friction angle and not up: phi in (-atan2(1, 0.3), 0) =
    (-73.30, 0) deg."""
    cmds = [(-58.5, A10), (-30.0, A10), (-75.0, A10), (-72.0, A10), (10.0, A10), (-58.5, 0.0)]
    bag = write_bag(tmp_path / "run", cmds, letters=["snn"] * len(cmds))
    assert main(["replay", str(bag), "--mode", "arr", "--json"]) == 0
    out = __import__("json").loads(capsys.readouterr().out)
    inside = [r["consistent"] for r in out["rows"]]
    assert inside == [True, True, False, True, False, False]
    assert [r["margin"] is None for r in out["rows"]] == [False] * 5 + [True]  # level tray
    assert out["left"] == pytest.approx([0.03, 0.05], abs=1e-6)
    assert out["entered"] == pytest.approx([0.04], abs=1e-6)
    assert out["rows"][0]["classified"] == ["arr"] and out["rows"][0]["letters"] == "snn"
    assert main(["replay", str(bag), "--mode", "arr", "--table", "-o",
                 str(tmp_path / "run.png")]) == 0
    text = capsys.readouterr().out
    assert "left the cone at t = 0.030, 0.050 s" in text and (tmp_path / "run.png").stat().st_size


def test_a_bag_directory_and_its_mcap_file_read_the_same(tmp_path, capsys):
    bag = write_bag(tmp_path / "run", [(-58.5, A10)] * 3)
    assert main(["replay", str(bag), "--mode", "arr"]) == 0
    a = capsys.readouterr().out.split(":", 1)[1]
    assert main(["replay", str(bag / "run.mcap"), "--mode", "arr"]) == 0
    assert capsys.readouterr().out.split(":", 1)[1] == a


@pytest.mark.parametrize("make, words", [
    (lambda p: p / "missing.mcap", "no such file"),
    (lambda p: (p / "junk.mcap").write_bytes(b"\x89MCAP0\r\n garbage") and p / "junk.mcap",
     "not a readable rosbag2 bag"),
    (lambda p: write_bag(p / "nocmd", [], scene=True), "no messages of"),
    (lambda p: write_bag(p / "nopose", [(-58.5, A10)], poses=False), "PoseStamped"),
    (lambda p: write_bag(p / "noscene", [(-58.5, A10)], scene=False), "--scene FILE"),
])
def test_a_bad_bag_gets_one_line_and_exit_status_2(tmp_path, make, words):
    path = make(tmp_path)
    proc = subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", "replay", str(path),
                           "--mode", "arr"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in proc.stderr


def test_no_ros_is_imported(tmp_path):
    bag = write_bag(tmp_path / "run", [(-58.5, A10)])
    code = ("import sys; from wrenchcone_ros.cli import main; "
            f"rc = main(['replay', {str(bag)!r}, '--mode', 'arr']); "
            "bad = [m for m in sys.modules if m.split('.')[0] in "
            "('rclpy', 'wrenchcone_msgs', 'geometry_msgs', 'std_msgs')]; "
            "sys.exit(rc or (1 if bad else 0))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_with_a_plan_file_and_a_friction_interval_coulombs_law_for_every_model(
        tmp_path, capsys):
    """``--plan PLAN.json --friction 0.2 0.4``: at the start pose pin 1 (the stop) is
    off, so the plan's second segment (nnn) is not allowed and every command is replayed
    in arr; sliding right for every mu in [0.2, 0.4] needs phi in (-atan2(1, 0.4), 0) =
    (-68.20, 0) deg: -70 deg is inside the nominal cone (mu 0.3) but not for every model."""
    plan = tmp_path / "plan.json"
    plan.write_text('{"segments": [{"mode": "arr"}, {"mode": "nnn"}]}')
    cmds = [(-60.0, A10), (-70.0, A10), (-67.0, A10), (-69.0, A10), (10.0, A10)]
    bag = write_bag(tmp_path / "run", cmds)
    assert main(["replay", str(bag), "--plan", str(plan), "--friction", "0.2", "0.4",
                 "--json"]) == 0
    rows = __import__("json").loads(capsys.readouterr().out)["rows"]
    assert [r["segment_mode"] for r in rows] == ["arr"] * 5
    assert [r["consistent"] for r in rows] == [True, True, True, True, False]
    assert [r["robust_consistent"] for r in rows] == [True, False, True, False, False]
    assert all(r["robust_margin"] <= r["margin"] for r in rows)
    assert main(["replay", str(bag), "--plan", str(plan), "--friction", "0.2", "0.4",
                 "--table"]) == 0
    text = capsys.readouterr().out
    assert "plan arr -> nnn" in text and "for every model" in text and "2 of 5 inside" in text


@pytest.mark.parametrize("content, args, words", [
    (None, ["--plan"], "no controller state"),  # the recorded plan: no states in this bag
    ('{"feasible": false}', ["--plan", "{plan}"], "no segments"),
    ("[1, 2", ["--plan", "{plan}"], "not JSON or YAML"),
    ('{"segments": [{"mode": "arr"}]}', ["--plan", "{plan}", "--mode", "arr"], "not allowed"),
    ('{"segments": [{"mode": "arr"}]}', ["--plan", "{plan}", "--friction", "0.4", "0.2"],
     "LO <= HI"),
])
def test_a_bad_plan_gets_one_line_and_exit_status_2(tmp_path, content, args, words):
    plan = tmp_path / "plan.json"
    if content is not None:
        plan.write_text(content)
    bag = write_bag(tmp_path / "run", [(-58.5, A10)])
    proc = subprocess.run([sys.executable, "-m", "wrenchcone_ros.cli", "replay", str(bag)]
                          + [a.format(plan=plan) for a in args],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in proc.stderr


@pytest.mark.parametrize("mode, words", [
    ("xyz", "letter 'x' at fixel 1 is not one of 'aslrn'"),
    ("arrr", "has 4 letter(s) but the scene has 3 fixel(s)"),
    ("a*q", "letter 'q' at fixel 3"),
])
def test_an_impossible_mode_gets_one_line_and_exit_status_2(tmp_path, capsys, mode, words):
    """A mode no pose could allow (a letter outside the alphabet, the wrong length) is an
    error, not "0 of 0" commands replayed."""
    bag = write_bag(tmp_path / "run", [(-58.5, A10)] * 2)
    assert main(["replay", str(bag), "--mode", mode]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0] and repr(mode) in err[0], err
    assert main(["replay", str(bag), "--mode", "a*r"]) == 0  # wildcards are modes


def test_a_run_that_never_left_the_cone_says_so(tmp_path, capsys):
    bag = write_bag(tmp_path / "run", [(-58.5, A10)] * 3)
    assert main(["replay", str(bag), "--mode", "arr"]) == 0
    out = capsys.readouterr().out
    assert "never left the cone" in out and "(never)" not in out, out


def test_json_into_a_pipe_closed_early_ends_quietly(tmp_path):
    """``wrenchcone replay ... --json | head -c 100``: the reader stops early; no
    traceback, no error line, exit status 0 (the output was written as far as it was
    read)."""
    bag = write_bag(tmp_path / "run", [(-58.5, A10)] * 600)  # JSON far above a pipe's 64 kB
    command = (f"{sys.executable} -m wrenchcone_ros.cli replay {bag} --mode arr --json "
               "| head -c 100")
    proc = subprocess.run(["bash", "-o", "pipefail", "-c", command], capture_output=True,
                          text=True, timeout=300)
    assert len(proc.stdout) == 100
    assert proc.returncode == 0 and proc.stderr == "", (proc.returncode, proc.stderr)
