# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The closed loop in one launch: the wrenchcone node, the simulated tray and the
reference controller in one namespace (docs/closed_loop.md section 1, three shells).

    ros2 launch wrenchcone_ros closed_loop.launch.py
    ros2 launch wrenchcone_ros closed_loop.launch.py namespace:=cell1 lockstep:=true

Arguments: ``scene_file`` (default: the installed examples/pawl_seating.yaml), ``target``
(the fixels, 1-based, that must touch), ``friction`` ([lo, hi]: the tray samples its
models in it, the node and the controller plan for it), ``contact_tolerance`` (m),
``lockstep``, ``namespace``, ``use_sim_time`` (the node and the controller on the tray's
/clock), ``autostart`` (the node's), ``log_level``. The controller reaches the node of its
own namespace (its ``server`` parameter is relative).
"""

from typing import List  # noqa: UP035 - launch's type_utils reads typing.List

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import LifecycleNode, Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare

PACKAGE = "wrenchcone_ros"


def _value(name: str, value_type: type) -> ParameterValue:
    return ParameterValue(LaunchConfiguration(name), value_type=value_type)


def generate_launch_description() -> LaunchDescription:
    log = ["--log-level", LaunchConfiguration("log_level")]
    ns = LaunchConfiguration("namespace")
    scene = LaunchConfiguration("scene_file")
    sim_time = _value("use_sim_time", bool)
    lockstep = _value("lockstep", bool)
    friction = _value("friction", List[float])
    return LaunchDescription([
        DeclareLaunchArgument(
            "scene_file",
            default_value=PathJoinSubstitution(
                [FindPackageShare(PACKAGE), "examples", "pawl_seating.yaml"]),
            description="the scene: workpiece, fixels, start pose (YAML)"),
        DeclareLaunchArgument("target", default_value="[1, 2, 3]",
                              description="fixels (1-based) the part must touch"),
        DeclareLaunchArgument("friction", default_value="[0.2, 0.4]",
                              description="friction interval [lo, hi] of every fixel"),
        DeclareLaunchArgument("contact_tolerance", default_value="8.35e-6",
                              description="the node's contact tolerance (m)"),
        DeclareLaunchArgument("lockstep", default_value="false",
                              description="the tray waits for the controller's answer"),
        DeclareLaunchArgument("namespace", default_value="",
                              description="namespace of the three nodes"),
        DeclareLaunchArgument("use_sim_time", default_value="false",
                              description="the node and the controller on the tray's /clock"),
        DeclareLaunchArgument("autostart", default_value="true",
                              description="the wrenchcone node configures and activates "
                                          "itself at start"),
        DeclareLaunchArgument("log_level", default_value="info",
                              description="debug, info, warn, error or fatal"),
        LifecycleNode(
            package=PACKAGE, executable="wrenchcone_node", name="wrenchcone", namespace=ns,
            parameters=[{"scene_file": scene,
                         "contact_tolerance": _value("contact_tolerance", float),
                         "uncertainty.friction": friction,
                         "use_sim_time": sim_time,
                         "autostart": _value("autostart", bool)}],
            ros_arguments=log, output="screen"),
        Node(
            package=PACKAGE, executable="tray_sim", name="tray_sim", namespace=ns,
            parameters=[{"scene_file": scene, "friction": friction, "lockstep": lockstep}],
            ros_arguments=log, output="screen"),
        Node(
            package=PACKAGE, executable="tilt_controller", name="tilt_controller",
            namespace=ns,
            parameters=[{"target": _value("target", List[int]), "friction": friction,
                         "lockstep": lockstep, "use_sim_time": sim_time}],
            ros_arguments=log, output="screen"),
    ])
