# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The launch files (launch/*.launch.py), tested without the launch packages.

``ros2 launch`` needs the packages launch and launch_ros, which have no PyPI wheel, so
the files cannot be run here. Each file is executed instead with a small stand-in of the
launch API (:class:`FakeLaunch`: ``launch``, ``launch.actions``,
``launch.substitutions``, ``launch_ros.actions``, ``launch_ros.parameter_descriptions``,
``launch_ros.substitutions`` put in ``sys.modules`` for the import only), whose classes
record their arguments; any other launch name fails the import, so a file using a
construct this test does not model fails. Then:

* the recorded description is checked: the usual arguments (``use_sim_time``,
  ``autostart``, ``log_level``, ``namespace``, ``params_file``), every launch
  configuration used is a declared argument, the wrenchcone node is a LifecycleNode;
* the substitutions are evaluated as launch would for given argument values
  (:meth:`Recorded.evaluate`: defaults, ``FindPackageShare`` through the ament index,
  ``ParameterValue`` parsed as YAML and coerced to its type), and the command line
  launch_ros gives a node is built from them (``--ros-args --log-level L -r __node:=NAME
  -r __ns:=NS --params-file FILE ...``);
* the installed executable started with that command line comes up in the argument's
  namespace, unconfigured with ``autostart:=false`` (over DDS, with rclpy);
* the closed-loop file starts the three programs of docs/closed_loop.md section 1 with
  the parameters its three shell commands give, in one namespace.

