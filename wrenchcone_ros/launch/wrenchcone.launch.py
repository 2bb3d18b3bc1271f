# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Start the wrenchcone node with a parameters file.

    ros2 launch wrenchcone_ros wrenchcone.launch.py
    ros2 launch wrenchcone_ros wrenchcone.launch.py params_file:=/path/my.yaml namespace:=cell1

For a ROS 2 installation with the launch packages (/opt/ros/jazzy); the PyPI wheels this
repository's Makefile uses have no `launch`, so there use `make run` (docs/node.md).
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
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
        Node(
            package="wrenchcone_ros",
            executable="wrenchcone_node",
            name="wrenchcone",
            namespace=LaunchConfiguration("namespace"),
            parameters=[LaunchConfiguration("params_file")],
            output="screen",
        ),
    ])
