# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The registry of engines and the one configuration point of the default engine.

An engine is registered by name with a function that makes it (:func:`register_engine`),
called at the name's first use; a function that returns None (the engine cannot be
loaded: numba missing) leaves the name to the reference engine, :data:`REFERENCE`. The
names' order of registration is their order of preference: the first is the default.
:mod:`wrenchcone_ros.core.engines` registers ``"kernel"`` then ``"numpy"``.

The default is set here only: the name given to :func:`configure_engine`, else the
environment variable ``WRENCHCONE_ENGINE`` (read once per process), else the first name.
The only read of the environment in the core.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from .protocol import Engine

#: Environment variable naming the default engine: "kernel" or "numpy".
ENGINE_ENV = "WRENCHCONE_ENGINE"
#: The reference engine's name: every engine gives its cones, and a name whose engine
#: cannot be loaded is given to it.
REFERENCE = "numpy"

_makers: dict[str, Callable[[], Engine | None]] = {}
_engines: dict[str, Engine] = {}
_first: str | None = None  # the first name registered: the default
_configured: str | None = None
_environment: str | None = None
_environment_read = False


def register_engine(name: str, make: Callable[[], Engine | None]) -> None:
    """Register the engine ``name``, made by ``make()`` at its first use.

    Parameters
    ----------
    name : str
        The engine's name (``engine=``, :func:`configure_engine`, ``$WRENCHCONE_ENGINE``).
    make : callable
        ``make() -> Engine | None``; None: the engine cannot be loaded, the name is the
        reference engine's (:data:`REFERENCE`).
    """
    global _first
    _makers[name] = make
    _engines.pop(name, None)
    if _first is None:
        _first = name


def engine_names() -> tuple[str, ...]:
    """The registered names, in order of preference (the first is the default).

    Returns
    -------
    tuple of str
        The names.
    """
    return tuple(_makers)


def _by_name(name: str) -> Engine:
    """The registered engine ``name`` (the reference when it cannot be loaded)."""
    if name not in _makers:
        raise ValueError(f"unknown engine {name!r}; choose one of {list(engine_names())} "
                         f"(argument engine=, configure_engine() or ${ENGINE_ENV})")
    got = _engines.get(name)
    if got is None:  # first use: make (load, compile) it
        made = _makers[name]()
        got = _engines[name] = made if made is not None else _by_name(REFERENCE)
    return got


def configure_engine(name: str | None) -> None:
    """Set the process's default engine (the one configuration point).

    Parameters
    ----------
    name : str or None
        "kernel" or "numpy"; None: back to ``$WRENCHCONE_ENGINE``, else "kernel".

    Raises
    ------
    ValueError
        For an unknown name.
    """
    global _configured
    if name is not None and name not in _makers:
        _by_name(name)  # raises the worded ValueError
    _configured = name


@contextmanager
def using_engine(name: str | None) -> Iterator[None]:
    """:func:`configure_engine` ``name`` for the duration of a ``with`` block (then restored):
    how a one-shot command (the CLI) chooses the engine of everything it calls.

    Parameters
    ----------
    name : str or None
        "kernel", "numpy", or None (back to the environment's or the default).

    Yields
    ------
    None
        Inside the block, the engine is ``name``.

    Raises
    ------
    ValueError
        For an unknown name.
    """
    global _configured
    saved = _configured
    configure_engine(name)
    try:
        yield
    finally:
        _configured = saved


def engine_from_environment() -> str | None:
    """The engine ``$WRENCHCONE_ENGINE`` names, read once per process (the only read of
    the environment in the core).

    Returns
    -------
    str or None
        The variable's value; None when it is unset or empty.
    """
    global _environment, _environment_read
    if not _environment_read:
        _environment = os.environ.get(ENGINE_ENV) or None
        _environment_read = True
    return _environment


def default_engine() -> Engine:
    """The engine a call without ``engine=`` uses: the name given to :func:`configure_engine`,
    else ``$WRENCHCONE_ENGINE`` (read once), else "kernel".

    Returns
    -------
    Engine
        "kernel" becomes the numpy engine when numba cannot be loaded.

    Raises
    ------
    ValueError
        For an unknown name in the configuration or the environment.
    """
    return _by_name(_configured or engine_from_environment() or _first)


def get_engine(engine: str | Engine | None = None) -> Engine:
    """The engine a call uses.

    Parameters
    ----------
    engine : str, Engine or None
        A registered name (:func:`engine_names`), an engine object, or None for
        :func:`default_engine`.

    Returns
    -------
    Engine

    Raises
    ------
    ValueError
        For an unknown name.
    """
    if engine is None:
        return default_engine()
    if isinstance(engine, str):
        return _by_name(engine)
    return engine


def resolve_engine(engine: str | Engine | None = None) -> str:
    """The name of the engine a call uses.

    Parameters
    ----------
    engine : str, Engine or None, optional
        An engine, its name, or None (the default engine).

    Returns
    -------
    str
        ``get_engine(engine).name``: "kernel" or "numpy".

    Raises
    ------
    ValueError
        For an unknown name.
    """
    return get_engine(engine).name


__all__ = ["ENGINE_ENV", "REFERENCE", "configure_engine", "default_engine",
           "engine_from_environment", "engine_names", "get_engine", "register_engine",
           "resolve_engine", "using_engine"]
