# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""rosdep can install the packages: every dependency key of both package.xml files is a
Jazzy package or a rosdep key of rosdistro (a stored excerpt, test/packaging/data/), but
for the one key rosdistro lacks, which the shipped rosdep.yaml defines; and the node runs
with only what package.xml declares (the optional capabilities blocked), each missing
capability saying what to install."""

from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
EXCERPT = yaml.safe_load((Path(__file__).parent / "data" / "rosdistro_excerpt.yaml")
                         .read_text())
OWN_RULES = yaml.safe_load((ROOT / "wrenchcone_ros" / "rosdep.yaml").read_text())
DEPEND_TAGS = ("depend", "exec_depend", "build_depend", "build_export_depend",
               "buildtool_depend", "test_depend")
#: The optional capabilities (test_packaging.OPTIONAL_IMPORTS): blocked below.
OPTIONAL = ("numba", "pymunk", "dask", "distributed", "pyarrow", "rosbags", "matplotlib",
            "tqdm")


def _keys(package: str) -> set[str]:
    root = ET.parse(ROOT / package / "package.xml").getroot()
    return {e.text.strip() for t in DEPEND_TAGS for e in root.iter(t)}


def test_every_key_resolves_in_rosdistro_but_the_one_the_package_defines():
    own = {"wrenchcone_msgs"}
    unresolved = {}
    for package in ("wrenchcone_ros", "wrenchcone_msgs"):
        for key in sorted(_keys(package) - own):
            if key not in EXCERPT["rosdep"] and key not in EXCERPT["jazzy_packages"]:
                unresolved.setdefault(key, package)
    # exactly the keys the shipped rule file defines, and one only (pycddlib)
    assert set(unresolved) == set(OWN_RULES) == {"python3-pycddlib-pip"}, unresolved


def test_the_system_keys_resolve_on_ubuntu_noble_with_rosdeps_own_reading():
    from rosdep2.lookup import RosdepDefinition

    keys = (_keys("wrenchcone_ros") | _keys("wrenchcone_msgs")) & set(EXCERPT["rosdep"])
    assert {"python3-numpy", "python3-scipy", "python3-yaml", "libcdd-dev"} <= keys
    for key in sorted(keys):
        definition = RosdepDefinition(key, EXCERPT["rosdep"][key], "rosdistro")
        installer, rule = definition.get_rule_for_platform("ubuntu", "noble",
                                                           ["apt", "pip"], "apt")
        assert installer == "apt" and rule, (key, installer, rule)
    for key, rule in OWN_RULES.items():
        definition = RosdepDefinition(key, rule, "rosdep.yaml")
        installer, _ = definition.get_rule_for_platform("ubuntu", "noble", ["apt", "pip"],
                                                        "apt")
        assert installer == "pip", key


def blocked(modules) -> str:
    """Python that makes every import of ``modules`` fail, as on a machine without them."""
    return f"""
import importlib.abc, sys
class Blocker(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in {tuple(modules)!r}:
            raise ImportError(f"No module named {{name!r}}")
sys.meta_path.insert(0, Blocker())
"""


NODE = blocked(OPTIONAL) + """
import warnings
import wrenchcone_ros.node.wrenchcone_node  # noqa: F401  the node's whole import tree
from wrenchcone_ros.core import default_scene, load_scene, wrench_cones
from wrenchcone_ros.core.engines import resolve_engine
from wrenchcone_ros.core.plan import plan_seating
with warnings.catch_warnings(record=True) as said:
    warnings.simplefilter("always")
    n = len(wrench_cones(default_scene(), ["na", "la", "ss"]))
print("CONES", n, resolve_engine())
print("WARNED", [str(w.message) for w in said])
try:
    plan_seating(load_scene(sys.argv[1]), [1, 2, 3])
except Exception as exc:
    print("PLAN", type(exc).__name__, exc)
"""


def test_the_node_runs_with_only_what_package_xml_declares():
    # the default engine (the kernel, then numpy's), whatever this run chose
    env = {k: v for k, v in os.environ.items() if k != "WRENCHCONE_ENGINE"}
    out = subprocess.run([sys.executable, "-c", NODE,
                          str(ROOT / "examples" / "pawl_seating.yaml")],
                         capture_output=True, text=True, timeout=300, env=env)
    assert out.returncode == 0, out.stderr
    assert "CONES 3 numpy" in out.stdout, out.stdout
    assert "compiled kernel unavailable" in out.stdout and "pip install" in out.stdout
    assert "PLAN SimulationUnavailable" in out.stdout and "pip install" in out.stdout, \
        out.stdout


def test_each_missing_capability_says_what_to_install(tmp_path):
    cli = "from wrenchcone_ros.cli import main\nsys.exit(main(sys.argv[1:]))\n"
    ex = ROOT / "examples"
    cases = {"pymunk": ["plan", str(ex / "pawl_seating.yaml"), "--target", "1", "2", "3"],
             "pyarrow": ["design", str(ex / "pawl_seating.yaml"), "--plate",
                         str(ex / "plates" / "plate_10mm.yaml"), "--workers", "0",
                         "--out", str(tmp_path / "d.parquet")],
             "rosbags": ["replay", str(tmp_path), "--mode", "na"],
             "matplotlib": ["plot", str(ex / "paper_disc.yaml"), "--mode", "na", "--out",
                            str(tmp_path / "x.png")]}
    for name, args in cases.items():
        out = subprocess.run([sys.executable, "-c", blocked([name]) + cli, *args],
                             capture_output=True,
                             text=True, timeout=300)
        lines = out.stderr.strip().splitlines()
        assert out.returncode == 2 and len(lines) == 1, (name, out.stderr)
        assert "pip install" in lines[0], (name, lines[0])