Not tested: launch's own process handling and its substitution engine.
"""

from __future__ import annotations

import os
import re
import secrets
import shlex
import signal
import subprocess
import sys
import tempfile
import time
import types
import typing
from pathlib import Path

import pytest
import yaml

ament_index_python = pytest.importorskip("ament_index_python")
rclpy = pytest.importorskip("rclpy")

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "wrenchcone_ros"
LAUNCH_DIR = ROOT / PACKAGE / "launch"
SOURCE = LAUNCH_DIR / "wrenchcone.launch.py"
CLOSED_LOOP = LAUNCH_DIR / "closed_loop.launch.py"
START_TIMEOUT_S = 60.0  # a guard against a hang only: the node starts in a few seconds
USUAL_ARGUMENTS = {"use_sim_time", "autostart", "log_level", "namespace"}


class Recorded:
    """One launch object: its class name, positional and keyword arguments."""

    def __init__(self, *args, **kwargs):
        self.args, self.kwargs = args, kwargs

    @property
    def kind(self) -> str:
        return type(self).__name__


def _fake_modules() -> dict[str, types.ModuleType]:
    """The launch API's names this project's launch files may use, as recorders."""
    layout = {
        "launch": ["LaunchDescription"],
        "launch.actions": ["DeclareLaunchArgument"],
        "launch.substitutions": ["LaunchConfiguration", "PathJoinSubstitution"],
        "launch_ros.actions": ["Node", "LifecycleNode"],
        "launch_ros.parameter_descriptions": ["ParameterValue"],
        "launch_ros.substitutions": ["FindPackageShare"],
    }
    modules = {"launch_ros": types.ModuleType("launch_ros")}
    for name, classes in layout.items():
        module = types.ModuleType(name)
        for cls in classes:
            setattr(module, cls, type(cls, (Recorded,), {}))
        modules[name] = module
    return modules


class FakeLaunch:
    """A launch file's description, executed with the recording launch API."""

    def __init__(self, path: Path):
        saved = {k: sys.modules.get(k) for k in _fake_modules()}
        sys.modules.update(_fake_modules())
        try:
            namespace: dict = {"__name__": "launch_file", "__file__": str(path)}
            exec(compile(path.read_text(), str(path), "exec"), namespace)  # noqa: S102
            description = namespace["generate_launch_description"]()
        finally:
            for k, v in saved.items():
                if v is None:
                    sys.modules.pop(k, None)
                else:
                    sys.modules[k] = v
        assert description.kind == "LaunchDescription"
        [entities] = description.args
        self.arguments = {}
        self.nodes = []
        for entity in entities:
            if entity.kind == "DeclareLaunchArgument":
                [name] = entity.args
                assert entity.kwargs.get("description"), name
                self.arguments[name] = entity.kwargs.get("default_value")
            else:
                assert entity.kind in ("Node", "LifecycleNode"), entity.kind
                self.nodes.append(entity)
        self.used = set()
        for node in self.nodes:
            self._collect(node.kwargs)
        for default in self.arguments.values():
            self._collect(default)

    def _collect(self, value) -> None:
        if isinstance(value, Recorded):
            if value.kind == "LaunchConfiguration":
                self.used.add(value.args[0])
            for v in (*value.args, *value.kwargs.values()):
                self._collect(v)
        elif isinstance(value, (list, tuple)):
            for v in value:
                self._collect(v)
        elif isinstance(value, dict):
            for v in value.values():
                self._collect(v)

    def node(self, name: str) -> Recorded:
        [node] = [n for n in self.nodes if n.kwargs["name"] == name]
        return node

    def evaluate(self, value, given: dict[str, str]):
        """The value of an argument expression, as launch would substitute it."""
        if value is None or isinstance(value, (str, int, float, bool)):
            return value
        if isinstance(value, list):
            return [self.evaluate(v, given) for v in value]
        if isinstance(value, dict):
            return {k: self.evaluate(v, given) for k, v in value.items()}
        kind = value.kind
        if kind == "LaunchConfiguration":
            key = value.args[0]
            return given[key] if key in given else self.evaluate(self.arguments[key], given)
        if kind == "FindPackageShare":
            return ament_index_python.get_package_share_directory(
                self.evaluate(value.args[0], given))
        if kind == "PathJoinSubstitution":
            return os.path.join(*self.evaluate(value.args[0], given))
        if kind == "ParameterValue":
            text = self.evaluate(value.args[0], given)
            parsed = yaml.safe_load(text)
            wanted = value.kwargs.get("value_type")
            if wanted in (bool, int, float, str):
                assert type(parsed) is wanted or (wanted is float and type(parsed) is int), \
                    f"{text!r} is not a {wanted.__name__}"
                return wanted(parsed)
            item = typing.get_args(wanted)[0]
            assert isinstance(parsed, list), text
            return [item(v) for v in parsed]
        raise AssertionError(f"a launch construct this test does not evaluate: {kind}")

    def command(self, node: Recorded, given: dict[str, str], tmp: Path) -> list[str]:
        """The command launch_ros runs for a node action: the executable from the
        package's lib directory, then ``--ros-args`` with the node's ros_arguments, its
        name and namespace remaps, and one ``--params-file`` per parameters entry (a dict
        written to a file of its own, as launch_ros does)."""
        package = self.evaluate(node.kwargs["package"], given)
        executable = Path(ament_index_python.get_package_prefix(package), "lib", package,
                          self.evaluate(node.kwargs["executable"], given))
        cmd = [str(executable), "--ros-args",
               *self.evaluate(node.kwargs.get("ros_arguments", []), given),
               "-r", f"__node:={self.evaluate(node.kwargs['name'], given)}"]
        ns = self.evaluate(node.kwargs["namespace"], given)
        if ns:
            cmd += ["-r", f"__ns:={ns if ns.startswith('/') else '/' + ns}"]
        for i, entry in enumerate(self.evaluate(node.kwargs.get("parameters", []), given)):
            if isinstance(entry, dict):
                path = tmp / f"{node.kwargs['name']}_{i}.yaml"
                path.write_text(yaml.safe_dump({"/**": {"ros__parameters": entry}}))
                entry = str(path)
            cmd += ["--params-file", entry]
        return cmd

    def parameters(self, node: Recorded, given: dict[str, str]) -> dict:
        """The node's parameters as the launch gives them (files read, later wins)."""
        merged: dict = {}
        for entry in self.evaluate(node.kwargs.get("parameters", []), given):
            if isinstance(entry, str):
                [section] = yaml.safe_load(Path(entry).read_text()).values()
                entry = section["ros__parameters"]
            merged.update(entry)
        return merged


@pytest.fixture(scope="module")
def launch_file():
    return FakeLaunch(SOURCE)


@pytest.fixture(scope="module")
def closed_loop():
    return FakeLaunch(CLOSED_LOOP)


