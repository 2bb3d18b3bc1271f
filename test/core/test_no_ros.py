# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The core must import and work where rclpy (and every ROS package) is absent."""

import subprocess
import sys

import pytest

CODE = r"""
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        root = name.split('.')[0]
        if root in ('rclpy', 'rosidl_runtime_py', 'geometry_msgs', 'std_msgs', 'rclpy_message'):
            raise ImportError('blocked for this test: ' + name)
        if name == 'wrenchcone_msgs.srv' or name.startswith('wrenchcone_msgs.srv.'):
            raise ImportError('blocked for this test: ' + name)
sys.meta_path.insert(0, Block())
for mod in list(sys.modules):
    if mod.startswith('rclpy'):
        del sys.modules[mod]
from wrenchcone_ros.core import default_scene, wrench_cone
import wrenchcone_ros.core.drawing, wrenchcone_ros.core.plot  # noqa: E401 - no matplotlib yet
assert not any(m.startswith('matplotlib') for m in sys.modules), 'core imported matplotlib'
from wrenchcone_ros import cli, __version__
cone = wrench_cone(default_scene(), 'na')
assert cone.contains((1.0, -1.0, -1.0))
assert cli.main(['check', 'default', '--mode', 'na', '--wrench', '1', '0', '-1']) == 0
try:
    import rclpy  # noqa
except ImportError:
    print('RCLPY_ABSENT')
assert not any(m.startswith('rclpy') for m in sys.modules), 'core imported rclpy'
"""


@pytest.mark.slow
def test_core_and_cli_work_without_rclpy():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "RCLPY_ABSENT" in out.stdout
