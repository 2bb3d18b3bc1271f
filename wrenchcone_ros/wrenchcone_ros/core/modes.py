# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Augmented contact modes: Table 2 of the paper as data, validation and enumeration.

This module is the single source of truth for what each mode letter means. Every
method (the paper's algorithm, the planar formulation, the LP check) reads
:data:`MODE_TABLE` and nothing else.

Table 2 of Devin J. Balkcom and Jeffrey C. Trinkle, "Computing wrench cones for planar
rigid body contact tasks", The International Journal of Robotics Research,
21(12):1053-1066, 2002 (restated in docs/theory.md), per fixel i, with a = J^T xdd the contact
accelerations and c the contact forces in the fixel frame (n_i, t_i):

======  ===============  ==========================  ======  =====  ===============
letter  contact          a_in                        a_it    c_in   c_it
======  ===============  ==========================  ======  =====  ===============
a       no (gap > 0)     < 0                         free    = 0    = 0
s       either           >= 0 (> 0 when in contact)  free    = 0    = 0
l       yes              = 0                         > 0     >= 0   = -mu c_in
r       yes              = 0                         < 0     >= 0   = +mu c_in
n       yes              = 0                         = 0     >= 0   |c_it| <= mu c_in
======  ===============  ==========================  ======  =====  ===============
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from enum import Enum


class ModeError(ValueError):
    """A mode string that is malformed or not allowed by the scene's contact state."""


class ModeSyntaxError(ModeError):
    """A malformed mode string: not a string, an unknown letter or the wrong length."""


class Sign(Enum):
    """Constraint on one scalar variable (an acceleration or a force component)."""

    FREE = "free"
    ZERO = "= 0"
    NONNEG = ">= 0"
    NONPOS = "<= 0"
    POS = "> 0"  # strict
    NEG = "< 0"  # strict

    @property
    def strict(self) -> bool:
        """True for the open conditions that Theorem 1 (k = 0) relaxes to their closure."""
        return self in (Sign.POS, Sign.NEG)

    @property
    def closure(self) -> Sign:
        """The non-strict version of the condition (Theorem 1 with k = 0)."""
        return {Sign.POS: Sign.NONNEG, Sign.NEG: Sign.NONPOS}.get(self, self)

    @property
    def direction(self) -> int:
        """+1 for >= / >, -1 for <= / <, 0 for = 0 and free."""
        return _DIRECTION[self]


_DIRECTION = {Sign.FREE: 0, Sign.ZERO: 0, Sign.NONNEG: 1, Sign.POS: 1, Sign.NONPOS: -1,
              Sign.NEG: -1}


class Contact(Enum):
    """Which contact states allow an interaction."""

    REQUIRED = "in contact"
    FORBIDDEN = "not in contact"
    EITHER = "either"


class Friction(Enum):
    """Coulomb constraint on the tangential force c_it, given c_in."""

    ZERO = "c_it = 0"
    LEFT_EDGE = "c_it = -mu c_in"  # sliding left (+t): friction along -t
    RIGHT_EDGE = "c_it = +mu c_in"  # sliding right (-t): friction along +t
    CONE = "|c_it| <= mu c_in"

    @property
    def edges(self) -> tuple[int, ...]:
        """Signs s of the friction-cone edges c = c_in (n + s mu t) this rule allows.

        The set of allowed (c_in, c_it) with c_in >= 0 is pos{(1, s mu) : s in edges}.
        """
        return {
            Friction.ZERO: (),
            Friction.LEFT_EDGE: (-1,),
            Friction.RIGHT_EDGE: (1,),
            Friction.CONE: (1, -1),
        }[self]


@dataclass(frozen=True)
class Interaction:
    """One row of Table 2.

    Parameters
    ----------
    letter : str
        The mode letter (``a``, ``s``, ``l``, ``r``, ``n``; ``?`` for a relaxation).
    name : str
        Its name (approach, separate, slide left, slide right, roll).
    contact : Contact
        Whether the fixel must touch, must not touch, or either.
    a_n_contact : Sign
        The condition on a_in when the fixel is in contact.
    a_n_free : Sign
        The condition on a_in when it is not (gap above the contact tolerance).
    a_t : Sign
        The condition on the tangential acceleration a_it.
    c_n : Sign
        The condition on the normal contact force c_in.
    c_t : Friction
        The rule for the tangential contact force c_it.
    """

    letter: str
    name: str
    contact: Contact
    a_n_contact: Sign  # a_in when the fixel is in contact
    a_n_free: Sign  # a_in when it is not (gap > tolerance)
    a_t: Sign
    c_n: Sign
    c_t: Friction

    def a_n(self, in_contact: bool) -> Sign:
        """The condition on the normal acceleration a_in for this contact state.

        Parameters
        ----------
        in_contact : bool
            Whether the fixel touches the workpiece.

        Returns
        -------
        Sign
            ``a_n_contact`` or ``a_n_free``.
        """
        return self.a_n_contact if in_contact else self.a_n_free

    def allowed(self, in_contact: bool) -> bool:
        """Whether the interaction can be asked for in this contact state.

        Parameters
        ----------
        in_contact : bool
            Whether the fixel touches the workpiece.

        Returns
        -------
        bool
            True when the letter is valid there.
        """
        if self.contact is Contact.EITHER:
            return True
        return (self.contact is Contact.REQUIRED) == in_contact

    @property
    def loaded(self) -> bool:
        """Whether the fixel can carry a contact force in this interaction."""
        return self.c_n is not Sign.ZERO


#: Table 2, one entry per letter; the one place the meaning of a letter is written.
MODE_TABLE: dict[str, Interaction] = {
    "a": Interaction("a", "approaching", Contact.FORBIDDEN, Sign.NEG, Sign.NEG,
                     Sign.FREE, Sign.ZERO, Friction.ZERO),
    "s": Interaction("s", "separating", Contact.EITHER, Sign.POS, Sign.NONNEG,
                     Sign.FREE, Sign.ZERO, Friction.ZERO),
    "l": Interaction("l", "sliding left", Contact.REQUIRED, Sign.ZERO, Sign.ZERO,
                     Sign.POS, Sign.NONNEG, Friction.LEFT_EDGE),
    "r": Interaction("r", "sliding right", Contact.REQUIRED, Sign.ZERO, Sign.ZERO,
                     Sign.NEG, Sign.NONNEG, Friction.RIGHT_EDGE),
    "n": Interaction("n", "rolling", Contact.REQUIRED, Sign.ZERO, Sign.ZERO,
                     Sign.ZERO, Sign.NONNEG, Friction.CONE),
}

LETTERS: str = "".join(MODE_TABLE)

#: Wildcards: "c" keeps contact with any tangential behaviour (l, r or n); "*" is any
#: interaction valid for the fixel's contact state. A mode with wildcards stands for the
#: union of the concrete modes it expands to (:func:`expand_mode`).
WILDCARDS: dict[str, str | None] = {"c": "lrn", "*": None}


def is_wildcard(mode: object) -> bool:
    """Whether ``mode`` is a mode string with at least one wildcard letter (WILDCARDS):
    it then stands for the union of the concrete modes it expands to. False for a
    non-string (which parse_mode refuses with a worded error).

    Parameters
    ----------
    mode : object
        Anything; a mode string is the interesting case.

    Returns
    -------
    bool
        True for a string with a ``c`` or ``*``.
    """
    return isinstance(mode, str) and any(ch in WILDCARDS for ch in mode)

_SIGN_PARTS = {Sign.ZERO: {0}, Sign.POS: {1}, Sign.NONNEG: {0, 1}, Sign.NEG: {-1},
               Sign.NONPOS: {-1, 0}, Sign.FREE: {-1, 0, 1}}


def _sign_hull(signs) -> Sign:
    """The smallest Sign (a convex set) containing every given one."""
    parts = set().union(*(_SIGN_PARTS[s] for s in signs))
    if {-1, 1} <= parts:
        return Sign.FREE
    return next(s for s, p in _SIGN_PARTS.items() if p == parts)


def _friction_hull(rules) -> Friction:
    edges = set().union(*(r.edges for r in rules))
    return {(): Friction.ZERO, (-1,): Friction.LEFT_EDGE, (1,): Friction.RIGHT_EDGE,
            (-1, 1): Friction.CONE}[tuple(sorted(edges))]


def relaxation(letters: str, in_contact: bool, label: str = "?") -> Interaction:
    """A convex relaxation of the union of several letters at one fixel.

    Each constraint of Table 2 is replaced by the convex hull of the letters' constraints
    (e.g. {s, l, r, n} in contact: a_in >= 0, a_it free, c_i in the friction cone). The
    set of wrenches of a mode using it contains the union of the modes it relaxes, which
    is what makes pruning the mode enumeration safe (:mod:`.classify`).

    Parameters
    ----------
    letters : str
        The letters whose union is relaxed.
    in_contact : bool
        Whether the fixel touches the workpiece (letters not allowed there are ignored).
    label : str, optional
        The relaxation's letter in the relaxed mode string.

    Returns
    -------
    Interaction
        The relaxed row.
    """
    rows = [MODE_TABLE[ch] for ch in letters if MODE_TABLE[ch].allowed(in_contact)]
    a_n = _sign_hull([r.a_n(in_contact) for r in rows])
    return Interaction(label, f"relaxation of {letters!r}", Contact.EITHER, a_n, a_n,
                       _sign_hull([r.a_t for r in rows]), _sign_hull([r.c_n for r in rows]),
                       _friction_hull([r.c_t for r in rows]))


#: Letters of a mode shown in an error message; a longer mode is abbreviated (a refused
#: request must not be echoed whole: a 100,000-letter mode made a 100 kB reply).
MODE_SHOWN_LETTERS = 40


def shown_mode(mode: object) -> str:
    """``repr(mode)`` for a message, abbreviated to its first MODE_SHOWN_LETTERS letters
    and its length when longer (``'nnnn...' (100000 letters)``).

    Parameters
    ----------
    mode : object
        What a user gave as a mode.

    Returns
    -------
    str
        Its repr, at most about 2 * MODE_SHOWN_LETTERS characters.
    """
    if isinstance(mode, str) and len(mode) > MODE_SHOWN_LETTERS:
        return f"{mode[:MODE_SHOWN_LETTERS]!r}... ({len(mode)} letters)"
    text = repr(mode)
    return text if len(text) <= 2 * MODE_SHOWN_LETTERS else text[:2 * MODE_SHOWN_LETTERS] + "..."


def allowed_letters(in_contact: bool) -> str:
    """Letters valid for a fixel in this contact state ("slrn" in contact, "as" free).

    Parameters
    ----------
    in_contact : bool
        Whether the fixel touches the workpiece.

    Returns
    -------
    str
        The letters, in the order of MODE_TABLE.
    """
    return "".join(k for k, v in MODE_TABLE.items() if v.allowed(in_contact))


def parse_mode(mode: str, in_contact: Sequence[bool], gaps: Sequence[float] | None = None,
               tolerance: float | None = None) -> tuple[Interaction, ...]:
    """Validate a mode string against the contact state (Table 2 of the paper).

    Parameters
    ----------
    mode : str
        One letter per fixel from ``aslrn`` (approaching, separating, sliding left,
        sliding right, rolling), no wildcard.
    in_contact : sequence of bool
        Whether each fixel touches the workpiece.
    gaps : sequence of float, optional
        The fixels' gaps (m), quoted in the error message.
    tolerance : float, optional
        The contact tolerance (m), quoted in the error message.

    Returns
    -------
    tuple of Interaction
        One per fixel: the letter's acceleration and force constraints (Table 2).

    Raises
    ------
    ModeSyntaxError
        ``mode`` is not a string, has a letter not in ``aslrn`` or the wrong length.
    ModeError
        A letter is not allowed in its fixel's contact state (``l``, ``r``, ``n`` need
        contact; ``a`` needs a free fixel): the message names the fixel (1-based, as in
        the paper), its gap and the contact tolerance.
    """
    if not isinstance(mode, str):
        raise ModeSyntaxError(
            f"mode must be a string of letters from {LETTERS!r}, got {shown_mode(mode)}")
    n = len(in_contact)
    if len(mode) != n:
        raise ModeSyntaxError(
            f"mode {shown_mode(mode)} has {len(mode)} letter(s) but the scene has {n} fixel(s); "
            f"give one letter from {LETTERS!r} (or a wildcard c, *) per fixel, in fixel order")
    out = []
    for i, (ch, touching) in enumerate(zip(mode, in_contact)):
        if ch not in MODE_TABLE:
            raise ModeSyntaxError(
                f"mode {shown_mode(mode)}: letter {ch!r} at fixel {i + 1} is not one of {LETTERS!r} "
                "(a approach, s separate, l slide left, r slide right, n roll)")
        inter = MODE_TABLE[ch]
        if not inter.allowed(touching):
            state = "in contact" if touching else "not in contact"
            detail = ""
            if gaps is not None and tolerance is not None:
                detail = f" (gap {gaps[i]:.6g} m, contact tolerance {tolerance:.3g} m)"
            raise ModeError(
                f"mode {shown_mode(mode)}: fixel {i + 1} is {state}{detail}, so {inter.name!r} "
                f"({ch!r}) is not possible; allowed letters there: "
                f"{allowed_letters(touching)!r}")
        out.append(inter)
    return tuple(out)


def _choices(mode: str, in_contact: Sequence[bool], gaps: Sequence[float] | None,
             tolerance: float | None) -> list[str]:
    """The letters each fixel of ``mode`` may take (one string per fixel)."""
    if not isinstance(mode, str):
        raise ModeSyntaxError(
            f"mode must be a string of letters from {LETTERS!r}, got {shown_mode(mode)}")
    if len(mode) != len(in_contact):
        parse_mode(mode, in_contact, gaps, tolerance)  # the length error, worded once
    choices = []
    for i, ch in enumerate(mode):
        if ch in WILDCARDS:
            touching = in_contact[i]
            allowed = allowed_letters(touching)
            letters = allowed if WILDCARDS[ch] is None else WILDCARDS[ch]
            if not any(x in allowed for x in letters):
                detail = "" if gaps is None else f" (gap {gaps[i]:.6g} m, contact tolerance " \
                    f"{tolerance:.3g} m)"
                raise ModeError(f"mode {shown_mode(mode)}: wildcard {ch!r} at fixel {i + 1} needs contact "
                                f"but the fixel is not in contact{detail}")
            choices.append("".join(x for x in letters if x in allowed))
        else:
            choices.append(ch)
    return choices


def count_concrete_modes(mode: str, in_contact: Sequence[bool],
                         gaps: Sequence[float] | None = None,
                         tolerance: float | None = None) -> int:
    """How many concrete modes :func:`expand_mode` would return, without expanding
    (the product of the per-fixel choices); raises ModeError like it.

    Parameters
    ----------
    mode : str
        A mode, wildcards allowed.
    in_contact : sequence of bool
        Whether each fixel touches the workpiece.
    gaps : sequence of float, optional
        The fixels' gaps (m), quoted in an error message.
    tolerance : float, optional
        The contact tolerance (m), quoted in an error message.

    Returns
    -------
    int
        The number of concrete modes.

    Raises
    ------
    ModeError
        As :func:`expand_mode`.
    """
    return math.prod(len(c) for c in _choices(mode, in_contact, gaps, tolerance))


def expand_mode(mode: str, in_contact: Sequence[bool], gaps: Sequence[float] | None = None,
                tolerance: float | None = None) -> list[str]:
    """The concrete modes a mode string with wildcards ("c", "*") stands for.

    Raises ModeError like :func:`parse_mode` (a "c" at a fixel not in contact is an error).
    Use :func:`count_concrete_modes` first to bound the work.

    Parameters
    ----------
    mode : str
        A mode, wildcards allowed: ``c`` (l, r or n; needs contact), ``*`` (any valid
        letter).
    in_contact : sequence of bool
        Whether each fixel touches the workpiece.
    gaps : sequence of float, optional
        The fixels' gaps (m), quoted in an error message.
    tolerance : float, optional
        The contact tolerance (m), quoted in an error message.

    Returns
    -------
    list of str
        The concrete modes, in lexicographic order of the per-fixel choices.

    Raises
    ------
    ModeSyntaxError
        ``mode`` is not a string, has a letter not allowed or the wrong length.
    ModeError
        A letter or wildcard is not possible in its fixel's contact state.
    """
    choices = _choices(mode, in_contact, gaps, tolerance)
    concrete = ["".join(c) for c in itertools.product(*choices)]
    for m in concrete[:1]:
        parse_mode(m, in_contact, gaps, tolerance)  # length and letter errors
    return concrete


def enumerate_modes(in_contact: Sequence[bool]) -> Iterator[str]:
    """Every valid augmented mode of a contact state, in lexicographic order.

    Parameters
    ----------
    in_contact : sequence of bool
        Whether each fixel touches the workpiece.

    Yields
    ------
    str
        A mode string: ``a`` or ``s`` for a free fixel; ``s``, ``l``, ``r`` or ``n`` for a
        fixel in contact (Table 2).
    """
    choices = [allowed_letters(t) for t in in_contact]
    for combo in itertools.product(*choices):
        yield "".join(combo)