@pytest.mark.parametrize("path", [SOURCE, CLOSED_LOOP])
def test_the_installed_launch_files_are_the_sources(path):
    installed = Path(ament_index_python.get_package_share_directory(PACKAGE), "launch",
                     path.name)
    assert installed.read_text() == path.read_text()


def test_the_node_launch_has_the_usual_arguments_and_a_lifecycle_node(launch_file):
    assert launch_file.used <= set(launch_file.arguments), launch_file.used
    assert set(launch_file.arguments) == USUAL_ARGUMENTS | {"params_file"}
    [node] = launch_file.nodes
    assert node.kind == "LifecycleNode"
    defaults = launch_file.parameters(node, {})
    assert defaults["autostart"] is True and defaults["use_sim_time"] is False
    given = {"autostart": "false", "use_sim_time": "true", "namespace": "cell1",
             "log_level": "debug"}
    chosen = launch_file.parameters(node, given)
    assert chosen["autostart"] is False and chosen["use_sim_time"] is True
    assert launch_file.evaluate(node.kwargs["namespace"], given) == "cell1"
    assert launch_file.evaluate(node.kwargs["ros_arguments"], given) == \
        ["--log-level", "debug"]


def test_the_node_launch_names_what_is_installed(launch_file, tmp_path):
    [node] = launch_file.nodes
    package = launch_file.evaluate(node.kwargs["package"], {})
    assert package == PACKAGE
    executable = Path(launch_file.command(node, {}, tmp_path)[0])
    assert executable.is_file() and os.access(executable, os.X_OK), executable
    [params_file, _overrides] = launch_file.evaluate(node.kwargs["parameters"], {})
    share = Path(ament_index_python.get_package_share_directory(PACKAGE))
    assert Path(params_file) == share / "config" / "wrenchcone.yaml"
    # the file's section is this node's (else its parameters would not apply)
    name = launch_file.evaluate(node.kwargs["name"], {})
    sections = yaml.safe_load(Path(params_file).read_text())
    assert list(sections) == [f"/**/{name}"] and "ros__parameters" in sections[f"/**/{name}"]
    assert launch_file.evaluate(node.kwargs["parameters"], {"params_file": "/my.yaml"})[0] \
        == "/my.yaml"


def test_a_bad_boolean_argument_is_refused(launch_file):
    [node] = launch_file.nodes
    with pytest.raises(AssertionError, match="is not a bool"):
        launch_file.parameters(node, {"autostart": "maybe"})


def _docs_commands() -> dict[str, dict]:
    """The three programs' parameters as docs/closed_loop.md section 1 starts them."""
    text = (ROOT / "docs" / "closed_loop.md").read_text()
    section = text[text.index("## 1. Running the loop by hand"):text.index("**In lockstep**")]
    commands = {}
    for line in re.sub(r"\\\n\s*", " ", section).splitlines():
        words = shlex.split(line.strip())
        if words and words[0] in ("wrenchcone_node", "tray_sim", "tilt_controller"):
            params = {}
            for i, w in enumerate(words):
                if w == "-p":
                    key, value = words[i + 1].split(":=", 1)
                    params[key] = yaml.safe_load(value)
            commands[words[0]] = params
    assert set(commands) == {"wrenchcone_node", "tray_sim", "tilt_controller"}, commands
    return commands


def test_the_closed_loop_launch_starts_the_docs_three_programs(closed_loop):
    assert closed_loop.used <= set(closed_loop.arguments), closed_loop.used
    assert USUAL_ARGUMENTS <= set(closed_loop.arguments)
    by_executable = {closed_loop.evaluate(n.kwargs["executable"], {}): n
                     for n in closed_loop.nodes}
    assert by_executable["wrenchcone_node"].kind == "LifecycleNode"
    docs = _docs_commands()
    share = Path(ament_index_python.get_package_share_directory(PACKAGE))
    for program, wanted in docs.items():
        got = closed_loop.parameters(by_executable[program], {})
        for key, value in wanted.items():
            if key == "scene_file":  # the docs' path in the repository, installed here
                assert Path(got[key]) == share / value, (program, got[key])
                assert (ROOT / PACKAGE / value).is_file()
            else:
                assert got[key] == value, (program, key, got.get(key), value)
    # one namespace for the three: the controller's relative server finds the node
    given = {"namespace": "cell7"}
    assert {closed_loop.evaluate(n.kwargs["namespace"], given) for n in closed_loop.nodes} \
        == {"cell7"}
    assert {closed_loop.evaluate(n.kwargs["name"], {}) for n in closed_loop.nodes} == \
        {"wrenchcone", "tray_sim", "tilt_controller"}
    lockstep = {"lockstep": "true"}
    for program in ("tray_sim", "tilt_controller"):
        assert closed_loop.parameters(by_executable[program], lockstep)["lockstep"] is True


