# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's parameters: one table (parameters.SPECS) and what is made from it.

The four made from the table agree with it: the declarations of a real node (descriptors,
ranges, read-only flags, defaults), config/wrenchcone.yaml (generated, and read by rcl as
for `ros2 run`), docs/node.md's table (test_docs_node.py) and the validation (every range
checked at its bounds). Over DDS, rclpy itself refuses an out-of-range value with its
reason and the node keeps its value; a misspelt name set at run time is refused with a
reason that names it and the closest declared names.
"""

from __future__ import annotations

import math
import threading
from pathlib import Path

import pytest
import yaml
from helpers.node_harness import DEADLINE_S, published_rows, same_rows
from rclpy.exceptions import ParameterNotDeclaredException
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import QoSProfile

from wrenchcone_ros.core import SceneError, default_scene, load_scene, wrench_cone
from wrenchcone_ros.node import PARAMETERS
from wrenchcone_ros.node import parameters as params
from wrenchcone_ros.node.parameter_files import (
    NODE_KEY,
    config_yaml,
    misaddressed_params_files,
    params_file_paths,
)

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "wrenchcone_ros" / "config" / "wrenchcone.yaml"
PAPER_DISC = ROOT / "examples" / "paper_disc.yaml"
PAWL = ROOT / "examples" / "pawl_polygon.yaml"
#: The scene every node test runs on unless it says otherwise (the built-in scene's file).
ON_DISC = ["-p", f"scene_file:={PAPER_DISC}"]


def _config() -> dict:
    return yaml.safe_load(CONFIG.read_text())[NODE_KEY]["ros__parameters"]


def _commented_config() -> dict:
    """The ``    # name: value`` lines of the config file (the scene-file parameters)."""
    found = {}
    for line in CONFIG.read_text().splitlines():
        body = line.strip().removeprefix("# ")
        name = body.split(":", 1)[0]
        if line.strip().startswith("# ") and name in params.SPEC:
            found[name] = yaml.safe_load(body)[name]
    return found


def _params_file(tmp_path: Path, values: dict, key: str = NODE_KEY) -> str:
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump({key: {"ros__parameters": values}}))
    return str(path)


def _wait(future, what: str):
    done = threading.Event()
    future.add_done_callback(lambda _f: done.set())
    assert done.wait(DEADLINE_S), f"no reply to {what}"
    return future.result()


# --- the table and the declarations --------------------------------------------------
def test_the_table_is_well_formed():
    assert len(set(PARAMETERS)) == len(params.SPECS)
    for spec in params.SPECS:
        assert spec.description.endswith("."), spec.name
        if spec.type in ("double", "int"):
            assert spec.low is not None and spec.high is not None, spec.name
            assert math.isfinite(spec.low) and math.isfinite(spec.high), spec.name
            # rclpy takes a value within 1e-6 (relative) of a bound as the bound: a range
            # to an infinite bound would let inf in
        if spec.read_only:
            assert spec.start_only, spec.name


def test_declared_descriptors_and_defaults_are_the_tables(harness_factory):
    """A real node, no overrides but the scene file of the built-in scene: each declared
    parameter's descriptor (type, range, read-only, description) and value is its row's."""
    node = harness_factory(cli_args=["--ros-args", *ON_DISC]).node
    declared = {n for n in node.list_parameters([], 0).names
                if not params.is_known(n) or n in params.SPEC}
    assert declared == set(PARAMETERS)  # nothing declared outside the table
    # the built-in defaults, but the scene file's own for what it gives (its modes)
    defaults = {**params.builtin_defaults(),
                **params.scene_defaults(load_scene(PAPER_DISC), str(PAPER_DISC))}
    for spec in params.SPECS:
        d = node.describe_parameter(spec.name)
        assert d.type == params.TYPES[spec.type], spec.name
        assert d.read_only == spec.read_only, spec.name
        assert d.description.startswith(spec.description), spec.name
        assert d.additional_constraints == spec.allowed(), spec.name
        if spec.type == "double":
            [r] = d.floating_point_range
            assert (r.from_value, r.to_value) == (spec.low, spec.high), spec.name
        elif spec.type == "int":
            [r] = d.integer_range
            assert (r.from_value, r.to_value) == (spec.low, spec.high), spec.name
        else:
            assert not d.floating_point_range and not d.integer_range, spec.name
        if spec.name == "scene_file":
            continue
        value = params.parameter_value(node, spec.name)
        value = list(value) if isinstance(value, (list, tuple)) or hasattr(value, "tolist") \
            else value
        assert value == defaults[spec.name], spec.name


