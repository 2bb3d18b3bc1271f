# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Options and argument values shared by the subcommands (one definition each).

A subcommand module adds the options it needs with these helpers, so that the scene
argument, the mode, the wrench, the point and ``--json`` read and behave the same in
every subcommand, and turns the parsed strings into checked values with the ``*_value``
functions (bad input: ValueError with a one-line message, printed by ``main``).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence

from ..core import METHODS, Scene, default_scene, load_scene
from ..core.numbers import rescale_wrench

MODE_HELP = "mode string, one letter per fixel from 'aslrn' (wildcards c, * allowed)"


def add_scene(sp: argparse.ArgumentParser, json: bool = True) -> None:
    """The positional SCENE argument (and ``--json`` unless ``json`` is False)."""
    sp.add_argument("scene", help="scene YAML file, or 'default' for the paper's disc")
    if json:
        add_json(sp)


def add_json(sp: argparse.ArgumentParser) -> None:
    sp.add_argument("--json", action="store_true", help="one JSON object on stdout")


def add_mode(sp: argparse.ArgumentParser, help: str = MODE_HELP) -> None:
    sp.add_argument("--mode", required=True, help=help)


def add_wrench(sp: argparse.ArgumentParser, required: bool = True,
               help: str = "force (N) and torque about the com (N m), world frame") -> None:
    sp.add_argument("--wrench", nargs=3, type=float, required=required,
                    metavar=("FX", "FY", "TZ"), help=help)


def add_method(sp: argparse.ArgumentParser) -> None:
    """``--exact`` and ``--method`` (which algorithm makes the cone)."""
    sp.add_argument("--exact", action="store_true", help="rational arithmetic (cddlib GMP)")
    sp.add_argument("--method", choices=sorted(METHODS), default=None,
                    help="algorithm (default: the fastest verified one)")


def add_point(sp: argparse.ArgumentParser,
              help: str = "where the force acts, workpiece frame, m (default: the com)"
              ) -> None:
    sp.add_argument("--point", nargs=2, type=float, metavar=("X", "Y"), default=None,
                    help=help)


def add_common(sp: argparse.ArgumentParser, *, mode: bool = True, wrench: bool = False,
               method: bool = False, point: bool = False) -> None:
    """SCENE and ``--json``, then the shared options a subcommand asks for, in the order
    every subcommand lists them: ``--mode``, ``--wrench``, ``--point``, ``--exact`` /
    ``--method``."""
    add_scene(sp)
    if mode:
        add_mode(sp)
    if wrench:
        add_wrench(sp)
    if point:
        add_point(sp)
    if method:
        add_method(sp)


def scene_value(arg: str) -> Scene:
    """The scene named by the SCENE argument."""
    return default_scene() if arg == "default" else load_scene(arg)


def wrench_value(values: Sequence[float]) -> list[float]:
    """The ``--wrench`` values as a checked list of three finite floats (as given)."""
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"--wrench must be three finite numbers (N, N, N m), got "
                         f"{list(values)}")
    return [float(v) for v in values]


def wrench_to_compute(values: Sequence[float]) -> list[float]:
    """The wrench the computation uses: as given, or rescaled by an exact power of two
    when a component is huge or all are tiny (:func:`~..core.numbers.rescale_wrench`,
    the node's rule): consistency and margins depend only on the direction."""
    return list(rescale_wrench(values))


def point_value(point: Sequence[float] | None) -> list[float] | None:
    """The ``--point`` values (workpiece frame, m), or None for the centre of mass."""
    if point is None:
        return None
    if not all(math.isfinite(v) for v in point):
        raise ValueError(f"--point must be two finite numbers (m), got {list(point)}")
    return [float(v) for v in point]
