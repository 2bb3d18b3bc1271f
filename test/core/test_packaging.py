"""Packaging facts that drift silently: one version everywhere, every imported
dependency declared in package.xml, the licence file matching package.xml."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import wrenchcone_ros

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ET.parse(ROOT / "package.xml").getroot()
#: Top-level import -> the package.xml keys that provide it.
IMPORT_KEYS = {
    "rclpy": ["rclpy"], "rcl_interfaces": ["rcl_interfaces"],
    "builtin_interfaces": ["builtin_interfaces"], "geometry_msgs": ["geometry_msgs"],
    "std_msgs": ["std_msgs"], "std_srvs": ["std_srvs"],
    "visualization_msgs": ["visualization_msgs"], "diagnostic_msgs": ["diagnostic_msgs"],
    "numpy": ["python3-numpy"], "scipy": ["python3-scipy"], "yaml": ["python3-yaml"],
    "matplotlib": ["python3-matplotlib"], "tqdm": ["python3-tqdm"],  # wrenchcone plan's bar
    "cdd": ["libcdd-dev", "libgmp"],  # pycddlib (no rosdep key), built against both
    "launch": ["launch"], "launch_ros": ["launch_ros"],
    # optional, pip-only: the compiled kernel; package.xml says so in a comment (checked)
    "numba": [],
    # optional, pip-only: the physics engine of plans (core/simulate.py)
    "pymunk": [],
    # optional, pip-only: the fixture design's engine and output (wrenchcone_ros/design)
    "dask": [], "distributed": [], "pyarrow": [],
}


def _declared() -> set[str]:
    tags = ("depend", "exec_depend", "build_depend", "buildtool_depend", "test_depend")
    return {e.text.strip() for t in tags for e in PACKAGE.iter(t)}


def _imports(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def test_one_version_everywhere():
    version = wrenchcone_ros.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", version)
    assert PACKAGE.findtext("version") == version
    changelog = (ROOT / "CHANGELOG.rst").read_text()
    releases = re.findall(r"^(\d+\.\d+\.\d+) \(\d{4}-\d\d-\d\d\)\n-+$", changelog, re.M)
    assert releases and releases[0] == version, releases
    out = subprocess.run([sys.executable, "setup.py", "--version"], cwd=ROOT,
                         capture_output=True, text=True)
    assert out.stdout.strip().splitlines()[-1] == version, out.stderr


def test_every_imported_package_is_declared():
    files = [*ROOT.glob("wrenchcone_ros/**/*.py"), *ROOT.glob("launch/*.py")]
    assert len(files) > 10
    stdlib = set(sys.stdlib_module_names) | {"wrenchcone_ros", "__future__"}
    declared = _declared()
    for path in files:
        for name in sorted(_imports(path) - stdlib):
            keys = IMPORT_KEYS.get(name)
            assert keys is not None, f"{path.relative_to(ROOT)} imports {name!r}: add " \
                                     "its key to package.xml (and to IMPORT_KEYS here)"
            if not keys:  # optional and pip-only: package.xml must say how to get it
                assert f"`pip install {name}`" in (ROOT / "package.xml").read_text(), name
            missing = [k for k in keys if k not in declared]
            assert not missing, f"{path.relative_to(ROOT)} imports {name!r}; package.xml " \
                                f"lacks {missing}"


def test_licence_file_matches_package_xml():
    assert PACKAGE.findtext("license") == "MIT"
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_launch_file_starts_the_installed_executable_with_the_config():
    # The launch file cannot run here (no launch packages in the wheels): check what it
    # names against what CMake installs.
    text = (ROOT / "launch" / "wrenchcone.launch.py").read_text()
    cmake = (ROOT / "CMakeLists.txt").read_text()
    assert 'executable="wrenchcone_node"' in text and "wrenchcone_node" in cmake
    assert '"config", "wrenchcone.yaml"' in text and (ROOT / "config/wrenchcone.yaml").is_file()
    assert re.search(r"install\(DIRECTORY examples launch config DESTINATION share", cmake)
