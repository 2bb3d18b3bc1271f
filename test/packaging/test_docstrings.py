# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Every public name has a numpy-style docstring, and the API reference lists every
public module.

The public API is the modules of ``PUBLIC_MODULES`` (each one has an ``automodule`` page
in docs/api, which ``make docs`` builds): of each, the names of its ``__all__`` or, without
one, the functions and classes it defines whose names do not start with ``_``; of each
public class, the methods and properties it defines itself. Each is checked by numpydoc's
validator (``numpydoc.validate``) with the checks of ``CHECKS``: a docstring with a
one-line summary; for a function or method with parameters, a ``Parameters`` section
naming exactly the signature's parameters (``self`` / ``cls`` aside) in its order; a
``Returns`` (or ``Yields``) section when the function returns a value (a return
annotation other than ``None``, or a ``return`` with a value in its body); a ``Raises``
section naming every exception class the body raises by name (outside a ``try`` block;
what its callees raise is not traced); sections numpydoc knows, in numpydoc's order. A class is checked against its constructor (a
dataclass's fields are its parameters) when the package defines that constructor.

Names that are not functions or classes (constants, mode tables, status codes) carry no
docstring of their own: they are documented by a ``#:`` comment, which autodoc shows.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import re
import textwrap
from pathlib import Path

import numpydoc.validate as numpydoc_validate
import pytest


ROOT = Path(__file__).resolve().parents[2]
DOCS_API = ROOT / "docs" / "api"
PACKAGE = "wrenchcone_ros"

#: The public modules. The core, the planner (``core.plan``: its ``__all__`` covers its
#: submodules), fixture design, recorded-run replay, the CLI's entry point, and the ROS
#: side (conversions, the client, the node, the closed loop's programs and the test kit),
#: which need the colcon install tree sourced.
PUBLIC_MODULES = (
    "wrenchcone_ros.core",
    "wrenchcone_ros.core.geometry",
    "wrenchcone_ros.core.scene",
    "wrenchcone_ros.core.scene_yaml",
    "wrenchcone_ros.core.modes",
    "wrenchcone_ros.core.dynamics",
    "wrenchcone_ros.core.constraints",
    "wrenchcone_ros.core.paper",
    "wrenchcone_ros.core.planar",
    "wrenchcone_ros.core.cones",
    "wrenchcone_ros.core.cone3d",
    "wrenchcone_ros.core.wrenchset",
    "wrenchcone_ros.core.engines",
    "wrenchcone_ros.core.batch",
    "wrenchcone_ros.core.uncertainty",
    "wrenchcone_ros.core.robust",
    "wrenchcone_ros.core.classify",
    "wrenchcone_ros.core.directions",
    "wrenchcone_ros.core.regions",
    "wrenchcone_ros.core.sweeps",
    "wrenchcone_ros.core.tilt",
    "wrenchcone_ros.core.tolerances",
    "wrenchcone_ros.core.numbers",
    "wrenchcone_ros.core.stats",
    "wrenchcone_ros.core.budget",
    "wrenchcone_ros.core.lp_check",
    "wrenchcone_ros.core.drawing",
    "wrenchcone_ros.core.plot",
    "wrenchcone_ros.core.simulate",
    "wrenchcone_ros.core.plan",
    "wrenchcone_ros.core.animate",
    "wrenchcone_ros.design",
    "wrenchcone_ros.design.problem",
    "wrenchcone_ros.design.geometry",
    "wrenchcone_ros.design.enumerate",
    "wrenchcone_ros.design.stages",
    "wrenchcone_ros.design.rank",
    "wrenchcone_ros.design.pipeline",
    "wrenchcone_ros.design.plot",
    "wrenchcone_ros.replay",
    "wrenchcone_ros.replay.bag",
    "wrenchcone_ros.replay.analysis",
    "wrenchcone_ros.cli",
    "wrenchcone_ros.ros",
    "wrenchcone_ros.ros.conversions",
    "wrenchcone_ros.ros.client",
    "wrenchcone_ros.ros.environment",
    "wrenchcone_ros.ros.qos",
    "wrenchcone_ros.ros.contexts",
    "wrenchcone_ros.ros.spinning",
    "wrenchcone_ros.ros.domains",
    "wrenchcone_ros.node",
    "wrenchcone_ros.node.inprocess",
    "wrenchcone_ros.sim",
    "wrenchcone_ros.sim.tray",
    "wrenchcone_ros.sim.tray_sim",
    "wrenchcone_ros.sim.tilt_controller",
    "wrenchcone_ros.sim.controller_states",
    "wrenchcone_ros.sim.loop",
    "wrenchcone_ros.sim.recorder",
    "wrenchcone_ros.testing",
    "wrenchcone_ros.testing.harness",
    "wrenchcone_ros.testing.domains",
    "wrenchcone_ros.testing.plugin",
)

