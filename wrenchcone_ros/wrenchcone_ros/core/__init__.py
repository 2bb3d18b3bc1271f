# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""wrenchcone_ros.core: wrench cones of augmented contact modes, without ROS.

    from wrenchcone_ros.core import load_scene, wrench_cone
    scene = load_scene("examples/paper_disc.yaml")
    cone = wrench_cone(scene, "na")
    cone.F, cone.equalities, cone.G, cone.contains(g), cone.margin(g)
    cones = wrench_cones(scene, ["na", "ss"])  # all modes of one pose in one pass
    plan = plan_seating(scene, [1, 2, 3], "tilt")  # the planner (needs pymunk to run)

Everything the README and docs/ use is importable from here. The planner and the
simulation (``plan_seating``, ``execute``, ``Actuator``, ...) are imported on first use
(module ``__getattr__``), so that ``import wrenchcone_ros.core`` stays as fast as the
cone code needs; they need pymunk (``pip install .[sim]``) only when a plan is run.

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

# The robust answers' guarantee and the robust classification.
from .robust import Guarantee, robust_consistent_modes  # noqa: E402

__all__ += ["Guarantee", "robust_consistent_modes"]

#: Names imported on first use: name -> submodule (the planner and the simulation). The
#: function ``simulate`` is not among them: ``wrenchcone_ros.core.simulate`` is its module.
_LAZY = {
    **dict.fromkeys(("plan_seating", "execute", "run_models", "sample_models", "Plan",
                     "Segment", "RunResult", "PlanError", "PlanCancelled"), "plan"),
    **dict.fromkeys(("Actuator", "Simulation", "SimulationUnavailable", "initial_mode"),
                    "simulate"),
}
__all__ += list(_LAZY)


def __getattr__(name: str):
    """The planner's and the simulation's names, imported on first use (PEP 562).

    Raises
    ------
    AttributeError
        ``name`` is not a name of ``wrenchcone_ros.core``.
    """
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
