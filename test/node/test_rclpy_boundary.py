# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""No private name of another library (rclpy's above all) is used outside the one boundary
module, node/rclpy_boundary.py.

The rule is read from the syntax tree of every module of the package, not grepped from a
list of known names. A *private name* is one with a single leading underscore (``_x``,
not ``__x__``). A module may use one

* as an attribute of ``self`` / ``cls`` / ``super()`` when this package defines that name
  itself (a method, a class or module attribute, an assignment ``self._x = ...``): a Node
  subclass reaching rclpy's ``self._parameter_overrides`` is caught;
* as an attribute of a module of this package (``params._as_double`` after ``from
  wrenchcone_ros.node import parameters as params``; ``from . import x``);
* from an import of this package.

Everything else is a use of another library's internals: ``node._parameter_overrides``,
``executor._is_shutdown``, ``getattr(executor, "_is_shutdown")`` (a private name as a
string given to getattr / hasattr / setattr / delattr), ``from rclpy.x import _y``,
``import rclpy._rclpy``. Python documents a few underscored names as public API; those are
allowed by name (:data:`DOCUMENTED`).
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

PACKAGE = "wrenchcone_ros"
SOURCE = Path(__file__).resolve().parents[2] / "wrenchcone_ros" / PACKAGE
#: The modules allowed to use other libraries' private names (each documents why).
#: rclpy_boundary.py for rclpy; core/engines/kernel_engine.py for numba (it reads numba's
#: cache index to say when the first call will compile, and answers "not cold" on any
#: other numba); core/pymunk_boundary.py for pymunk (Chipmunk's point queries and impulses
#: without pymunk's per-call objects, checked against its public calls).
BOUNDARY_MODULES = {"node/rclpy_boundary.py", "core/engines/kernel_engine.py",
                    "core/pymunk_boundary.py"}
#: Underscored names Python documents as public API: module -> names; and attribute names
#: public on any object (namedtuple's API).
DOCUMENTED = {"os": {"_exit"}, "sys": {"_getframe"}}
DOCUMENTED_ANYWHERE = {"_replace", "_asdict", "_fields", "_make", "_field_defaults"}
ATTRIBUTE_FUNCTIONS = {"getattr", "hasattr", "setattr", "delattr"}


def is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


@dataclass(frozen=True)
class Violation:
    module: str
    line: int
    use: str

    def __str__(self) -> str:
        return f"{self.module}:{self.line}: {self.use}"


def modules() -> list[Path]:
    return sorted(SOURCE.rglob("*.py"))


def rel(path: Path) -> str:
    return path.relative_to(SOURCE).as_posix()


def dotted(path: Path) -> str:
    parts = [PACKAGE, *path.relative_to(SOURCE).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def is_package_module(name: str) -> bool:
    """Whether ``name`` (dotted) is a module or package of this package."""
    if name != PACKAGE and not name.startswith(PACKAGE + "."):
        return False
    path = SOURCE.joinpath(*name.split(".")[1:])
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def defined_private_names() -> set[str]:
    """Every private name this package defines: functions, classes, module and class
    attributes, ``self._x = ...`` / ``cls._x = ...`` assignments, ``__slots__`` entries,
    ``object.__setattr__(self, "_x", ...)``."""
    names: set[str] = set()
    for path in modules():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                names.add(node.id)
            elif (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store)
                  and isinstance(node.value, ast.Name)
                  and node.value.id in ("self", "cls")):
                names.add(node.attr)
            elif isinstance(node, ast.Call) and _called(node) in ("__setattr__", "setattr") \
                    and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant):
                names.add(str(node.args[1].value))
            elif isinstance(node, ast.Assign) and any(
                    isinstance(t, ast.Name) and t.id == "__slots__" for t in node.targets):
                names |= {c.value for c in ast.walk(node.value)
                          if isinstance(c, ast.Constant) and isinstance(c.value, str)}
    return {n for n in names if is_private(n)}


def _called(call: ast.Call) -> str:
    f = call.func
    return f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else ""