def _wait_for_node(name: str, namespace: str, process, service: str) -> set[str]:
    context = rclpy.context.Context()
    rclpy.init(context=context)
    services: set[str] = set()
    try:
        observer = rclpy.create_node("launch_file_observer", context=context)
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline and process.poll() is None:
            services = {s for s, _ in observer.get_service_names_and_types_by_node(
                name, namespace)} if (name, namespace) in \
                observer.get_node_names_and_namespaces() else set()
            if f"{namespace}/{name}/{service}" in services:
                break
            time.sleep(0.2)
        observer.destroy_node()
    finally:
        rclpy.shutdown(context=context)
    return services


def _stop(process) -> str:
    process.send_signal(signal.SIGINT)
    try:
        return process.communicate(timeout=20)[0]
    except subprocess.TimeoutExpired:
        process.kill()
        return process.communicate()[0]


@pytest.mark.slow
@pytest.mark.parametrize("autostart", ["true", "false"])
def test_the_node_action_starts_the_node(launch_file, autostart):
    """As launched: active with the installed parameters, or, with ``autostart:=false``,
    unconfigured (its lifecycle services up, check_wrench not yet made)."""
    [node] = launch_file.nodes
    namespace = f"/launch_test_{secrets.token_hex(4)}"  # unique: parallel runs share a domain
    given = {"namespace": namespace, "autostart": autostart}
    name = launch_file.evaluate(node.kwargs["name"], given)
    with tempfile.TemporaryDirectory() as tmp:
        command = launch_file.command(node, given, Path(tmp))
        process = subprocess.Popen(command, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True)
        try:
            services = _wait_for_node(name, namespace, process,
                                      "check_wrench" if autostart == "true" else "get_state")
        finally:
            output = _stop(process)
    assert f"{namespace}/{name}/get_state" in services, (sorted(services), output)
    assert (f"{namespace}/{name}/check_wrench" in services) == (autostart == "true"), \
        sorted(services)
    assert "Traceback" not in output, output


@pytest.mark.slow
def test_the_closed_loop_launch_runs_the_loop(closed_loop, tmp_path):
    """The three programs started as launch_ros would start the closed-loop file's
    actions, in one namespace: the controller gets a plan from the node (it executes
    a segment) for the tray's part."""
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import QoSProfile

    from wrenchcone_msgs.msg import ControllerState

    namespace = f"/loop_test_{secrets.token_hex(4)}"
    given = {"namespace": namespace}
    processes = [subprocess.Popen(closed_loop.command(node, given, tmp_path),
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
                 for node in closed_loop.nodes]
    context = rclpy.context.Context()
    rclpy.init(context=context)
    states: list[str] = []
    try:
        observer = rclpy.create_node("loop_observer", context=context)
        observer.create_subscription(ControllerState, f"{namespace}/tilt_controller/state",
                                     lambda m: states.append(m.state), QoSProfile(depth=100))
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(observer)
        deadline = time.monotonic() + 4 * START_TIMEOUT_S
        while time.monotonic() < deadline and all(p.poll() is None for p in processes):
            executor.spin_once(timeout_sec=0.2)
            if {"EXECUTING", "HOLDING", "SEATED"} & set(states):
                break
        observer.destroy_node()
    finally:
        rclpy.shutdown(context=context)
        outputs = [_stop(p) for p in processes]
    assert {"EXECUTING", "HOLDING", "SEATED"} & set(states), (
        sorted(set(states)), [o[-2000:] for o in outputs])
    for node, output in zip(closed_loop.nodes, outputs):
        assert "Traceback" not in output, (node.kwargs["name"], output[-3000:])