#: The package's other modules, not part of the public API: what each offers a user is
#: reached through a public module (the node's names through ``wrenchcone_ros.node``, the
#: planner's through ``wrenchcone_ros.core.plan``), a command line or a program.
INTERNAL_MODULES = {
    "wrenchcone_ros": "the version only",
    "wrenchcone_ros.core.kernel": "the compiled kernel: only core.engines.kernel_engine calls it",
    "wrenchcone_ros.core.pymunk_boundary": "pymunk's internals, read by core.simulate only",
    **dict.fromkeys(
        (f"wrenchcone_ros.core.engines.{m}" for m in
         ("kernel_engine", "numpy_engine", "packing", "protocol", "registry")),
        "the engines' modules: their names are wrenchcone_ros.core.engines'"),
    "wrenchcone_ros.sim.program": "the start-up and shutdown the two sim programs share",
    **dict.fromkeys(
        (f"wrenchcone_ros.core.plan.{m}" for m in
         ("execution", "poses", "region", "region_cones", "results", "search", "segment_funnels",
          "segments")),
        "the planner's modules: their names are wrenchcone_ros.core.plan's"),
    **dict.fromkeys(
        (f"wrenchcone_ros.cli.{m}" for m in
         ("check", "classify", "cone", "design", "directions", "options", "plan", "plot",
          "render", "replay", "sweep", "uncertain")),
        "a subcommand of the wrenchcone command line (wrenchcone --help)"),
    **dict.fromkeys(
        (f"wrenchcone_ros.node.{m}" for m in
         ("answers", "diagnostics", "executors", "freshness", "inputs", "lane", "markers",
          "parameter_files", "parameters", "plan_action", "publishers", "rclpy_boundary",
          "services", "status", "store", "worker", "wrenchcone_node")),
        "the node's modules: their public names are wrenchcone_ros.node's"),
}

#: numpydoc's checks that every public name must pass (numpydoc.validate.ERROR_MSGS):
#: GL08 no docstring; SS01 no summary; GL06 an unknown section; GL07 sections out of
#: numpydoc's order; PR01 a parameter not documented; PR02 a documented parameter that
#: the signature does not have; PR03 parameters out of the signature's order; RT01 no
#: Returns section for a function that returns a value; YD01 no Yields section for a
#: generator. RT01 is also given, here, to a function whose return annotation is not
#: ``None`` (numpydoc reads only the ``return`` statements). RS01 is this test's own: an
#: exception class the body raises by name (outside a ``try`` block) that the Raises
#: section does not name.
CHECKS = frozenset({"GL08", "SS01", "GL06", "GL07", "PR01", "PR02", "PR03", "RT01", "YD01",
                    "RS01"})

#: Modules that import ROS (they need ``source install/setup.bash``).
_ROS_PREFIXES = ("wrenchcone_ros.ros", "wrenchcone_ros.node", "wrenchcone_ros.sim",
                 "wrenchcone_ros.testing",
    "wrenchcone_ros.testing.harness", "wrenchcone_ros.testing.plugin")


def _import(name: str):
    try:
        return importlib.import_module(name)
    except (ImportError, SystemExit) as exc:  # ros/: exit 2 without the ROS environment
        if name.startswith(_ROS_PREFIXES):
            pytest.skip(f"{name} needs the ROS environment (source install/setup.bash): {exc}")
        raise


def _own(obj) -> bool:
    return (getattr(obj, "__module__", None) or "").split(".")[0] == PACKAGE


def _public_names(module) -> list[str]:
    names = getattr(module, "__all__", None)
    if names is not None:
        return list(names)
    return [n for n, v in vars(module).items() if not n.startswith("_")
            and (inspect.isfunction(v) or inspect.isclass(v))
            and getattr(v, "__module__", None) == module.__name__]


def _interfaces(cls) -> list[type]:
    """The package's classes ``cls`` inherits from, and the protocols (``typing.Protocol``)
    of its module that it implements, whose methods document ``cls``'s."""
    protocols = [p for p in vars(inspect.getmodule(cls)).values() if inspect.isclass(p)
                 and getattr(p, "_is_protocol", False) and _own(p) and p is not cls]
    return [c for c in cls.__mro__[1:] if _own(c)] + protocols


def _documented_elsewhere(cls, name: str, value) -> bool:
    """``value`` has no docstring of its own and implements a documented method of an
    interface of ``cls`` (autodoc shows the interface's docstring)."""
    return not getattr(value, "__doc__", None) and any(
        getattr(getattr(base, name, None), "__doc__", None) for base in _interfaces(cls))


