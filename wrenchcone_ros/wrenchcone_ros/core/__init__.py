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
[tool.importlinter]): tolerances; budget, kernel, modes, numbers, stats; scene;
dynamics; constraints; cone3d; cones; planar; paper; wrenchset; engine; batch;
uncertainty; robust; classify; directions, drawing, lp_check; regions, sweeps, tilt;
plot; simulate; plan; animate.

Every set of wrenches is a :class:`WrenchSet` (one convex cone, a wildcard mode's union,
a robust "all" / "any" set) with its :class:`Guarantee`. The float planar cones are
computed by an :class:`Engine` (the compiled kernel or the numpy reference), chosen by
an ``engine=`` argument or, for the whole process, :func:`configure_engine`.
"""

from .batch import DEFAULT_METHOD, METHODS, mode_union, wrench_cone, wrench_cones
from .classify import consistent_modes, exclusive_region, only_mode
from .cones import Cone
from .directions import DirectionInterval, force_directions
from .engines import Engine, configure_engine, get_engine
from .modes import MODE_TABLE, ModeError, ModeSyntaxError, enumerate_modes, parse_mode
from .regions import ForceRegion, force_region
from .robust import robust_cone, robust_cones
from .geometry import Disc, Fixel, Polygon, SceneError, Workpiece
from .scene import Scene
from .scene_yaml import PAPER_DISC, default_scene, load_scene
from .sweeps import SweepResult, sweep
from .tilt import STANDARD_GRAVITY, TiltInterval, tilt_directions, tilt_gravity_force
from .uncertainty import NOMINAL, Uncertainty, UncertaintyError, load_uncertainty
from .wrenchset import EXACT_GUARANTEE, Guarantee, WrenchSet

__all__ = [
    "DEFAULT_METHOD", "METHODS", "wrench_cone", "wrench_cones", "Cone", "consistent_modes",
    "exclusive_region", "mode_union", "only_mode", "MODE_TABLE", "ModeError", "ModeSyntaxError",
    "enumerate_modes", "parse_mode", "PAPER_DISC", "Disc", "Fixel", "Polygon", "Scene",
    "SceneError", "Workpiece", "default_scene", "load_scene",
    "DirectionInterval", "ForceRegion", "SweepResult", "force_directions", "force_region",
    "sweep", "tilt_directions", "tilt_gravity_force", "TiltInterval", "STANDARD_GRAVITY",
    "Uncertainty", "UncertaintyError", "load_uncertainty", "robust_cone", "robust_cones",
    "NOMINAL", "WrenchSet", "Guarantee", "EXACT_GUARANTEE", "Engine", "get_engine",
    "configure_engine",
]

#: Names imported on first use: name -> submodule (the planner and the simulation). The
#: function ``simulate`` is not among them: ``wrenchcone_ros.core.simulate`` is its module.
_LAZY = {
    **dict.fromkeys(("plan_seating", "execute", "run_models", "sample_models", "Plan",
                     "Segment", "RunResult", "PlanError", "PlanCancelled", "StartRegion",
                     "RegionCertificate"), "plan"),
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