def test_new_parameters():
    assert params.SPEC["autostart"].default is True and params.SPEC["autostart"].read_only
    s = params.SPEC["stamp_reset_threshold"]
    assert (s.type, s.default, s.unit, s.low, s.high) == ("double", 1.0, "s", 0.0, 1e6)
    assert "fast_check" not in params.SPEC  # the compiled lane is gone
    assert "NO_INPUTS" in params.SPEC["scene_file"].description
    # a vision-fed pose needs a tolerance on the sensor's scale: the range admits it
    c = params.SPEC["contact_tolerance"]
    assert c.contains(2e-3) and "2e-3 m" in c.description


# --- the validation against the ranges -----------------------------------------------
def _values(**changes) -> dict:
    return {**params.builtin_defaults(), "modes": [], **changes}


def _refused(name: str, value, **partner) -> bool:
    try:
        params.validate_values(_values(**{name: value}, **partner))
    except SceneError as exc:
        assert name.split("[")[0] in str(exc) or name in str(exc), str(exc)
        return True
    return False


@pytest.mark.parametrize("spec", [s for s in params.SPECS if s.low is not None],
                         ids=lambda s: s.name)
def test_validation_refuses_exactly_what_the_range_refuses(spec):
    """At each bound (by the next float, or integer, beyond it): inside accepted, outside
    refused; an open bound refused; nan and inf refused; 0 < x < min_nonzero refused."""
    def put(x):
        if spec.type != "double[]":
            return x
        n = spec.length or 2
        return [x] * n if spec.name not in ("workpiece.vertices",) else None

    integer = spec.type == "int"
    below = spec.low - 1 if integer else math.nextafter(spec.low, -math.inf)
    above = spec.high + 1 if integer else math.nextafter(spec.high, math.inf)
    if spec.name == "workpiece.vertices":  # a square far out, then one vertex beyond
        base = [spec.high / 2, 0.0, spec.high, 0.0, spec.high, spec.high / 2]
        assert not _refused(spec.name, base)
        assert _refused(spec.name, [above, *base[1:]])
        return
    assert _refused(spec.name, put(below))
    assert _refused(spec.name, put(above))
    if spec.type == "int":
        assert _refused(spec.name, float(spec.low))  # a double for an integer
    else:
        assert _refused(spec.name, put(math.nan)) and _refused(spec.name, put(math.inf))
    inside = {"workpiece.radius": 1.0, "uncertainty.friction": 0.2,
              "uncertainty.mass": 1.0, "uncertainty.inertia": 1.0}
    if spec.name in inside:  # the cross checks need a sensible value (an interval, a
        assert not _refused(spec.name, put(inside[spec.name]))  # disc of this size)
        return
    defaults = params.builtin_defaults()
    for bound, open_ in ((spec.low, spec.low_open), (spec.high, spec.high_open)):
        if spec.name in ("workpiece.com",) and bound:
            continue  # a com 1e9 m away from its disc is refused by the core (length)
        partner = {}
        if spec.name in ("workpiece.mass", "workpiece.inertia"):
            # the other one scaled alike, so that I/(m L^2) stays inside the accepted range
            other = ({"workpiece.mass": "workpiece.inertia", "workpiece.inertia":
                      "workpiece.mass"})[spec.name]
            partner = {other: bound * defaults[other] / defaults[spec.name]}
        assert _refused(spec.name, put(bound), **partner) == open_, (spec.name, bound)
    if spec.min_nonzero is not None:
        assert _refused(spec.name, spec.min_nonzero / 2)
        assert not _refused(spec.name, spec.min_nonzero)


def test_validation_checks_types_choices_and_the_cross_parameter_rules():
    assert _refused("workpiece.shape", "triangle")
    assert _refused("fixture_frame", "")
    assert _refused("publish_markers", 1)
    assert _refused("workpiece.com", [0.0])
    assert _refused("friction", "high")
    with pytest.raises(SceneError, match="wildcards"):
        params.validate_values(_values(modes=["na", "n*"]))
    with pytest.raises(SceneError, match="longer than max_mode_length"):
        params.validate_values(_values(modes=["nn"], max_mode_length=1))
    with pytest.raises(SceneError, match="vertices"):
        params.validate_values(_values(**{"workpiece.shape": "polygon",
                                          "workpiece.vertices": [0.0, 0.0, 1.0, 0.0]}))
    with pytest.raises(SceneError, match="uncertainty"):
        params.validate_values(_values(**{"uncertainty.mass": [2.0, 1.0]}))
    assert params.CROSS_CHECKS  # the named checks