def _members(cls) -> list[tuple[str, object]]:
    """The public methods and properties ``cls`` defines itself, by qualified name."""
    out = []
    for name, value in vars(cls).items():
        if name.startswith("_") or _documented_elsewhere(cls, name, value):
            continue
        if isinstance(value, (staticmethod, classmethod)):
            value = value.__func__
        if isinstance(value, property) or (inspect.isfunction(value) and _own(value)):
            out.append((f"{cls.__qualname__}.{name}", getattr(cls, name)
                        if not isinstance(value, property) else value))
    return out


def public_api(modules: tuple[str, ...] = PUBLIC_MODULES) -> dict[str, object]:
    """Every public function, class, method and property of ``modules``, by its defining
    name (``module.qualname``): a name exported by several modules is checked once."""
    api: dict[str, object] = {}
    for module_name in modules:
        module = _import(module_name)
        for name in _public_names(module):
            obj = getattr(module, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)) or not _own(obj):
                continue
            key = f"{obj.__module__}.{obj.__qualname__}"
            if "<locals>" in key:  # made by a function (a decorator): by its public name
                key = f"{module_name}.{name}"
            api[key] = obj
            if inspect.isclass(obj):
                for qualname, member in _members(obj):
                    api[f"{obj.__module__}.{qualname}"] = member
    return api


def _own_constructor(cls) -> bool:
    init = cls.__dict__.get("__init__")
    if init is None:
        init = next((c.__dict__["__init__"] for c in cls.__mro__[1:]
                     if "__init__" in c.__dict__), None)
    return init is not None and inspect.isfunction(init) and _own(init)


def _returns_value(obj) -> bool:
    """Its return annotation says it returns a value (not ``None`` or ``NoReturn``)."""
    if not inspect.isfunction(obj):
        return False
    ann = obj.__annotations__.get("return", inspect.Signature.empty)
    if ann is inspect.Signature.empty:
        return False
    text = ann if isinstance(ann, str) else getattr(ann, "__name__", repr(ann))
    return text not in ("None", "NoReturn", "Never", "NoneType") and ann is not None


def _raised(fn) -> set[str]:
    """The exception classes ``fn``'s own body raises by name (``raise Name(...)`` or
    ``raise module.Name``), outside a ``try`` block (which may catch them) and outside
    nested functions and classes; a re-raise or a raise of a variable is not counted."""
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(fn))).body[0]
    except (OSError, TypeError, SyntaxError, IndexError):
        return set()
    found: set[str] = set()

    def walk(node) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef,
                                  ast.Lambda)):
                continue
            if isinstance(child, ast.Try):
                for part in (*child.handlers, *child.orelse, *child.finalbody):
                    walk(part)
                continue
            if isinstance(child, ast.Raise) and child.exc is not None:
                exc = child.exc.func if isinstance(child.exc, ast.Call) else child.exc
                last = ast.unparse(exc).split(".")[-1]
                if isinstance(exc, (ast.Name, ast.Attribute)) and last[:1].isupper():
                    found.add(last)
            walk(child)

    walk(tree)
    return found


def _undocumented_raises(obj, doc) -> list[str]:
    """RS01 (this test's own check): exceptions the body raises that no entry of the
    Raises section names (a class is checked through its ``__init__`` and
    ``__post_init__``)."""
    if inspect.isclass(obj):
        fns = [obj.__dict__.get(k) for k in ("__init__", "__post_init__")]
        fns = [f for f in fns if inspect.isfunction(f) and _own(f)]
    else:
        fns = [obj] if inspect.isfunction(obj) else []
    raised = set().union(*(_raised(f) for f in fns)) if fns else set()
    named = {word.split(".")[-1] for entry in doc["Raises"]
             for word in re.split(r"[\s,]+", f"{entry.name} {entry.type}") if word}
    return sorted(raised - named)


def problems(name: str, obj) -> list[str]:
    """The failed checks of ``obj``'s docstring, as ``CODE message`` lines."""
    checks = CHECKS
    if isinstance(obj, property):  # a summary; its getter's return is the property
        obj, checks = obj.fget, CHECKS & {"GL08", "SS01", "GL06", "GL07"}
    doc = numpydoc_validate.get_doc_object(obj)
    result = numpydoc_validate.validate(doc)
    errors = [(code, msg) for code, msg in result["errors"] if code in checks]
    if inspect.isclass(obj) and not _own_constructor(obj):
        # the constructor is Exception's, Protocol's, NamedTuple's, Enum's: not ours
        errors = [(c, m) for c, m in errors if c not in ("PR01", "PR02", "PR03")]
    if ("RT01" in checks and result["docstring"] and _returns_value(obj) and not doc["Returns"]
            and not doc["Yields"] and not any(c in ("RT01", "YD01") for c, _ in errors)):
        errors.append(("RT01", "No Returns section found (the return annotation is not None)"))
    if "RS01" in checks and result["docstring"]:
        missing = _undocumented_raises(obj, doc)
        if missing:
            errors.append(("RS01", f"Raises section does not name {', '.join(missing)}"))
    return [f"{code} {msg}" for code, msg in errors]


