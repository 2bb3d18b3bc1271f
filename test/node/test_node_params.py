"""Starting the node with config/wrenchcone.yaml (`--params-file`, parsed by rcl as for
`ros2 run`), a changed copy of it, and a misspelt key, which is reported at start."""

from __future__ import annotations

from pathlib import Path

import yaml
from node_harness import HARNESS_DEFAULTS, published_rows, same_rows
from rclpy.qos import QoSProfile

from wrenchcone_ros.core import default_scene, load_scene, wrench_cone
from wrenchcone_ros.node import PARAMETERS
from wrenchcone_ros.node.parameters import fast_check_default

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "config" / "wrenchcone.yaml"
NODE_KEY = "/**/wrenchcone"


def _config() -> dict:
    return yaml.safe_load(CONFIG.read_text())[NODE_KEY]["ros__parameters"]


def _params_file(tmp_path: Path, values: dict) -> str:
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump({NODE_KEY: {"ros__parameters": values}}))
    return str(path)


#: The scene parameters: their defaults come from scene_file, so the config lists them as
#: comments (given there, they would override the scene file's values).
SCENE_PARAMETERS = {"workpiece.mass", "workpiece.inertia", "workpiece.com", "workpiece.shape",
                    "workpiece.radius", "workpiece.vertices", "friction",
                    "contact_tolerance", "fixel_radius", "modes", "uncertainty.friction",
                    "uncertainty.mass", "uncertainty.inertia", "uncertainty.com_radius",
                    "uncertainty.normal_error"}
#: Commented examples, not defaults (the default is unset).
EXAMPLES = {"workpiece.vertices", "uncertainty.friction", "uncertainty.mass",
            "uncertainty.inertia"}


def test_config_lists_every_parameter_with_its_default(harness_factory):
    values = _config()
    assert set(values) | SCENE_PARAMETERS == set(PARAMETERS)
    assert not set(values) & SCENE_PARAMETERS
    text = CONFIG.read_text()
    commented = {}
    for line in text.splitlines():  # "    # name: value" lines: the built-in disc's values
        body = line.strip().removeprefix("# ")
        name = body.split(":", 1)[0]
        if line.strip().startswith("# ") and name in SCENE_PARAMETERS:
            commented[name] = yaml.safe_load(body)[name]
    assert set(commented) == SCENE_PARAMETERS
    plain = harness_factory()  # the harness sets HARNESS_DEFAULTS: compare the rest
    for name, value in {**values, **commented}.items():
        if name not in HARNESS_DEFAULTS and name not in EXAMPLES:
            if name == "fast_check":  # its default comes from WRENCHCONE_FAST_CHECK
                value = value and fast_check_default()
            assert plain.node.get_parameter(name).value == value, name


def test_params_file_config_starts_the_node(harness_factory):
    h = harness_factory(cli_args=["--ros-args", "--params-file", str(CONFIG)])
    for name, value in _config().items():
        assert h.node.get_parameter(name).value == value, name
    assert h.node.diagnostics.unknown == []
    r = h.check("na", (0.1, -1.0, 0.0))
    cone = wrench_cone(default_scene(), "na")
    assert r.status == 0 and r.consistent == cone.contains((0.1, -1.0, 0.0))


def test_params_file_values_take_effect(harness_factory, tmp_path):
    values = {**_config(), "friction": 0.35, "modes": ["na", "ra"],
              "scene_file": str(ROOT / "examples" / "paper_disc.yaml"),
              "publish_markers": False}
    h = harness_factory(cli_args=["--ros-args", "--params-file",
                                  _params_file(tmp_path, values)])
    assert h.node.get_parameter("friction").value == 0.35
    assert h.node.get_parameter("modes").value == ["na", "ra"]
    assert h.node.get_parameter("publish_markers").value is False
    scene = load_scene({**default_scene().to_dict(), "friction": 0.35})
    for mode in ("na", "ra"):
        msg = h.subscribe_cone(mode).wait_for(lambda m: True, f"~/cone/{mode}")
        assert same_rows(published_rows(msg)[0], wrench_cone(scene, mode).F)


