# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""numbers.py: the wrench rescaling rule shared by the CLI and the node."""

import sys
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from wrenchcone_ros.core.numbers import rescale_wrench
from wrenchcone_ros.core.tolerances import WRENCH_RESCALE_ABOVE

finite = st.floats(allow_nan=False, allow_infinity=False)


@given(st.lists(finite, min_size=3, max_size=6))
def test_rescaling_is_one_exact_positive_power_of_two(values):
    """Checked in exact rational arithmetic: every component is multiplied by the same
    power of two (so direction, signs and zeros are kept exactly, up to the rounding of
    a component pushed below the smallest normal double), and only when the largest
    magnitude is outside [1 / WRENCH_RESCALE_ABOVE, WRENCH_RESCALE_ABOVE]."""
    out = rescale_wrench(values)
    assert len(out) == len(values) and all(isinstance(v, float) for v in out)
    big = max(abs(v) for v in values)
    if not (big > WRENCH_RESCALE_ABOVE or 0.0 < big < 1.0 / WRENCH_RESCALE_ABOVE):
        assert out == tuple(values)
        return
    k = max(range(len(values)), key=lambda i: abs(values[i]))
    r = Fraction(out[k]) / Fraction(values[k])  # the factor, from the largest component
    assert r > 0 and (r.numerator == 1 or r.denominator == 1)
    assert bin(r.numerator * r.denominator).count("1") == 1  # a power of two
    for o, v in zip(out, values):
        exact = Fraction(v) * r
        if abs(exact) >= Fraction(sys.float_info.min):
            assert Fraction(o) == exact  # a normal double: exactly the same direction
        else:  # scaled into the subnormal range: rounded to its spacing 2^-1074
            assert abs(Fraction(o) - exact) <= Fraction(1, 2 ** 1074)
    assert Fraction(1, 2) <= max(abs(Fraction(o)) for o in out) < 1


@pytest.mark.parametrize("values", [(0.0, 0.0, 0.0), (1.0, -2.0, 3.0),
                                    (WRENCH_RESCALE_ABOVE, 0.0, -1.0),
                                    (1.0 / WRENCH_RESCALE_ABOVE, 0.0, 0.0)])
def test_ordinary_wrenches_are_unchanged(values):
    assert rescale_wrench(values) == values


def test_the_wrench_of_the_first_hour_report():
    out = rescale_wrench((1e200, -1.0, -1.0))
    assert 0.5 <= out[0] < 1.0 and out[1] < 0 and out[2] < 0 and out[1] == out[2]
