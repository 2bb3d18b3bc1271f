# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Command-line front end: ``wrenchcone`` (also ``python -m wrenchcone_ros.cli``)::

    wrenchcone cone SCENE.yaml --mode na [--exact] [--method planar|paper] [--json]
    wrenchcone check SCENE.yaml --mode na --wrench FX FY TZ [--json] [--exit-code]
    wrenchcone classify SCENE.yaml --wrench FX FY TZ [--json]
    wrenchcone directions SCENE.yaml --mode arr [--point X Y] [--exclusive] [--exact] [--json]
    wrenchcone sweep SCENE.yaml --mode arr --poses POSES.yaml [--point X Y] [--exclusive] [--json]
    wrenchcone plot SCENE.yaml --mode M [--wrench FX FY TZ] [--point X Y] -o FILE.png|svg|pdf
    wrenchcone plan SCENE.yaml --target 1 2 3 [--actuator tilt|spring] [--friction LO HI] [--animate F.gif]
    wrenchcone design PART.yaml --plate PLATE.yaml [--friction LO HI] [--top K] --out F.parquet
    wrenchcone --version

SCENE may be ``default`` for the built-in paper disc example. A mode may carry wildcards
(``c``: l, r or n; ``*``: any valid letter): ``cone`` then prints every concrete mode's cone of
the union, ``check`` tests the union. Bad input exits with code 2 and a one-line error on
stderr, never a traceback. ``check --exit-code`` exits 0 when the wrench is consistent
and 1 when it is not (for scripts). A warning (a scene outside the range the error study
verifies, :class:`~wrenchcone_ros.core.scene.UnverifiedRangeWarning`) is one line on
stderr, ``wrenchcone: warning: ...``, and the command goes on.

One module per subcommand. Each defines ``NAME``, ``HELP``, ``add_arguments(parser)`` and
``run(args) -> str`` (the text printed on stdout; it may set ``args.exit_status``); the
options several subcommands share (scene, mode, wrench, point, ``--json``) come from
:mod:`wrenchcone_ros.cli.options`. A new subcommand is one more entry in ``COMMANDS``.

The CLI computes float cones with the numpy reference engine
(:func:`wrenchcone_ros.core.engine.using_engine`) unless $WRENCHCONE_ENGINE says otherwise
(except ``design``, a long run of thousands of cones, which keeps the default, the
compiled kernel): a one-shot command computes a handful of cones, and loading the numba
kernel from its cache costs more than that (measured: 1.1 s per `wrenchcone check` with
numpy against 2.3 s with the kernel, docs/performance.md). Both engines give the same
cones (test/core/test_kernel.py).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from .._version import __version__
from ..core.engine import engine_from_environment, using_engine
from ..core.scene import UnverifiedRangeWarning
from . import check, classify, cone, design, directions, plan, plot, replay, sweep

# The subcommands, in the order `wrenchcone --help` lists them.
COMMANDS = (cone, check, classify, directions, sweep, plot, plan, design, replay)


#: Every float literal with a leading minus, which argparse must read as a value and not
#: as an option: its own pattern misses exponents and words ('-1e-3', '-1E+3', '-inf').
_NEGATIVE_NUMBER = re.compile(
    r"^-(?:(?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?|inf(?:inity)?|nan)$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER

    def error(self, message: str) -> None:  # one line, exit 2 (argparse's own convention)
        self.exit(2, f"wrenchcone: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The ``wrenchcone`` argument parser with one subparser per module in COMMANDS.

    Returns
    -------
    argparse.ArgumentParser
        The parser; its errors exit with status 2 and one line on stderr.
    """
    p = _Parser(prog="wrenchcone", description="Wrench cones of planar augmented contact modes.")
    p.add_argument("--version", action="version", version=f"wrenchcone {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for command in COMMANDS:
        sp = sub.add_parser(command.NAME, help=command.HELP)
        command.add_arguments(sp)
        sp.set_defaults(run=command.run)
    return p


@contextmanager
def _one_shot_engine() -> Iterator[None]:
    """The numpy engine for this one command unless $WRENCHCONE_ENGINE names one (see
    the module docstring); the process's default engine is restored afterwards, because
    main() is also called in-process (tests, scripts) and must not choose the engine of
    the rest of the process."""
    with using_engine(None if engine_from_environment() else "numpy"):
        yield


def main(argv: Sequence[str] | None = None) -> int:
    """Run one ``wrenchcone`` command; returns the exit status (0, 1 or 2).

    Parameters
    ----------
    argv : sequence of str or None, optional
        The arguments after the program's name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        0 on success; 1 for ``check --exit-code`` on an inconsistent wrench; 2 for bad
        input (one line on stderr).
    """
    words = list(sys.argv[1:] if argv is None else argv)
    if words[:1] == ["design"]:  # thousands of cones: the compiled kernel pays off
        return _main(argv)
    with _one_shot_engine():
        return _main(argv)


def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line on stderr (``wrenchcone: warning: ...``), no source line."""
    text = " ".join(str(message).split())
    print(f"wrenchcone: warning: {text}", file=sys.stderr if file is None else file)


def _print_to_a_reader(text: str) -> None:
    """Print ``text``; a reader that stopped reading (``wrenchcone ... | head``) ends the
    output quietly: no error, no traceback, exit status unchanged. stdout is pointed at
    the null device so that Python's flush at exit does not fail again."""
    try:
        print(text)
        sys.stdout.flush()
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


def _main(argv: Sequence[str] | None) -> int:
    args = build_parser().parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("default", UnverifiedRangeWarning)
            warnings.showwarning = _warning_line
            out = args.run(args)
        _print_to_a_reader(out)
    except (ValueError, OSError, ArithmeticError) as exc:  # SceneError, ModeError: ValueError
        msg = " ".join(str(exc).split()) or type(exc).__name__
        print(f"wrenchcone: error: {msg}", file=sys.stderr)
        return 2
    return getattr(args, "exit_status", 0)
