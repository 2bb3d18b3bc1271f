# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""engines.py: the engine choice, and the one visible line before the kernel compiles."""

import os
import subprocess
import sys

import pytest

from wrenchcone_ros.core import engines

MESSAGE = engines.COMPILE_MESSAGE
WARM = ("from wrenchcone_ros.core import batch\n"
        "print('ENGINE', batch.resolve_engine(), round(batch.warm_up(), 1))\n")


def test_unknown_engine_is_refused(monkeypatch):
    monkeypatch.setenv(engines.ENGINE_ENV, "gpu")
    with pytest.raises(ValueError, match="unknown engine 'gpu'"):
        engines.resolve_engine()
    assert engines.resolve_engine("numpy") == "numpy"


@pytest.mark.slow
def test_cold_kernel_cache_says_so_once_and_a_warm_one_does_not(tmp_path):
    """After `pip install .` the first kernel use blocked silently for about a minute
    (numba compiling): with an empty numba cache one line on stderr says so before the
    wait; with the cache filled by that run, nothing is said. (Slow: one real compile.)"""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "WRENCHCONE_ENGINE": "kernel"}
    cold = subprocess.run([sys.executable, "-c", WARM], capture_output=True, text=True,
                          env=env, timeout=900)
    assert cold.returncode == 0, cold.stderr
    assert "ENGINE kernel" in cold.stdout
    assert cold.stderr.count(MESSAGE) == 1, cold.stderr
    assert any(tmp_path.rglob("*.nbi")), "numba wrote no cache"
    warm = subprocess.run([sys.executable, "-c", WARM], capture_output=True, text=True,
                          env=env, timeout=900)
    assert warm.returncode == 0 and "ENGINE kernel" in warm.stdout, warm.stderr
    assert MESSAGE not in warm.stderr, warm.stderr
