# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Which engine computes float planar cones: the compiled kernel or the numpy reference.

``"kernel"`` (default when numba can be imported) is the planar float method compiled
(:mod:`.kernel`); ``"numpy"`` is the reference (:func:`.planar.planar_cone` per mode).
Choose with an ``engine`` argument or the ``WRENCHCONE_ENGINE`` environment variable.
This module only selects and loads; :mod:`.batch` runs the kernel, and
:func:`.batch.warm_up` loads it (or compiles it, the first time) ahead of use.
"""

from __future__ import annotations

import os
import sys
import warnings

#: Environment variable choosing the default engine: "kernel" or "numpy".
ENGINE_ENV = "WRENCHCONE_ENGINE"
ENGINES = ("kernel", "numpy")

#: One line on stderr before numba compiles the kernel (a cold cache: the first use after
#: an install, or after kernel.py changed), so that the wait is not a silent one.
COMPILE_MESSAGE = ("wrenchcone: compiling the batch kernel once (about a minute; cached "
                   "afterwards)")

_kernel_module = None
_kernel_error: str | None = None


def _cache_is_cold(kernel) -> bool:
    """Whether numba's on-disk cache lacks a usable compiled copy of the kernel's entry
    points (then the first call compiles them, about a minute). Reads numba's cache
    index, a numba internal; on any surprise it answers False (say nothing)."""
    try:
        return any(not f._cache._cache_file._load_index()
                   for f in (kernel.planar_batch, kernel.contact_geometry))
    except Exception:  # another numba version: no message rather than a wrong one
        return False


def kernel_module():
    """The compiled kernel module, or None when it cannot be loaded: numba missing, or
    no writable cache directory (then the reference engine is used, with one
    RuntimeWarning; :func:`kernel_unavailable` says why)."""
    global _kernel_module, _kernel_error
    if _kernel_module is None and _kernel_error is None:
        try:
            from . import kernel  # lazy: numba is optional, and slow to import
        except Exception as exc:  # numba missing or broken, or no writable cache
            # location (numba's RuntimeError "no locator available"): the numpy engine
            _kernel_error = f"{type(exc).__name__}: {exc}"
            warnings.warn(f"wrenchcone_ros: compiled kernel unavailable ({_kernel_error}); "
                          "using the numpy reference engine", RuntimeWarning, stacklevel=3)
        else:
            if _cache_is_cold(kernel):
                print(COMPILE_MESSAGE, file=sys.stderr, flush=True)
            _kernel_module = kernel
    return _kernel_module


def kernel_unavailable() -> str | None:
    """Why the kernel could not be loaded (None if it loaded or was not tried yet)."""
    return _kernel_error


def resolve_engine(engine: str | None = None) -> str:
    """The engine a call uses: the argument, else $WRENCHCONE_ENGINE, else "kernel";
    "kernel" becomes "numpy" when numba cannot be imported."""
    name = engine if engine is not None else os.environ.get(ENGINE_ENV, "kernel") or "kernel"
    if name not in ENGINES:
        raise ValueError(f"unknown engine {name!r}; choose one of {list(ENGINES)} "
                         f"(argument engine= or ${ENGINE_ENV})")
    if name == "kernel" and kernel_module() is None:
        return "numpy"
    return name
