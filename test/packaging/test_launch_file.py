# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The launch file (launch/wrenchcone.launch.py), tested without the launch packages.

``ros2 launch`` needs the packages launch and launch_ros, which have no PyPI wheel
(``pip index versions ros-jazzy-launch ros-jazzy-launch-ros`` finds none), so the file
cannot be run here. What can be tested without them is:

* the file parses, imports only launch and launch_ros, and every launch configuration
  it reads is a declared argument;
* its arguments and its Node action, read from the syntax tree (not by matching
  strings) and evaluated for a small, closed set of launch constructs (any other
  construct fails the test): the package, the executable, the node's name and the
  default parameters file name what the build installed (found through the ament
  index, as launch_ros finds them), and the parameters file's section is the node's;
* the installed executable, started with the arguments launch_ros gives a Node action
  (``--ros-args -r __node:=NAME -r __ns:=NAMESPACE --params-file FILE``), starts with the
  installed parameters file and offers its services in the launch argument's namespace
  (over DDS, seen with rclpy).

Not tested: launch's own substitution and process handling.
"""

from __future__ import annotations

import ast
import os
import secrets
import signal
import subprocess
import time
from pathlib import Path

import pytest
import yaml

ament_index_python = pytest.importorskip("ament_index_python")
rclpy = pytest.importorskip("rclpy")

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "wrenchcone_ros"
SOURCE = ROOT / PACKAGE / "launch" / "wrenchcone.launch.py"
START_TIMEOUT_S = 60.0  # a guard against a hang only: the node starts in a few seconds
LAUNCH_MODULES = {"launch", "launch.actions", "launch.substitutions", "launch_ros.actions",
                  "launch_ros.substitutions"}


def _call_name(call: ast.Call) -> str:
    func = call.func
    return func.id if isinstance(func, ast.Name) else func.attr


class LaunchDescriptionReader:
    """The launch file's arguments and Node actions, from its syntax tree."""

    def __init__(self, text: str):
        tree = ast.parse(text)
        imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import)
                     for a in n.names}
        assert imported <= LAUNCH_MODULES, imported - LAUNCH_MODULES
        functions = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
        assert [f.name for f in functions] == ["generate_launch_description"]
        self.calls = [n for n in ast.walk(functions[0]) if isinstance(n, ast.Call)]
        self.arguments = {}  # name -> default (an AST node) and description
        for call in self._named("DeclareLaunchArgument"):
            name = self.literal(call.args[0])
            keywords = {k.arg: k.value for k in call.keywords}
            assert self.literal(keywords["description"]), name
            self.arguments[name] = keywords.get("default_value")
        self.nodes = [{k.arg: k.value for k in call.keywords} for call in self._named("Node")]
        self.used = [self.literal(c.args[0]) for c in self._named("LaunchConfiguration")]

    def _named(self, name: str) -> list[ast.Call]:
        return [c for c in self.calls if _call_name(c) == name]

    @staticmethod
    def literal(node: ast.AST):
        assert isinstance(node, ast.Constant), ast.dump(node)
        return node.value

    def evaluate(self, node: ast.AST, given: dict[str, str]):
        """The value of an argument expression, as launch would substitute it."""
        if isinstance(node, ast.Constant):
            return node.value
        if isinstance(node, ast.List):
            return [self.evaluate(e, given) for e in node.elts]
        assert isinstance(node, ast.Call), f"not understood here: {ast.dump(node)}"
        name, args = _call_name(node), node.args
        if name == "LaunchConfiguration":
            key = self.literal(args[0])
            if key in given:
                return given[key]
            return self.evaluate(self.arguments[key], given)
        if name == "FindPackageShare":
            return ament_index_python.get_package_share_directory(self.evaluate(args[0], given))
        if name == "PathJoinSubstitution":
            return os.path.join(*self.evaluate(args[0], given))
        raise AssertionError(f"a launch construct this test does not evaluate: {name}")


@pytest.fixture(scope="module")
def launch_file():
    return LaunchDescriptionReader(SOURCE.read_text())


def test_the_installed_launch_file_is_the_source(launch_file):
    installed = Path(ament_index_python.get_package_share_directory(PACKAGE), "launch",
                     SOURCE.name)
    assert installed.read_text() == SOURCE.read_text()


def test_arguments_and_node_action_name_what_is_installed(launch_file):
    assert set(launch_file.used) <= set(launch_file.arguments), launch_file.used
    assert set(launch_file.arguments) == {"params_file", "namespace"}
    [node] = launch_file.nodes
    package = launch_file.evaluate(node["package"], {})
    assert package == PACKAGE
    # launch_ros finds the executable as `ros2 run` does: <prefix>/lib/<package>/<name>
    executable = Path(ament_index_python.get_package_prefix(package), "lib", package,
                      launch_file.evaluate(node["executable"], {}))
    assert executable.is_file() and os.access(executable, os.X_OK), executable
    [params_file] = launch_file.evaluate(node["parameters"], {})
    share = Path(ament_index_python.get_package_share_directory(PACKAGE))
    assert Path(params_file) == share / "config" / "wrenchcone.yaml"
    # the file's section is this node's (else its parameters would not apply)
    name = launch_file.evaluate(node["name"], {})
    sections = yaml.safe_load(Path(params_file).read_text())
    assert list(sections) == [f"/**/{name}"] and "ros__parameters" in sections[f"/**/{name}"]
    assert launch_file.evaluate(node["namespace"], {}) == ""
    assert launch_file.evaluate(node["namespace"], {"namespace": "cell1"}) == "cell1"
    assert launch_file.evaluate(node["parameters"], {"params_file": "/my.yaml"}) == ["/my.yaml"]


@pytest.mark.slow
def test_node_action_starts_the_node_with_the_installed_parameters(launch_file):
    [node] = launch_file.nodes
    namespace = f"/launch_test_{secrets.token_hex(4)}"  # unique: parallel runs share a domain
    given = {"namespace": namespace}
    package = launch_file.evaluate(node["package"], given)
    executable = Path(ament_index_python.get_package_prefix(package), "lib", package,
                      launch_file.evaluate(node["executable"], given))
    name = launch_file.evaluate(node["name"], given)
    [params_file] = launch_file.evaluate(node["parameters"], given)
    command = [str(executable), "--ros-args", "-r", f"__node:={name}", "-r",
               f"__ns:={launch_file.evaluate(node['namespace'], given)}",
               "--params-file", params_file]
    context = rclpy.context.Context()
    rclpy.init(context=context)
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True)
    try:
        observer = rclpy.create_node("launch_file_observer", context=context)
        deadline = time.monotonic() + START_TIMEOUT_S
        services = set()
        while time.monotonic() < deadline and process.poll() is None:
            services = {s for s, _ in observer.get_service_names_and_types_by_node(
                name, namespace)} if (name, namespace) in \
                observer.get_node_names_and_namespaces() else set()
            if f"{namespace}/{name}/check_wrench" in services:
                break
            time.sleep(0.2)
        observer.destroy_node()
    finally:
        process.send_signal(signal.SIGINT)
        try:
            output = process.communicate(timeout=20)[0]
        except subprocess.TimeoutExpired:
            process.kill()
            output = process.communicate()[0]
        rclpy.shutdown(context=context)
    assert f"{namespace}/{name}/check_wrench" in services, (sorted(services), output)
    assert f"{namespace}/{name}/get_cone" in services, sorted(services)
    assert "Traceback" not in output, output
