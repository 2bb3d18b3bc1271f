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
[tool.importlinter]): tolerances; budget, kernel, modes, numbers, stats; scene;
dynamics; constraints; cone3d; cones; planar; paper; wrenchset; engine; batch;
uncertainty; robust; classify; directions, drawing, lp_check; plot; simulate; plan;
animate.

Every set of wrenches is a :class:`WrenchSet` (one convex cone, a wildcard mode's union,
a robust "all" / "any" set) with its :class:`Guarantee`. The float planar cones are
computed by an :class:`Engine` (the compiled kernel or the numpy reference), chosen by
an ``engine=`` argument or, for the whole process, :func:`configure_engine`.
"""

from .batch import DEFAULT_METHOD, METHODS, mode_union, wrench_cone, wrench_cones
from .classify import consistent_modes, exclusive_region, only_mode
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
from .engine import Engine, configure_engine, get_engine
from .modes import MODE_TABLE, ModeError, ModeSyntaxError, enumerate_modes, parse_mode
from .robust import robust_cone, robust_cones
from .scene import PAPER_DISC, Disc, Fixel, Polygon, Scene, SceneError, Workpiece
from .scene import default_scene, load_scene
from .uncertainty import NOMINAL, Uncertainty, UncertaintyError, load_uncertainty
from .wrenchset import EXACT_GUARANTEE, Guarantee, WrenchSet

__all__ = [
    "DEFAULT_METHOD", "METHODS", "wrench_cone", "wrench_cones", "Cone", "consistent_modes",
    "exclusive_region", "mode_union", "only_mode", "MODE_TABLE", "ModeError", "ModeSyntaxError",
    "enumerate_modes", "parse_mode", "PAPER_DISC", "Disc", "Fixel", "Polygon", "Scene",
    "SceneError", "Workpiece", "default_scene", "load_scene",
    "DirectionInterval", "ForceRegion", "SweepResult", "force_directions", "force_region",
    "sweep", "tilt_directions", "tilt_gravity_force",
    "Uncertainty", "UncertaintyError", "load_uncertainty", "robust_cone", "robust_cones",
    "NOMINAL", "WrenchSet", "Guarantee", "EXACT_GUARANTEE", "Engine", "get_engine",
    "configure_engine",
]
