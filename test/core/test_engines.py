# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""core/engines/ (registry.py): the engine choice (argument, configure_engine, $WRENCHCONE_ENGINE read
once), the caches one reset clears, and the one visible line before the kernel
compiles."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from wrenchcone_ros.core import default_scene, engines, stats, wrench_cones
from wrenchcone_ros.core.robust import robust_cone
from wrenchcone_ros.core.uncertainty import Uncertainty

MESSAGE = engines.COMPILE_MESSAGE
WARM = ("from wrenchcone_ros.core import batch, engines\n"
        "print('ENGINE', engines.resolve_engine(), round(batch.warm_up(), 1))\n")


def test_unknown_engine_is_refused():
    with pytest.raises(ValueError, match="unknown engine 'gpu'"):
        engines.configure_engine("gpu")
    with pytest.raises(ValueError, match="unknown engine 'gpu'"):
        engines.get_engine("gpu")
    assert engines.resolve_engine("numpy") == "numpy"


def test_configuration_point_and_restoring_it():
    """using_engine chooses the default engine for a block (the scene's geometry and
    every call without engine=), and restores it afterwards; an argument beats it."""
    before = engines.resolve_engine()
    with engines.using_engine("numpy"):
        assert engines.resolve_engine() == "numpy"
        assert isinstance(engines.default_engine(), engines.NumpyEngine)
        assert engines.resolve_engine("kernel") in ("kernel", "numpy")  # numpy w/o numba
    assert engines.resolve_engine() == before
    assert isinstance(engines.get_engine(), engines.Engine)


def test_environment_is_read_once(monkeypatch):
    """$WRENCHCONE_ENGINE is read by one function, once per process: changing it later
    changes nothing (configure_engine is the way to change the engine in a process)."""
    first = engines.engine_from_environment()
    monkeypatch.setenv(engines.ENGINE_ENV, "gpu")
    assert engines.engine_from_environment() == first
    engines.resolve_engine()  # no ValueError: the variable was not read again


def test_one_reset_clears_every_engine_cache():
    """Every cache the engines keep is in stats.CACHES, and stats.reset empties them:
    filled by a batch, a robust "all" batch over friction vertices and an "any" batch."""
    s = default_scene()
    u = Uncertainty(friction=(0.2, 0.4))
    with engines.using_engine("kernel"):
        wrench_cones(s, ["na", "la", "*a"])
        robust_cone(s, "la", u, "all")
        robust_cone(s, "la", u, "any")
    if engines.kernel_unavailable() is None:
        assert all(len(c) for c in (stats.PLAN_CODES, stats.BATCH_PLANS, stats.ANY_CODES))
    stats.reset(counters=False)
    assert not any(len(c) for c in stats.CACHES)


LOAD = ("from wrenchcone_ros.core import engines\n"
        "first, again = engines.kernel_module(), engines.kernel_module()\n"
        "print('LOADED', first is not None and again is first)\n")


@pytest.mark.slow
def test_cold_kernel_cache_says_so_once_and_a_warm_one_does_not(tmp_path):
    """After `pip install .` the first kernel use blocked silently for about a minute
    (numba compiling): with an empty numba cache one line on stderr says so before the
    wait, once however often the kernel is asked for; with the cache numba filled (the
    build fills it: `make build` warms the kernel), nothing is said. The cold child only
    loads the kernel (the line comes before any compile), so the test compiles nothing
    unless the default cache is cold too."""
    import wrenchcone_ros.core.kernel as kernel_source

    cold_env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "WRENCHCONE_ENGINE": "kernel"}
    cold = subprocess.run([sys.executable, "-c", LOAD], capture_output=True, text=True,
                          env=cold_env, timeout=300)
    assert cold.returncode == 0 and "LOADED True" in cold.stdout, cold.stderr
    assert cold.stderr.count(MESSAGE) == 1, cold.stderr
    assert not any(tmp_path.rglob("*.nbi")), "loading alone compiled the kernel"
    # the default cache (next to kernel.py, or the user's cache directory): filled by the
    # build, or here by one compile when it was not
    warm_env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    warm_env["WRENCHCONE_ENGINE"] = "kernel"
    fill = subprocess.run([sys.executable, "-c", WARM], capture_output=True, text=True,
                          env=warm_env, timeout=900)
    assert fill.returncode == 0 and "ENGINE kernel" in fill.stdout, fill.stderr
    cached = list(Path(kernel_source.__file__).parent.joinpath("__pycache__").glob(
        "kernel*.nbi")) + list(Path.home().joinpath(".cache").rglob("kernel*.nbi"))
    assert cached, "numba wrote no cache for the kernel"
    warm = subprocess.run([sys.executable, "-c", LOAD + WARM], capture_output=True,
                          text=True, env=warm_env, timeout=900)
    assert warm.returncode == 0 and "LOADED True" in warm.stdout, warm.stderr
    assert "ENGINE kernel" in warm.stdout, warm.stderr
    assert MESSAGE not in warm.stderr, warm.stderr
