# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_ros.core: wrench cones of augmented contact modes, without ROS.

    from wrenchcone_ros.core import load_scene, wrench_cone
    scene = load_scene("examples/paper_disc.yaml")
    cone = wrench_cone(scene, "na")
    cone.F, cone.equalities, cone.G, cone.contains(g), cone.margin(g)
    cones = wrench_cones(scene, ["na", "ss"])  # all modes of one pose in one pass

After Devin J. Balkcom and Jeffrey C. Trinkle, "Computing wrench cones for planar rigid
body contact tasks", The International Journal of Robotics Research, 21(12):1053-1066,
2002 (docs/theory.md). The modules form one-way layers, bottom to top (pyproject.toml,
[tool.importlinter]): tolerances; budget, kernel, modes, numbers, stats; engines; scene;
dynamics; constraints; cone3d; cones; planar; paper; unions; methods; batch; api;
uncertainty; robust; classify; directions, drawing, lp_check; plot; simulate; plan;
animate.
"""

from .api import DEFAULT_METHOD, METHODS, wrench_cone
from .batch import wrench_cones
from .classify import ConeUnion, consistent_modes, exclusive_region, mode_union, only_mode
from .cones import Cone
from .directions import (
    DirectionInterval,
    ForceRegion,
    SweepResult,
    force_directions,
    force_region,
    sweep,
    tilt_directions,
    tilt_gravity_force,
)
from .modes import MODE_TABLE, ModeError, ModeSyntaxError, enumerate_modes, parse_mode
from .robust import RobustCone, robust_cone, robust_cones
from .scene import PAPER_DISC, Disc, Fixel, Polygon, Scene, SceneError, Workpiece
from .scene import default_scene, load_scene
from .uncertainty import Uncertainty, UncertaintyError, load_uncertainty

__all__ = [
    "DEFAULT_METHOD", "METHODS", "wrench_cone", "wrench_cones", "Cone", "ConeUnion", "consistent_modes",
    "exclusive_region", "mode_union", "only_mode", "MODE_TABLE", "ModeError", "ModeSyntaxError",
    "enumerate_modes", "parse_mode", "PAPER_DISC", "Disc", "Fixel", "Polygon", "Scene",
    "SceneError", "Workpiece", "default_scene", "load_scene",
    "DirectionInterval", "ForceRegion", "SweepResult", "force_directions", "force_region",
    "sweep", "tilt_directions", "tilt_gravity_force",
    "Uncertainty", "UncertaintyError", "load_uncertainty", "RobustCone", "robust_cone",
    "robust_cones",
]