# --- config/wrenchcone.yaml -------------------------------------------------------------
def test_the_config_file_is_the_generated_one():
    """`python -m wrenchcone_ros.node.parameter_files --write` rewrites it."""
    assert CONFIG.read_text() == config_yaml()


def test_the_config_file_gives_every_default_of_the_table():
    values, commented = _config(), _commented_config()
    assert set(values) | set(commented) == set(PARAMETERS)
    defaults = params.builtin_defaults()
    for spec in params.SPECS:
        if spec.name in values:
            assert spec.default is not params.FROM_SCENE
            assert values[spec.name] == spec.default, spec.name
        elif defaults[spec.name] is None:
            assert commented[spec.name] == spec.example, spec.name
        else:
            assert spec.default is params.FROM_SCENE, spec.name
            assert commented[spec.name] == defaults[spec.name], spec.name


def test_the_config_file_comments_say_each_rows_description_and_range():
    """Read as words (the comment lines joined): each row's description, unit and
    allowed values, unchanged by the line wrapping."""
    words = " ".join(line.strip().removeprefix("#").strip()
                     for line in CONFIG.read_text().splitlines()
                     if line.strip().startswith("#"))
    for spec in params.SPECS:
        assert params.descriptor_text(spec) in words, spec.name
        assert f"Allowed: {spec.allowed()}." in words, spec.name


def test_params_file_config_starts_the_node(harness_factory):
    """The config file read by rcl (`--params-file`, as `ros2 run` passes it)."""
    h = harness_factory(cli_args=["--ros-args", "--params-file", str(CONFIG), *ON_DISC])
    for name, value in _config().items():
        if name != "scene_file":
            assert h.node.get_parameter(name).value == value, name
    assert params.unknown_start_parameters(h.node) == []
    r = h.check("na", (0.1, -1.0, 0.0))
    cone = wrench_cone(default_scene(), "na")
    assert r.status == 0 and r.consistent == cone.contains((0.1, -1.0, 0.0))


def test_params_file_values_take_effect(harness_factory, tmp_path):
    values = {**_config(), "friction": 0.35, "modes": ["na", "ra"],
              "scene_file": str(PAPER_DISC), "publish_markers": False}
    h = harness_factory(cli_args=["--ros-args", "--params-file",
                                  _params_file(tmp_path, values)])
    assert h.node.get_parameter("friction").value == 0.35
    assert h.node.get_parameter("modes").value == ["na", "ra"]
    assert h.node.get_parameter("publish_markers").value is False
    scene = load_scene({**default_scene().to_dict(), "friction": 0.35})
    for mode in ("na", "ra"):
        msg = h.subscribe_cone(mode).wait_for(lambda m: True, f"~/cone/{mode}")
        assert same_rows(published_rows(msg)[0], wrench_cone(scene, mode).F)


def test_a_scene_file_with_the_config_gives_the_files_scene(harness_factory):
    """The config carries no scene values (they come from scene_file); a value given
    explicitly still wins (test_params_file_values_take_effect)."""
    h = harness_factory(cli_args=["--ros-args", "--params-file", str(CONFIG),
                                  "-p", f"scene_file:={PAWL}"])
    pawl = load_scene(str(PAWL))
    snap = h.node.snapshot
    assert snap.status == 0, snap.message
    assert snap.scene.n_fixels == 3 and snap.scene.friction == pawl.friction
    assert h.node.get_parameter("workpiece.shape").value == "polygon"
    assert h.node.get_parameter("modes").value == list(pawl.modes)


def test_an_integer_for_a_double_is_that_double(harness_factory, tmp_path):
    """`-p friction:=1` and a params file's `friction: 1` (rcl: an integer) start the node
    with friction 1.0, through public rclpy API (the overrides are only read)."""
    h = harness_factory(cli_args=["--ros-args", *ON_DISC, "-p", "friction:=1",
                                  "-p", "workpiece.com:=[0, 0]"])
    p = h.node.get_parameter("friction")
    assert p.type_ == Parameter.Type.DOUBLE and p.value == 1.0
    assert list(h.node.get_parameter("workpiece.com").value) == [0.0, 0.0]
    [res] = h.set_parameters(friction=2)  # at run time too (the pre-set callback)
    assert res.successful, res.reason
    assert h.node.get_parameter("friction").value == 2.0