def test_the_public_api_is_found():
    api = public_api(GROUPS["pure"])
    # the core's own names, a method, a property and a lazily imported name are walked
    for name in ("wrenchcone_ros.core.batch.wrench_cone", "wrenchcone_ros.core.cones.Cone",
                 "wrenchcone_ros.core.cones.Cone.contains",
                 "wrenchcone_ros.core.plan.search.plan_seating"):
        assert name in api, name
    assert len(api) > 150


def test_the_checks_tell_a_numpy_docstring_from_prose():
    def prose(scene, mode: str) -> int:
        """The number of pieces of ``mode``'s cone in ``scene``."""

    def numpy_style(scene, mode: str) -> int:
        """The number of pieces of ``mode``'s cone.

        Parameters
        ----------
        scene : Scene
            The scene.
        mode : str
            A mode, wildcards allowed.

        Returns
        -------
        int
            The number of pieces.
        """

    def misnamed(scene, mode: str) -> None:
        """Nothing.

        Parameters
        ----------
        scene : Scene
            The scene.
        modes : str
            Not a parameter of the signature.
        """

    def raising(mode: str) -> None:
        """Refuse ``mode``.

        Parameters
        ----------
        mode : str
            A mode.
        """
        if mode:
            raise ValueError(mode)

    def caught(mode: str) -> None:
        """Refuse ``mode`` quietly.

        Parameters
        ----------
        mode : str
            A mode.
        """
        try:
            raise ValueError(mode)
        except ValueError:
            pass

    for fn in (prose, numpy_style, misnamed, raising, caught):
        fn.__module__ = __name__
    assert [p.split()[0] for p in problems("prose", prose)] == ["PR01", "RT01"]
    assert problems("numpy_style", numpy_style) == []
    assert sorted(p.split()[0] for p in problems("misnamed", misnamed)) == ["PR01", "PR02"]
    assert problems("raising", raising) == ["RS01 Raises section does not name ValueError"]
    assert problems("caught", caught) == []


#: The public modules in two groups: those that import without ROS, and the ROS side
#: (skipped, with the reason, where the colcon install tree is not sourced).
GROUPS = {
    "pure": tuple(m for m in PUBLIC_MODULES if not m.startswith(_ROS_PREFIXES)),
    "ros": tuple(m for m in PUBLIC_MODULES if m.startswith(_ROS_PREFIXES)),
}


@pytest.mark.parametrize("group", sorted(GROUPS))
def test_every_public_name_has_a_numpy_docstring(group):
    api = public_api(GROUPS[group])
    failures = {name: found for name, obj in sorted(api.items())
                if (found := problems(name, obj))}
    report = "\n".join(f"{name}: {'; '.join(found)}" for name, found in failures.items())
    assert not failures, (f"{len(failures)} of {len(api)} public names fail numpydoc's "
                          f"checks {sorted(CHECKS)}:\n{report}")


def _documented_modules() -> set[str]:
    pattern = re.compile(r"^\.\. automodule:: (\S+)", re.M)
    return {m for page in DOCS_API.glob("*.rst") for m in pattern.findall(page.read_text())}


def _package_modules() -> set[str]:
    """Every module of the package's source tree, by dotted name (no import): packages by
    their ``__init__.py``; private (``_``) modules and ``__main__`` left out."""
    source = ROOT / "wrenchcone_ros" / PACKAGE
    out = set()
    for path in source.rglob("*.py"):
        parts = path.relative_to(source.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if not any(p.startswith("_") for p in parts):
            out.add(".".join(parts))
    return out


def test_every_module_is_public_or_internal():
    modules = _package_modules()
    assert "wrenchcone_ros.core.scene" in modules and "wrenchcone_ros.node" in modules
    unclassified = sorted(modules - set(PUBLIC_MODULES) - set(INTERNAL_MODULES))
    assert not unclassified, (
        f"modules neither in PUBLIC_MODULES (docstrings checked, a page in docs/api) nor "
        f"in INTERNAL_MODULES: {unclassified}")
    assert not (set(PUBLIC_MODULES) | set(INTERNAL_MODULES)) - modules, "a listed module is gone"


def test_the_api_reference_lists_every_public_module():
    missing = sorted(set(PUBLIC_MODULES) - _documented_modules())
    assert not missing, f"public modules without an automodule page in docs/api: {missing}"
