# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Mode strings: validation errors name the fixel, its gap and the tolerance; enumeration."""

import pytest

from wrenchcone_ros.core import ModeError, default_scene, enumerate_modes, wrench_cone
from wrenchcone_ros.core.modes import MODE_TABLE, ModeSyntaxError, allowed_letters, parse_mode


def test_allowed_letters():
    assert allowed_letters(True) == "slrn"
    assert allowed_letters(False) == "as"


def test_enumerate():
    modes = list(enumerate_modes([True, False]))
    assert modes == [a + b for a in "slrn" for b in "as"]
    assert len(list(enumerate_modes([True] * 3 + [False] * 2))) == 4 ** 3 * 2 ** 2


@pytest.mark.parametrize("mode, match", [
    ("n", r"1 letter\(s\) but the scene has 2"),
    ("nax", r"3 letter"),
    ("nx", r"letter 'x' at fixel 2"),
    ("aa", r"fixel 1 is in contact \(gap 0 m, contact tolerance 1e-09 m\).*'slrn'"),
    ("nn", r"fixel 2 is not in contact \(gap 0\.001 m"),
    ("NA", "letter 'N'"),
])
def test_bad_modes(mode, match):
    with pytest.raises(ModeError, match=match):
        wrench_cone(default_scene(), mode)


def test_mode_must_be_a_string():
    with pytest.raises(ModeError, match="must be a string"):
        wrench_cone(default_scene(), 3)


def test_every_letter_is_in_the_table():
    assert set(MODE_TABLE) == set("aslrn")


@pytest.mark.parametrize("mode,contact", [
    ("na", (True, False)), ("c*", (True, False)), ("**", (True, True)),
    ("*c*s", (False, True, True, True)), ("cccc", (True,) * 4), ("*" * 6, (True, False) * 3)])
def test_count_concrete_modes_is_the_length_of_the_expansion(mode, contact):
    from wrenchcone_ros.core.modes import count_concrete_modes, expand_mode

    assert count_concrete_modes(mode, contact) == len(expand_mode(mode, contact))


def test_count_concrete_modes_never_expands():
    """4^40 concrete modes are counted at once (an expansion would never finish)."""
    from wrenchcone_ros.core.modes import count_concrete_modes

    assert count_concrete_modes("*" * 40, (True,) * 40) == 4 ** 40
    with pytest.raises(ModeError):
        count_concrete_modes("c*", (False, True))  # c needs contact, as in expand_mode


def test_a_long_mode_is_abbreviated_in_its_error_message():
    """A refused 100,000-letter mode must not be echoed whole (a node reply carried
    about 100 kB of it): the message shows its start and says how long it is."""
    in_contact = [True, True, False]
    for bad in ("x" * 100_000, "n" * 100_000, "nnq" + "n" * 99_997):
        with pytest.raises(ModeSyntaxError) as info:
            parse_mode(bad, in_contact)
        text = str(info.value)
        assert len(text) < 400, len(text)
        assert "100000 letters" in text
    with pytest.raises(ModeSyntaxError) as info:
        parse_mode("nnq", in_contact)  # short modes are shown whole, as before
    assert "'nnq'" in str(info.value)