# --- start-up refusals --------------------------------------------------------------------
@pytest.mark.parametrize("name,value", [("worker_nice", 20), ("worker_nice", -1),
                                        ("friction", -1.0), ("max_fixels", 0),
                                        ("stamp_reset_threshold", -0.5)])
def test_a_start_value_out_of_range_is_refused_by_rclpy(harness_factory, name, value):
    """rclpy refuses it at declaration (its reason, "out of range"); the node says which
    parameter and what is allowed, in one line."""
    with pytest.raises(SceneError) as info:
        harness_factory(**{name: value})
    text = str(info.value)
    assert f"parameter {name}:" in text and "out of range" in text, text
    assert f"allowed: {params.SPEC[name].allowed()}" in text, text
    assert "\n" not in text


def test_unknown_key_is_reported_at_start(harness_factory, tmp_path):
    values = {"frction": 0.3, "modes": ["na"], "scene_file": str(PAPER_DISC)}
    h = harness_factory(cli_args=["--ros-args", "--params-file",
                                  _params_file(tmp_path, values)])
    assert params.unknown_start_parameters(h.node) == ["frction"]
    assert h.node.get_parameter("friction").value == 0.2  # the misspelt value is unused
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

    name = h.node.get_fully_qualified_name()
    col = h.subscribe(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))
    msg = col.wait_for(lambda m: any(s.hardware_id == name for s in m.status),
                       "this node's diagnostics")
    (inputs,) = [s for s in msg.status if s.name == f"{name}: inputs"]
    assert inputs.level == DiagnosticStatus.WARN and "frction" in inputs.message


# --- over DDS: ranges refused by rclpy, misspelt names -----------------------------------
def test_out_of_range_values_are_refused_by_rclpy_over_dds(harness_factory):
    """A parameter client (rclpy's AsyncParameterClient, the services `ros2 param` uses):
    the descriptor carries the range; a value out of it is refused with rclpy's reason
    ("Parameter <name> out of range"), before the node's own check; the value stays."""
    h = harness_factory()
    client = AsyncParameterClient(h.tester, h.node.get_fully_qualified_name())
    assert client.wait_for_services(DEADLINE_S)
    described = _wait(client.describe_parameters(["friction", "max_fixels"]),
                      "describe_parameters").descriptors
    assert described[0].floating_point_range[0].to_value == params.SPEC["friction"].high
    assert described[1].integer_range[0].from_value == 1
    for name, bad in (("friction", -0.1), ("friction", math.nan),
                      ("workpiece.mass", 1e31), ("max_fixels", 0),
                      ("stamp_reset_threshold", 2e6), ("diagnostics_rate", 1001.0)):
        before = _wait(client.get_parameters([name]), "get_parameters").values[0]
        [res] = _wait(client.set_parameters([Parameter(name, value=bad)]),
                      "set_parameters").results
        assert not res.successful
        assert res.reason.startswith(f"Parameter {name} out of range"), res.reason
        after = _wait(client.get_parameters([name]), "get_parameters").values[0]
        assert after == before, name
        if (name, bad) == ("friction", -0.1):  # as docs/node.md quotes it
            quoted = ("Parameter friction out of range Min: 0.0, Max: 1000000000000.0, "
                      "value: -0.1")
            assert res.reason == quoted
            doc = " ".join((ROOT / "docs" / "node.md").read_text().split())
            assert quoted in doc
    # a bound rclpy's closed range admits but the row excludes: the node's own check
    [res] = h.set_parameters(contact_tolerance=0.0)
    assert not res.successful and "contact_tolerance must be a finite number in (0" in \
        res.reason, res.reason
    # a type rclpy refuses itself
    [res] = h.set_parameters(friction="high")
    assert not res.successful and "type" in res.reason.lower(), res.reason


