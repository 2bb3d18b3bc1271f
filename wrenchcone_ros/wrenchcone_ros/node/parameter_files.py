# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Parameters files: the two generated from the node's parameter table
(:data:`.parameters.SPECS`), ``config/wrenchcone.yaml`` and the parameters table of
``docs/node_reference.md``; and a user's ``--params-file`` read for sections that miss a renamed
node (:func:`misaddressed_params_files`).

    python -m wrenchcone_ros.node.parameter_files --yaml       # the config file
    python -m wrenchcone_ros.node.parameter_files --markdown   # the docs' table
    python -m wrenchcone_ros.node.parameter_files --write      # rewrite both in place

The tests check that the committed files are this output, so a new or changed parameter
is written once, in the table.
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
import textwrap
from pathlib import Path
from typing import Any

import yaml

from wrenchcone_ros.node.parameters import (
    FROM_SCENE,
    GROUPS,
    SPECS,
    ParameterSpec,
    builtin_defaults,
    descriptor_text,
)

#: The params-file key of the node: the node named ``wrenchcone`` in any namespace.
NODE_KEY = "/**/wrenchcone"
#: The files, relative to the repository root (the colcon workspace).
CONFIG_PATH = Path("wrenchcone_ros") / "config" / "wrenchcone.yaml"
DOC_PATH = Path("docs") / "node_reference.md"
#: The page whose sections a row's "See ..." links to (the table's page is another).
SEE_PAGE = "node.md"
#: The header row of the docs' table (the table is the lines from it to the first line
#: that does not start with "|", inside the section "## Parameters").
TABLE_HEADER = "| name | type | default | unit | allowed | meaning |"

_CONFIG_HEADER = """\
# Parameters of the wrenchcone node, every one with its default, generated from the
# node's parameter table by
#   python -m wrenchcone_ros.node.parameter_files --yaml
# (docs/node.md, "Parameters", says more). Start with it:
#   ros2 launch wrenchcone_ros wrenchcone.launch.py            (installed copy)
#   wrenchcone_node --ros-args --params-file wrenchcone_ros/config/wrenchcone.yaml
# The key is the node's name: a node renamed with -r __node:=NAME reads the section
# /**/NAME (or /**), not this one.
# Scene and uncertainty parameters are comments: their defaults come from scene_file
# (shown: the values without one). Uncommented, a value here wins over scene_file's.
# A key the node does not know (a misspelling) is reported at start as a warning.
# SI units: m, kg, rad, s, Hz.
"""


def _yaml_scalar(name: str, value: Any) -> str:
    """``name: value`` as YAML (a list in flow style)."""
    if isinstance(value, list):
        return f"{name}: " + yaml.safe_dump(value, default_flow_style=True,
                                            width=1000).strip()
    return yaml.safe_dump({name: value}, default_flow_style=False, width=1000).strip()


def _comment(text: str, indent: str) -> list[str]:
    """``text`` as comment lines of at most 88 characters; an interval such as ``[0,
    1e+12]`` and a quantity such as ``1e-9 m`` stay on one line."""
    keep = re.sub(r"([\[(][^\])]*?), ", "\\1,\0", text)
    keep = re.sub(r"(\d) (m|s|rad|Hz|kg)\b", "\\1\0\\2", keep)
    lines = textwrap.wrap(keep, width=88, initial_indent=f"{indent}# ",
                          subsequent_indent=f"{indent}# ", break_on_hyphens=False)
    return [line.replace("\0", " ") for line in lines]


def config_yaml() -> str:
    """The text of ``config/wrenchcone.yaml``: every parameter, grouped, each with its
    description, allowed values and default; the scene-file parameters commented."""
    defaults = builtin_defaults()
    indent = "    "
    lines = _CONFIG_HEADER.splitlines() + [f"{NODE_KEY}:", "  ros__parameters:"]
    for group, heading in GROUPS.items():
        lines.append(f"{indent}# --- {heading}")
        for spec in (s for s in SPECS if s.group == group):
            allowed = spec.allowed()
            text = descriptor_text(spec) + (f" Allowed: {allowed}." if allowed else "")
            lines += _comment(text, indent)
            value = defaults[spec.name]
            if value is None:  # unset: an example
                lines.append(f"{indent}# {_yaml_scalar(spec.name, spec.example)}")
            elif spec.default is FROM_SCENE:
                lines.append(f"{indent}# {_yaml_scalar(spec.name, value)}")
            else:
                lines.append(f"{indent}{_yaml_scalar(spec.name, value)}")
    return "\n".join(lines) + "\n"


def _md_value(value: Any) -> str:
    if value is None:
        return "unset"
    if isinstance(value, bool):
        return "`true`" if value else "`false`"
    if isinstance(value, str):
        return f"`{value}`" if value else '`""`'
    if isinstance(value, list):
        return "`[" + ", ".join(str(v) for v in value) + "]`"
    return f"`{value!r}`"


def _md_cell(text: str) -> str:
    return text.replace("|", "\\|")


def _anchor(title: str) -> str:
    return "#" + "".join(c for c in title.lower().replace(" ", "-")
                         if c.isalnum() or c in "-_")


