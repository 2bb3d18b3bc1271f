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


def test_config_lists_every_parameter_with_its_default(harness_factory):
    values = _config()
    # workpiece.vertices has no default for the default disc: it is a comment there
    assert set(values) | {"workpiece.vertices"} == set(PARAMETERS)
    assert "# workpiece.vertices:" in CONFIG.read_text()
    plain = harness_factory()  # the harness sets HARNESS_DEFAULTS: compare the rest
    for name, value in values.items():
        if name not in HARNESS_DEFAULTS:
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