def test_unknown_key_is_reported_at_start(harness_factory, tmp_path):
    values = {"frction": 0.3, "modes": ["na"], "diagnostics_rate": 20.0}
    h = harness_factory(cli_args=["--ros-args", "--params-file",
                                  _params_file(tmp_path, values)])
    assert h.node.diagnostics.unknown == ["frction"]
    assert h.node.get_parameter("friction").value == 0.2  # the misspelt value is unused
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

    name = h.node.get_fully_qualified_name()
    col = h.subscribe(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))
    msg = col.wait_for(lambda m: any(s.hardware_id == name for s in m.status),
                       "this node's diagnostics")
    (inputs,) = [s for s in msg.status if s.name == f"{name}: inputs"]
    assert inputs.level == DiagnosticStatus.WARN and "frction" in inputs.message


def test_examples_launch_and_config_are_installed():
    from ament_index_python.packages import get_package_share_directory

    share = Path(get_package_share_directory("wrenchcone_ros"))
    for rel in ("examples/paper_disc.yaml", "examples/pawl_polygon.yaml",
                "launch/wrenchcone.launch.py", "config/wrenchcone.yaml"):
        assert (share / rel).is_file(), rel


def test_the_publishing_worker_runs_at_worker_nice(harness_factory):
    import os

    import pytest

    from wrenchcone_ros.core import SceneError

    h = harness_factory()
    base = os.getpriority(os.PRIO_PROCESS, 0)  # the process (the test's thread)
    worker = os.getpriority(os.PRIO_PROCESS, h.node.worker.thread.native_id)
    assert worker == 10 or (base > 10 and worker == base)  # raising it needs a privilege
    assert os.getpriority(os.PRIO_PROCESS, 0) == base  # only the worker thread
    h0 = harness_factory(worker_nice=0)
    assert os.getpriority(os.PRIO_PROCESS, h0.node.worker.thread.native_id) == base
    for bad in (20, -1):
        with pytest.raises(SceneError, match="worker_nice must be an integer in"):
            harness_factory(worker_nice=bad)
    assert not h.set_parameters(worker_nice=3)[0].successful  # read at start only


PAWL = ROOT / "examples" / "pawl_polygon.yaml"


def test_a_scene_file_with_the_config_gives_the_files_scene(harness_factory):
    """`make run ARGS="--ros-args --params-file config/wrenchcone.yaml -p
    scene_file:=examples/pawl_polygon.yaml"`: the file's scene, not the config's disc
    (the config carries no scene values: they come from scene_file; a value given
    explicitly still wins, test_params_file_values_take_effect). Before, the config's
    disc values replaced the pawl's polygon and the node started on a scene error
    ("fixel 1 penetrates the workpiece by 0.94 m")."""
    h = harness_factory(cli_args=["--ros-args", "--params-file", str(CONFIG),
                                  "-p", f"scene_file:={PAWL}"])
    pawl = load_scene(str(PAWL))
    snap = h.node.snapshot
    assert snap.status == 0, snap.message
    assert snap.scene.n_fixels == 3 and snap.scene.friction == pawl.friction
    assert h.node.get_parameter("workpiece.shape").value == "polygon"
    assert h.node.get_parameter("modes").value == list(pawl.modes)
    cone = wrench_cone(pawl, "arr")
    r = h.check("arr", (0.1, -1.0, 0.0))
    assert r.status == 0 and r.consistent == cone.contains((0.1, -1.0, 0.0))


def test_an_invalid_initial_scene_exits_2_with_one_line(tmp_path):
    """The node program on a scene that is not valid at start (the pawl's fixels in a
    1 m disc) ends at once with status 2 and one line saying why; before, it logged a
    warning and ran on, "ready: ? fixel(s)"."""
    import os
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "wrenchcone_ros.node", "--ros-args", "-p",
         f"scene_file:={PAWL}", "-p", "workpiece.shape:=disc", "-p",
         "workpiece.radius:=1.0"], capture_output=True, text=True, timeout=60,
        check=False, env=dict(os.environ), cwd=tmp_path)  # the installed package
    lines = (out.stdout + out.stderr).strip().splitlines()
    assert out.returncode == 2, lines[-5:]
    assert len(lines) == 1 and "penetrates" in lines[0], lines


def test_every_example_scene_monitors_only_possible_modes():
    """A monitored mode that no wrench realises publishes MODE_INFEASIBLE forever (the
    pawl example monitored 'ann')."""
    for path in sorted((ROOT / "examples").glob("*.yaml")):
        data = yaml.safe_load(path.read_text())
        if "workpiece" not in data:  # not a scene (a list of poses)
            continue
        scene = load_scene(str(path))
        for mode in scene.modes:
            assert wrench_cone(scene, mode).feasible, (path.name, mode)