def test_a_misspelt_name_is_refused_with_the_closest_names_over_dds(harness_factory):
    """rclpy alone answers "Invalid access to undeclared parameter(s): []" (its list is
    consumed before it is printed); the node's pre-set callback names the parameter and
    the declared names closest to it."""
    h = harness_factory()
    [res] = h.set_parameters(frction=0.3)
    assert not res.successful
    assert "'frction' is not a parameter of this node" in res.reason, res.reason
    assert "did you mean 'friction'?" in res.reason and "[]" not in res.reason
    res = h.set_parameters_atomically({"friction": 0.3, "max_fixel": 3})
    assert not res.successful and "'max_fixel'" in res.reason
    assert "'max_fixels'" in res.reason, res.reason
    assert h.node.get_parameter("friction").value == 0.2  # all or nothing
    [res] = h.set_parameters(zzzz=1)
    assert not res.successful and "no declared name is close" in res.reason
    with pytest.raises(ParameterNotDeclaredException, match="did you mean 'input_timeout'"):
        h.node.set_parameters([Parameter("input_timeot", value=1.0)])  # in-process too
    client = AsyncParameterClient(h.tester, h.node.get_fully_qualified_name())
    assert client.wait_for_services(DEADLINE_S)
    [res] = _wait(client.set_parameters([Parameter("stamp_reset_treshold", value=2.0)]),
                  "set_parameters").results
    assert "did you mean 'stamp_reset_threshold'?" in res.reason, res.reason


# --- renamed nodes and parameters files ---------------------------------------------------
def test_a_renamed_node_gets_no_values_of_the_default_names_section(ros_context,
                                                                      tmp_path):
    """Standard ROS behaviour, documented: `/**/wrenchcone` applies to nodes named
    wrenchcone only; a node renamed by `-r __node:=seater` needs `/**/seater` (or
    `/**`). misaddressed_params_files says so for a command line."""
    from wrenchcone_ros.node import WrenchConeNode

    path = str(tmp_path / "params.yaml")
    argv = ["wrenchcone_node", "--ros-args", "-r", "__node:=seater", "--params-file",
            path]
    for key, friction in ((NODE_KEY, 0.2), ("/**/seater", 0.35), ("/**", 0.35)):
        assert _params_file(tmp_path, {"friction": 0.35}, key) == path
        node = WrenchConeNode(context=ros_context, namespace=f"/rn{len(key)}",
                              cli_args=["--ros-args", *ON_DISC, *argv[2:]],
                              parameter_overrides=[Parameter("input_timeout", value=0.0)])
        try:
            assert node.get_name() == "seater"
            assert node.get_parameter("friction").value == friction, key
            warnings = misaddressed_params_files(argv, node.get_name(),
                                                        node.get_namespace())
            assert bool(warnings) == (key == NODE_KEY), (key, warnings)
            if warnings:
                assert "'/**/seater:'" in warnings[0] and path in warnings[0]
        finally:
            node.destroy_node()
    assert misaddressed_params_files(argv, "wrenchcone", "/") == []


def test_params_file_paths_are_read_from_the_ros_arguments():
    argv = ["prog", "--params-file", "not_ros.yaml", "--ros-args", "-r", "a:=b",
            "--params-file", "one.yaml", "--", "--ros-args", "--params-file", "two.yaml"]
    assert params_file_paths(argv) == ["one.yaml", "two.yaml"]


def test_the_publishing_worker_runs_at_worker_nice(harness_factory):
    import os

    h = harness_factory()
    base = os.getpriority(os.PRIO_PROCESS, 0)  # the process (the test's thread)
    worker = os.getpriority(os.PRIO_PROCESS, h.node.worker.thread.native_id)
    assert worker == 10 or (base > 10 and worker == base)  # raising it needs a privilege
    assert os.getpriority(os.PRIO_PROCESS, 0) == base  # only the worker thread
    h0 = harness_factory(worker_nice=0)
    assert os.getpriority(os.PRIO_PROCESS, h0.node.worker.thread.native_id) == base
    [res] = h.set_parameters(worker_nice=3)
    assert not res.successful and "read-only" in res.reason  # given at start only


def test_examples_launch_and_config_are_installed():
    from ament_index_python.packages import get_package_share_directory

    share = Path(get_package_share_directory("wrenchcone_ros"))
    for rel in ("examples/paper_disc.yaml", "examples/pawl_polygon.yaml",
                "launch/wrenchcone.launch.py", "config/wrenchcone.yaml"):
        assert (share / rel).is_file(), rel


@pytest.mark.slow
def test_an_invalid_initial_scene_exits_2_with_one_line(tmp_path):
    """The node program on a scene that is not valid at start (the pawl's fixels in a
    1 m disc) ends at once with status 2 and one line saying why."""
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