def package_aliases(tree: ast.Module, module: str) -> tuple[set[str], set[str]]:
    """(names bound to modules of this package, names bound to other modules) in a
    module's imports (anywhere in it)."""
    ours, others = set(), set()
    package = module if module.count(".") == 0 else module.rsplit(".", 1)[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                bound = a.asname or a.name.split(".")[0]
                (ours if is_package_module(a.name) else others).add(bound)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[:len(anchor) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            for a in node.names:
                if is_package_module(f"{base}.{a.name}"):
                    ours.add(a.asname or a.name)
    return ours, others


def receiver_root(expr: ast.expr) -> str:
    """The name an attribute chain starts from (``a`` of ``a.b.c``), or ''."""
    while isinstance(expr, ast.Attribute):
        expr = expr.value
    return expr.id if isinstance(expr, ast.Name) else ""


def violations(path: Path, defined: set[str], source: str | None = None) -> list[Violation]:
    """The uses of other libraries' private names in one module (rules: module docstring);
    ``source``: its text, if not the file's."""
    tree = ast.parse(path.read_text() if source is None else source, str(path))
    module = dotted(path)
    if path.name == "__init__.py":
        module += ".__init__"
    ours, _ = package_aliases(tree, module)
    found: list[Violation] = []

    def allowed(receiver: ast.expr, name: str) -> bool:
        if name in DOCUMENTED_ANYWHERE:
            return True
        if isinstance(receiver, ast.Name) and receiver.id in ("self", "cls"):
            return name in defined
        if isinstance(receiver, ast.Call) and _called(receiver) == "super":
            return name in defined
        root = receiver_root(receiver)
        if root in ours or root == PACKAGE and is_package_module(ast.unparse(receiver)):
            return True
        return isinstance(receiver, ast.Name) and name in DOCUMENTED.get(receiver.id, ())

    for node in ast.walk(tree):
        use = None
        if isinstance(node, ast.Attribute) and is_private(node.attr):
            if not allowed(node.value, node.attr):
                use = ast.unparse(node)
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
              and node.func.id in ATTRIBUTE_FUNCTIONS and len(node.args) >= 2
              and isinstance(node.args[1], ast.Constant)
              and isinstance(node.args[1].value, str) and is_private(node.args[1].value)):
            if not allowed(node.args[0], node.args[1].value):
                use = ast.unparse(node)
        elif isinstance(node, ast.ImportFrom) and not node.level:
            base = node.module or ""
            if not (base == PACKAGE or base.startswith(PACKAGE + ".")):
                private = [a.name for a in node.names if is_private(a.name)]
                if private or any(is_private(p) for p in base.split(".")):
                    use = f"from {base} import {', '.join(private or ['...'])}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if any(is_private(p) for p in a.name.split(".")) and \
                        not is_package_module(a.name):
                    use = f"import {a.name}"
        if use:
            found.append(Violation(rel(path), node.lineno, use))
    return found


DEFINED = defined_private_names()
CHECKED = [p for p in modules() if rel(p) not in BOUNDARY_MODULES]


@pytest.mark.parametrize("path", CHECKED, ids=rel)
def test_no_private_names_of_other_libraries_outside_the_boundary(path):
    found = violations(path, DEFINED)
    assert not found, ("private names of other libraries, allowed only in "
                       f"{sorted(BOUNDARY_MODULES)}:\n" + "\n".join(map(str, found)))


# --- the rule itself, on small modules -----------------------------------------------------
RULE_CASES = {
    "node._parameter_overrides": 1,
    "getattr(node, '_parameter_overrides', None)": 1,
    "getattr(executor, '_is_shutdown', False)": 1,
    "executor._is_shutdown": 1,
    "self._parameter_overrides": 1,  # a Node subclass reaching rclpy's attribute
    "super()._parameter_overrides": 1,
    "self._values": 0,  # this package defines _values (wrenchcone_node.py)
    "os._exit(0)": 0,  # documented Python API
    "p._replace(x=1)": 0,  # namedtuple API
    "from rclpy.qos_overriding_options import _declare_qos_parameters": 1,
    "import rclpy._rclpy_pybind11": 1,
    "from wrenchcone_ros.node import parameters as params\nparams._as_double": 0,
    "from wrenchcone_ros.node.parameters import _as_double": 0,
    "import numpy as np\nnp._core": 1,
    "f._cache._cache_file._load_index()": 3,
}


@pytest.mark.parametrize("source,expected", RULE_CASES.items())
def test_the_rule_on_small_modules(source, expected):
    module = SOURCE / "node" / "rule_case.py"  # judged as a module of the package
    found = violations(module, DEFINED | {"_values"}, source)
    assert len(found) == expected, found


def test_the_boundary_module_exists_and_the_rule_sees_it():
    """The boundary module does what the rule forbids elsewhere (so the rule is not empty
    by construction)."""
    boundaries = [p for p in modules() if rel(p) in BOUNDARY_MODULES]
    assert len(boundaries) == len(BOUNDARY_MODULES)
    for boundary in boundaries:
        assert violations(boundary, DEFINED), f"{boundary} uses no private name?"
