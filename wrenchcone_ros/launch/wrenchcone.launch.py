# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Start the wrenchcone node, a managed (lifecycle) node, with a parameters file.

    ros2 launch wrenchcone_ros wrenchcone.launch.py
    ros2 launch wrenchcone_ros wrenchcone.launch.py params_file:=/path/my.yaml namespace:=cell1
    ros2 launch wrenchcone_ros wrenchcone.launch.py autostart:=false   # for a lifecycle manager

Arguments: ``params_file``, ``namespace``, ``use_sim_time``, ``autostart`` (the node's
parameter: true configures and activates it at start; false leaves it unconfigured for
a lifecycle manager, e.g. nav2's, docs/node.md "Lifecycle"), ``log_level``. The values
given here override the parameters file's. For a ROS 2 installation with the launch
packages (/opt/ros/jazzy); the PyPI wheels this repository's Makefile uses have no
`launch`, so there use `make run` (docs/node.md).
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import LifecycleNode
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare


def generate_launch_description() -> LaunchDescription:
    return LaunchDescription([
        DeclareLaunchArgument(
            "params_file",
            default_value=PathJoinSubstitution(
                [FindPackageShare("wrenchcone_ros"), "config", "wrenchcone.yaml"]),
            description="node parameters (YAML); every parameter is listed in the default"),
        DeclareLaunchArgument("namespace", default_value="",
                              description="namespace of the node and its topics"),
        DeclareLaunchArgument("use_sim_time", default_value="false",
                              description="use /clock (simulation time) for the node clock"),
        DeclareLaunchArgument("autostart", default_value="true",
                              description="configure and activate at start; false: stay "
                                          "unconfigured for a lifecycle manager"),
        DeclareLaunchArgument("log_level", default_value="info",
                              description="debug, info, warn, error or fatal"),
        LifecycleNode(
            package="wrenchcone_ros",
            executable="wrenchcone_node",
            name="wrenchcone",
            namespace=LaunchConfiguration("namespace"),
            parameters=[
                LaunchConfiguration("params_file"),
                {"use_sim_time": ParameterValue(LaunchConfiguration("use_sim_time"),
                                                value_type=bool),
                 "autostart": ParameterValue(LaunchConfiguration("autostart"),
                                             value_type=bool)},
            ],
            ros_arguments=["--log-level", LaunchConfiguration("log_level")],
            output="screen",
        ),
    ])