def markdown_row(spec: ParameterSpec, default: Any) -> str:
    if spec.default is FROM_SCENE:
        shown = f"scene_file's, else {_md_value(default)}"
    else:
        shown = _md_value(default)
    meaning = spec.description
    if spec.read_only:
        meaning = "**Read-only** (given at start). " + meaning
    if spec.see:
        meaning += f" See [{spec.see}]({SEE_PAGE}{_anchor(spec.see)})."
    allowed = spec.allowed() if spec.low is not None or spec.choices else ""
    cells = [f"`{spec.name}`", spec.type, shown, spec.unit or "-", allowed or "-", meaning]
    return "| " + " | ".join(_md_cell(c) for c in cells) + " |"


def markdown_table() -> str:
    """The parameters table of docs/node_reference.md."""
    defaults = builtin_defaults()
    rows = [TABLE_HEADER, "| --- | --- | --- | --- | --- | --- |"]
    rows += [markdown_row(s, defaults[s.name]) for s in SPECS]
    return "\n".join(rows) + "\n"


def doc_table(doc: str) -> tuple[int, int]:
    """The (start, end) character offsets of the parameters table in the text of
    docs/node_reference.md; ValueError when the section or its table is missing."""
    section = doc.index("\n## Parameters\n")
    start = doc.index("\n| name |", section) + 1
    end = start
    for line in doc[start:].splitlines(keepends=True):
        if not line.startswith("|"):
            break
        end += len(line)
    return start, end


def write(root: Path) -> list[Path]:
    """Rewrite the two files under the repository ``root``; returns those changed."""
    changed = []
    config = root / CONFIG_PATH
    if config.read_text() != config_yaml():
        config.write_text(config_yaml())
        changed.append(config)
    doc_path = root / DOC_PATH
    doc = doc_path.read_text()
    start, end = doc_table(doc)
    new = doc[:start] + markdown_table() + doc[end:]
    if new != doc:
        doc_path.write_text(new)
        changed.append(doc_path)
    return changed


def params_file_paths(args: Sequence[str]) -> list[str]:
    """The paths given with ``--params-file`` in the ROS arguments of ``args`` (the
    command line: ``--ros-args ... [--]`` sections)."""
    paths, in_ros, k = [], False, 0
    while k < len(args):
        arg = args[k]
        if arg == "--ros-args":
            in_ros = True
        elif arg == "--" and in_ros:
            in_ros = False
        elif in_ros and arg == "--params-file" and k + 1 < len(args):
            paths.append(args[k + 1])
            k += 1
        k += 1
    return paths


def _key_pattern(key: str) -> re.Pattern[str]:
    """A params-file section key (``/**``, ``/**/name``, ``/ns/name``, ``name``) as a
    pattern of fully qualified node names."""
    key = key if key.startswith("/") else "/" + key
    parts = []
    for part in key.strip("/").split("/"):
        parts.append("(/[^/]+)*" if part == "**" else
                     "/" + re.escape(part).replace(r"\*", "[^/]*"))
    return re.compile("^" + "".join(parts) + "$")


def misaddressed_params_files(args: Sequence[str], node_name: str, namespace: str,
                              default_name: str = "wrenchcone") -> list[str]:
    """One warning per ``--params-file`` of ``args`` that has a section for the node
    under its default name ``default_name`` but none for ``node_name`` (a node renamed
    with ``-r __node:=NAME``): ROS applies a section to the nodes its key names, so the
    renamed node silently gets none of those values. Files that cannot be read are
    skipped (rcl has refused them already)."""
    namespace = namespace.rstrip("/")
    fqn, default_fqn = f"{namespace}/{node_name}", f"{namespace}/{default_name}"
    warnings = []
    for path in params_file_paths(args):
        try:
            with open(path, encoding="utf-8") as f:
                keys = [k for k in (yaml.safe_load(f) or {}) if isinstance(k, str)]
        except (OSError, yaml.YAMLError, TypeError):
            continue
        if any(_key_pattern(k).match(fqn) for k in keys):
            continue
        for_default = [k for k in keys if _key_pattern(k).match(default_fqn)]
        if for_default and node_name != default_name:
            warnings.append(
                f"--params-file {path}: section {for_default[0]!r} is for a node named "
                f"{default_name!r}, but this node is {fqn!r}, so none of its values apply "
                f"(parameters files are keyed by node name): put them under "
                f"'/**/{node_name}:' or '/**:'")
    return warnings


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m wrenchcone_ros.node.parameter_files", description=__doc__.split(
            "\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--yaml", action="store_true", help="print config/wrenchcone.yaml")
    what.add_argument("--markdown", action="store_true", help="print the docs' table")
    what.add_argument("--write", metavar="ROOT", nargs="?", const=".",
                      help="rewrite both files under the repository ROOT (default .)")
    args = parser.parse_args(argv)
    if args.yaml:
        sys.stdout.write(config_yaml())
    elif args.markdown:
        sys.stdout.write(markdown_table())
    else:
        for path in write(Path(args.write)):
            print(f"rewrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
