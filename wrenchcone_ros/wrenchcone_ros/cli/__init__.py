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

One module per subcommand, named as the subcommand. Each defines ``add_arguments(parser)``
and ``run(args) -> str`` (the text printed on stdout; it may set ``args.exit_status``);
the options several subcommands share (scene, mode, wrench, point, ``--json``) come from
:mod:`wrenchcone_ros.cli.options`. A new subcommand is one more entry in ``COMMANDS``
(its name and its one-line help). Only the module of the subcommand that runs is
imported, and it imports the core (numpy, pycddlib), the planner or Dask: ``wrenchcone
--version`` and ``wrenchcone --help`` import none of them (docs/performance.md).

The CLI computes float cones with the numpy reference engine
(:func:`wrenchcone_ros.core.engines.using_engine`) unless $WRENCHCONE_ENGINE says otherwise
(except ``design``, a long run of thousands of cones, which keeps the default, the
compiled kernel): a one-shot command computes a handful of cones, and loading the numba
kernel from its cache costs more than that (measured: 1.1 s per `wrenchcone check` with
numpy against 2.3 s with the kernel, docs/performance.md). Both engines give the same
cones (test/core/test_kernel.py).
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
import warnings
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager

from .._version import __version__

#: The subcommands, in the order ``wrenchcone --help`` lists them: each name (also the
#: name of its module in this package) with its one-line help.
COMMANDS: dict[str, str] = {
    "cone": "print F, equalities and generators of a mode's cone",
    "check": "is a wrench consistent with a mode?",
    "classify": "every mode a wrench is consistent with",
    "directions": "force directions at a point that give a mode",
    "sweep": "force directions along a path of poses",
    "plot": "picture of the scene and of a mode's cone (matplotlib)",
    "plan": "a plan of tilts or spring pulls that seats the part, checked in simulation",
    "design": "three-pin fixture designs on a modular plate: located, held, loadable, ranked",
    "replay": "a recorded run (rosbag2 MCAP): the cone at every recorded pose, the "
              "commands' margins",
}


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


def build_parser(commands: Iterable[str] | None = None) -> argparse.ArgumentParser:
    """The ``wrenchcone`` argument parser: one subparser per entry of COMMANDS.

    Parameters
    ----------
    commands : iterable of str or None, optional
        The subcommands whose options are added (their modules imported); the others are
        listed with their help but take no options. None (the default): every one, the
        complete parser.

    Returns
    -------
    argparse.ArgumentParser
        The parser; its errors exit with status 2 and one line on stderr.
    """
    full = set(COMMANDS) if commands is None else set(commands)
    p = _Parser(prog="wrenchcone", description="Wrench cones of planar augmented contact modes.")
    p.add_argument("--version", action="version", version=f"wrenchcone {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, help_text in COMMANDS.items():
        sp = sub.add_parser(name, help=help_text)
        if name in full:
            module = importlib.import_module(f".{name}", __name__)
            module.add_arguments(sp)
            sp.set_defaults(run=module.run)
    return p


def _command_of(words: Sequence[str]) -> list[str]:
    """The subcommand the words name, as a list of at most one name: the first word that
    is not an option (the top-level options, ``--help`` and ``--version``, take no
    value), if it is a subcommand."""
    first = next((w for w in words if not w.startswith("-")), None)
    return [first] if first in COMMANDS else []


@contextmanager
def _one_shot_engine() -> Iterator[None]:
    """The numpy engine for this one command unless $WRENCHCONE_ENGINE names one (see
    the module docstring); the process's default engine is restored afterwards, because
    main() is also called in-process (tests, scripts) and must not choose the engine of
    the rest of the process."""
    from ..core.engines import engine_from_environment, using_engine

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
    # Only the named subcommand's module is imported: --version and --help need none.
    parser = build_parser(_command_of(words))
    args = parser.parse_args(words)
    if args.command == "design":  # thousands of cones: the compiled kernel pays off
        return _run(args)
    with _one_shot_engine():
        return _run(args)


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


def _run(args: argparse.Namespace) -> int:
    from ..core.geometry import UnverifiedRangeWarning

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
