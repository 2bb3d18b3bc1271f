# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The engines that compute float planar cones, in one folder with their registry.

An engine (:class:`Engine`) computes, for the float planar method (:mod:`.planar`):

* the contact geometry of a scene (:meth:`Engine.contact_arrays`);
* the cones of a batch of valid concrete modes of one pose (:meth:`Engine.cones`);
* the relaxed cones of the mode search (:meth:`Engine.relaxed_rows`);
* the robust batches of :mod:`.robust`: the cones at the vertices of a friction box
  (:meth:`Engine.vertex_cones`), their intersection in one call
  (:meth:`Engine.vertex_intersection`), the "any" cones of many modes
  (:meth:`Engine.any_cones`), and a cone from many inequality rows
  (:meth:`Engine.hrep_cone`).

Two engines are registered (:mod:`.registry`, as qpsolvers registers its solvers), in
order of preference: ``"kernel"`` (:mod:`.kernel_engine`), the planar method compiled
with numba (:mod:`wrenchcone_ros.core.kernel`; the default when numba can be imported),
and ``"numpy"`` (:mod:`.numpy_engine`), the reference
(:func:`wrenchcone_ros.core.planar.planar_cone` mode by mode); :mod:`.protocol` says
what an engine computes. A mode the kernel declines (nearly
parallel acceleration rows, a failed cone3d self-check) is computed by the reference, so
both engines give the same cones (test/core/test_kernel.py).

Choosing the engine. Every function that computes cones takes ``engine=`` (a name, an
:class:`Engine`, or None for the default). The default is set in one place,
:func:`default_engine` (:mod:`.registry`): the name given to :func:`configure_engine`, else the environment
variable ``WRENCHCONE_ENGINE`` (``kernel`` or ``numpy``, read once per process), else
``"kernel"``; ``"kernel"`` becomes ``"numpy"`` when numba cannot be loaded (one
RuntimeWarning says why). Nothing else in the core reads the environment. A scene's
contact geometry is computed by the default engine (a scene is built before any call
names an engine).

:mod:`.packing` is the only module that sees the kernel's input layout (the op-code of a
mode's plan, :func:`plan_code`), :mod:`.kernel_engine` the only one that imports the
kernel. Their caches live in :mod:`wrenchcone_ros.core.stats`
(:func:`wrenchcone_ros.core.stats.reset` clears them).
"""

from __future__ import annotations

from ..geometry import ContactArrays, use_contact_geometry
from ..scene import Scene
from .kernel_engine import (
    COMPILE_MESSAGE,
    KERNEL_STATS,
    SLIDING,
    KernelEngine,
    kernel_module,
    kernel_unavailable,
    make_kernel_engine,
)
from .numpy_engine import NumpyEngine, make_numpy_engine
from .packing import BatchPlan, batch_plan, pack, plan_code, pose_arrays
from .protocol import ConeChecks, Engine, RelaxedRows
from .registry import (
    ENGINE_ENV,
    REFERENCE,
    configure_engine,
    default_engine,
    engine_from_environment,
    engine_names,
    get_engine,
    register_engine,
    resolve_engine,
    using_engine,
)

register_engine("kernel", make_kernel_engine)  # first: the default
register_engine(REFERENCE, make_numpy_engine)

#: Engine names, in order of preference.
ENGINE_NAMES = engine_names()


def _default_contact_arrays(scene: Scene) -> ContactArrays | None:
    return default_engine().contact_arrays(scene)


use_contact_geometry(_default_contact_arrays)  # asked for by Scene.contact_arrays


__all__ = ["ConeChecks", "ENGINE_ENV", "ENGINE_NAMES", "Engine", "NumpyEngine", "KernelEngine",
           "RelaxedRows", "BatchPlan", "KERNEL_STATS", "COMPILE_MESSAGE", "SLIDING",
           "configure_engine", "using_engine", "default_engine", "engine_from_environment",
           "get_engine", "resolve_engine", "register_engine", "engine_names",
           "kernel_module", "kernel_unavailable", "plan_code", "pack", "batch_plan",
           "pose_arrays"]
