# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone sweep``: the force directions that give a mode along a path of poses."""

from __future__ import annotations

from ..core.scene_yaml import yaml_problem
from ..core.sweeps import sweep
from .directions import add_direction_arguments
from .options import point_value, scene_value
from .render import sweep_answer
from .uncertain import uncertainty_value



def add_arguments(sp) -> None:
    add_direction_arguments(sp)
    sp.add_argument("--poses", required=True,
                    help="YAML file: a list of [x m, y m, theta rad] (or {poses: [...]})")


def load_poses(path: str) -> list:
    """The list of poses in a YAML file (a list, or a mapping with the key 'poses')."""
    import yaml

    try:
        with open(path) as fh:
            data = yaml.safe_load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read poses file {path!r}: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"poses file {path!r} is not valid YAML: "
                         f"{yaml_problem(exc)}") from None
    if isinstance(data, dict):
        if set(data) != {"poses"}:
            raise ValueError(f"poses file {path!r}: a mapping must have exactly the key "
                             f"'poses', got {sorted(map(str, data))}")
        data = data["poses"]
    if not isinstance(data, list) or not data:
        raise ValueError(f"poses file {path!r} must hold a non-empty list of "
                         f"[x m, y m, theta rad], got {type(data).__name__}")
    return data


def run(args) -> str:
    scene = scene_value(args.scene)
    point = point_value(args.point)
    U = uncertainty_value(args)
    res = sweep(scene, load_poses(args.poses), args.mode, point=point,
                exclusive=args.exclusive, uncertainty=U)
    return sweep_answer(args, scene, point, res, U)
