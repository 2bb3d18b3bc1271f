# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Packaging facts that drift silently: one version everywhere (the node package, the
Python package, CHANGELOG) and one interface version (wrenchcone_msgs' package.xml, the
INTERFACE_VERSION of Status.msg, wrenchcone_ros's dependency on it), every imported dependency declared in package.xml by a rosdep key,
the pip-only keys defined in the shipped rosdep rule file, the licence file matching
package.xml, and each package.xml carrying the elements a release needs.

The package.xml files are not validated against the format-3 XSD here: ament_xmllint
has no wheel, and the schema is online only. CMakeLists.txt runs ament_xmllint where
it is installed (a ROS installation)."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
import yaml

import wrenchcone_ros

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "wrenchcone_ros"  # the ROS package wrenchcone_ros (package.xml, setup.py)
MSGS = ROOT / "wrenchcone_msgs"
PACKAGE = ET.parse(PKG / "package.xml").getroot()
PACKAGES = {"wrenchcone_ros": PACKAGE,
            "wrenchcone_msgs": ET.parse(MSGS / "package.xml").getroot()}
ROSDEP_RULES = yaml.safe_load((PKG / "rosdep.yaml").read_text())
#: Top-level import -> the package.xml keys that provide it.
IMPORT_KEYS = {
    "rclpy": ["rclpy"], "rcl_interfaces": ["rcl_interfaces"],
    "builtin_interfaces": ["builtin_interfaces"], "geometry_msgs": ["geometry_msgs"],
    "std_msgs": ["std_msgs"], "std_srvs": ["std_srvs"], "action_msgs": ["action_msgs"],
    "lifecycle_msgs": ["lifecycle_msgs"], "wrenchcone_msgs": ["wrenchcone_msgs"],
    "visualization_msgs": ["visualization_msgs"], "diagnostic_msgs": ["diagnostic_msgs"],
    "numpy": ["python3-numpy"], "scipy": ["python3-scipy"], "yaml": ["python3-yaml"],
    # pycddlib: pip only (rosdep.yaml), built against cddlib and GMP
    "cdd": ["python3-pycddlib-pip", "libcdd-dev", "libgmp"],
    "launch": ["launch"], "launch_ros": ["launch_ros"],
    "setuptools": [],  # setup.py: the pip path only, not the ROS package's
    # wrenchcone_ros.testing, the pytest plugin: loaded by pytest, in a user's tests
    "pytest": ["python3-pytest"],
    # the closed loop (wrenchcone_ros.sim)
    "rosgraph_msgs": ["rosgraph_msgs"], "ament_index_python": ["ament_index_python"],
}
#: Top-level import -> the setup.py extra that installs it: optional capabilities, never a
#: key of package.xml (the node runs without them; each says what to install when missing).
OPTIONAL_IMPORTS = {"numba": "install_requires",  # the compiled kernel (else numpy's engine)
                    "pymunk": "sim", "dask": "design", "distributed": "design",
                    "pyarrow": "design", "tqdm": "design", "rosbags": "replay",
                    "matplotlib": "plot"}
#: The pip distribution each *-pip key installs (setup.py's install_requires).
PIP_DISTRIBUTIONS = {"python3-pycddlib-pip": "pycddlib"}
DEPEND_TAGS = ("depend", "exec_depend", "build_depend", "build_export_depend",
               "buildtool_depend", "test_depend")


def _declared(package: ET.Element = PACKAGE, tags: tuple[str, ...] = DEPEND_TAGS) -> set[str]:
    return {e.text.strip() for t in tags for e in package.iter(t)}


def _imports(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def _changelog_newest() -> str:
    """The newest version heading of CHANGELOG.rst: ``X.Y.Z (date)`` or ``(unreleased)``."""
    text = (ROOT / "CHANGELOG.rst").read_text()
    releases = re.findall(r"^(\d+\.\d+\.\d+) \((?:\d{4}-\d\d-\d\d|unreleased)\)\n-+$",
                          text, re.M)
    assert releases, "CHANGELOG.rst has no 'X.Y.Z (YYYY-MM-DD)' or 'X.Y.Z (unreleased)' heading"
    return releases[0]


def test_one_version_everywhere():
    version = wrenchcone_ros.__version__
    assert re.fullmatch(r"\d+\.\d+\.\d+", version)
    assert PACKAGE.findtext("version") == version
    assert _changelog_newest() == version
    out = subprocess.run([sys.executable, "setup.py", "--version"], cwd=PKG,
                         capture_output=True, text=True)
    assert out.stdout.strip().splitlines()[-1] == version, out.stderr


def test_one_interface_version():
    """wrenchcone_msgs' version is the interface version: Status.msg's INTERFACE_VERSION
    says it, and the node package requires at least it."""
    version = PACKAGES["wrenchcone_msgs"].findtext("version")
    assert re.fullmatch(r"\d+\.\d+\.\d+", version)
    status = (MSGS / "msg" / "Status.msg").read_text()
    assert re.findall(r'^string INTERFACE_VERSION="([^"]*)"', status, re.M) == [version]
    [dep] = [e for e in PACKAGE.iter("depend") if e.text.strip() == "wrenchcone_msgs"]
    assert dep.get("version_gte") == version
    # the interfaces are never older than the node package that speaks them
    assert tuple(map(int, version.split("."))) >= tuple(
        map(int, wrenchcone_ros.__version__.split(".")))


@pytest.mark.parametrize("name", sorted(PACKAGES))
def test_package_xml_has_what_a_release_needs(name):
    package = PACKAGES[name]
    assert package.get("format") == "3"
    assert package.findtext("name") == name
    assert (ROOT / name / "package.xml").is_file()
    assert package.findtext("description").strip()
    maintainers = package.findall("maintainer")
    assert maintainers and all(m.get("email") and m.text.strip() for m in maintainers)
    assert package.findtext("license") == "MIT"
    urls = {u.get("type"): u.text.strip() for u in package.findall("url")}
    assert urls.get("repository") == "https://github.com/wrenchcone/wrenchcone_ros", urls
    assert package.find("export/build_type").text == "ament_cmake"
    assert "ament_cmake" in _declared(package, ("buildtool_depend",))
    # format 3's element order (the XSD's sequence): name, version, description,
    # maintainer, license, url, author, then the dependencies, then export
    order = ["name", "version", "description", "maintainer", "license", "url", "author"]
    seen = [c.tag for c in package if isinstance(c.tag, str) and c.tag in order]
    assert seen == sorted(seen, key=order.index), seen
    assert [c.tag for c in package if isinstance(c.tag, str)][-1] == "export"


def test_interface_package_is_a_rosidl_package():
    msgs = PACKAGES["wrenchcone_msgs"]
    assert msgs.findtext("member_of_group") == "rosidl_interface_packages"
    assert "rosidl_default_generators" in _declared(msgs, ("buildtool_depend",))
    assert "rosidl_default_runtime" in _declared(msgs, ("exec_depend",))
    # what the interfaces use: every package named in a .msg/.srv/.action is declared
    used = set()
    for path in [*MSGS.glob("msg/*.msg"), *MSGS.glob("srv/*.srv"), *MSGS.glob("action/*.action")]:
        used |= set(re.findall(r"^\s*([a-z][a-z0-9_]*)/[A-Z]\w*", path.read_text(), re.M))
    assert used, "no field type found"
    assert used - {"wrenchcone_msgs"} <= _declared(msgs), used


#: The sample user package (a package of its own inside wrenchcone_ros/examples/).
SAMPLE = PKG / "examples" / "my_tilt_controller"


@pytest.mark.slow
def test_every_imported_package_is_declared():
    files = [p for p in PKG.rglob("*.py") if ".egg-info" not in str(p)
             and SAMPLE not in p.parents]
    assert len(files) > 10 and PKG / "launch" / "wrenchcone.launch.py" in files
    stdlib = set(sys.stdlib_module_names) | {"wrenchcone_ros", "__future__"}
    declared = _declared()
    for path in files:
        for name in sorted(_imports(path) - stdlib):
            if name in OPTIONAL_IMPORTS:
                continue  # test_optional_capabilities_are_extras_not_keys
            keys = IMPORT_KEYS.get(name)
            assert keys is not None, f"{path.relative_to(ROOT)} imports {name!r}: add " \
                                     "its key to package.xml (and to IMPORT_KEYS here)"
            missing = [k for k in keys if k not in declared]
            assert not missing, f"{path.relative_to(ROOT)} imports {name!r}; package.xml " \
                                f"lacks {missing}"


def test_the_sample_package_declares_what_it_imports():
    package = ET.parse(SAMPLE / "package.xml").getroot()
    assert package.findtext("name") == "my_tilt_controller"
    assert package.find("export/build_type").text == "ament_python"
    declared = _declared(package)
    assert "wrenchcone_ros" in _declared(package, ("test_depend",))  # the pytest kit
    for path in SAMPLE.rglob("*.py"):
        for name in sorted(_imports(path) - set(sys.stdlib_module_names)
                           - {"my_tilt_controller"}):
            keys = IMPORT_KEYS[name]
            assert set(keys) <= declared, f"{path.relative_to(ROOT)} imports {name!r}"


def test_compiled_programs_dependencies_are_declared():
    # src/*.c include the headers of these packages; CMakeLists.txt finds them
    cmake = (PKG / "CMakeLists.txt").read_text()
    headers = set()
    for path in PKG.glob("src/*.c"):
        headers |= set(re.findall(r'^#include [<"]([a-z_]+)/', path.read_text(), re.M))
    assert headers, "no ROS header included by src/*.c"
    build = _declared(PACKAGE, ("depend", "build_depend"))
    for name in headers:
        assert name in build, f"src/ includes {name}/ headers; package.xml lacks it"
        assert re.search(rf"find_package\({name}\b", cmake), f"CMakeLists.txt: {name}"
    # rcl includes rmw's and rcutils' headers: direct build dependencies too
    assert {"rcl", "rmw", "rcutils", "rosidl_runtime_c", "python3-dev"} <= build


def test_pip_keys_are_defined_by_the_shipped_rosdep_rules():
    # rosdep's own reading of the rule file: each key of package.xml ending in -pip
    # resolves, on Ubuntu noble and Debian bookworm, to rosdep's pip installer and the
    # distribution setup.py names
    from rosdep2.lookup import RosdepDefinition
    from rosdep2.platforms.pip import PipInstaller

    pip_keys = {k for k in _declared() if k.endswith("-pip")}
    assert pip_keys == set(PIP_DISTRIBUTIONS), pip_keys
    assert set(ROSDEP_RULES) == pip_keys, "rosdep.yaml defines keys package.xml lacks"
    setup_py = (PKG / "setup.py").read_text()
    for key in pip_keys:
        definition = RosdepDefinition(key, ROSDEP_RULES[key], "rosdep.yaml")
        for os_name, os_version in (("ubuntu", "noble"), ("debian", "bookworm")):
            installer, rule = definition.get_rule_for_platform(
                os_name, os_version, ["apt", "pip"], "apt")
            assert installer == "pip", (key, os_name)
            assert PipInstaller().resolve(rule) == [PIP_DISTRIBUTIONS[key]], (key, os_name)
        assert f'"{PIP_DISTRIBUTIONS[key]}' in setup_py, key  # the same distribution


def test_ament_flake8_checks_the_rule_classes_of_ruff():
    # CMakeLists.txt's ament_flake8 configuration against pyproject.toml's ruff settings:
    # the same rule classes (bugbear's B only in ruff: no flake8 plugin in ament), the
    # same line length
    import configparser
    import tomllib

    ruff = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["ruff"]
    flake8 = configparser.ConfigParser()
    flake8.read(PKG / "ament_flake8.ini")
    selected = {s.strip() for s in flake8["flake8"]["select"].split(",")}
    assert selected == set(ruff["lint"]["select"]) - {"B"}, selected
    assert int(flake8["flake8"]["max-line-length"]) == ruff["line-length"]
    assert 'ament_flake8(CONFIG_FILE "${CMAKE_CURRENT_SOURCE_DIR}/ament_flake8.ini")' in \
        (PKG / "CMakeLists.txt").read_text()


def test_warnings_are_errors_only_in_the_developers_build():
    cmake = (PKG / "CMakeLists.txt").read_text()
    guarded = re.findall(r"^if\(WRENCHCONE_WERROR\)\n(.*?)^endif\(\)", cmake, re.M | re.S)
    assert cmake.count("-Werror") == sum(g.count("-Werror") for g in guarded) >= 1
    assert re.search(r'option\(WRENCHCONE_WERROR "[^"]+" OFF\)', cmake)


def test_optional_capabilities_are_extras_not_keys():
    # no rosdep key for an optional capability (bloom releases no pip key, and a node
    # user should not pay for the planner's engine, the design cluster or bags): each is
    # a setup.py extra, and package.xml's comment names it
    call = next(n for n in ast.walk(ast.parse((PKG / "setup.py").read_text()))
                if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "setup")
    kw = {k.arg: k.value for k in call.keywords}
    requires = [re.split(r"[<>=\[]", r)[0] for r in ast.literal_eval(kw["install_requires"])]
    extras = {name: [re.split(r"[<>=\[]", r)[0] for r in reqs]
              for name, reqs in ast.literal_eval(kw["extras_require"]).items()}
    text = (PKG / "package.xml").read_text()
    comment = text[text.index("<!-- Not declared"):]
    comment = comment[:comment.index("-->")]
    declared = " ".join(_declared())
    for module, extra in OPTIONAL_IMPORTS.items():
        distribution = {"distributed": "dask"}.get(module, module)
        assert distribution not in declared, f"package.xml names {distribution}"
        where = requires if extra == "install_requires" else extras[extra]
        assert distribution in where, (module, extra)
        assert distribution in comment, f"package.xml's comment does not name {module}"


def test_licence_file_matches_package_xml():
    assert PACKAGE.findtext("license") == "MIT"
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
