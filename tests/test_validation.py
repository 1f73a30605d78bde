"""The one check of a count (``tactile_search._validation.as_count``), which the agents'
commands, training and encoders use for every thread count, interval and width, and the one
check of a flag (``as_bool``)."""

from __future__ import annotations

import numpy as np
import pytest

from tactile_search._validation import MAX_COUNT, as_bool, as_count


def test_a_count_comes_back_as_a_plain_int() -> None:
    assert as_count("n", 3) == 3 and type(as_count("n", np.int64(3))) is int
    assert as_count("n", 0, minimum=0) == 0 and as_count("n", MAX_COUNT) == MAX_COUNT


@pytest.mark.parametrize("value", [True, 2.0, "2", None])
def test_anything_but_an_integer_is_a_type_error_naming_it(value: object) -> None:
    with pytest.raises(TypeError, match=r"^threads must be an integer, got "):
        as_count("threads", value)


def test_a_count_below_its_minimum_or_beyond_64_bits_is_a_value_error() -> None:
    with pytest.raises(ValueError, match=r"^threads must be at least 1, got 0$"):
        as_count("threads", 0)
    with pytest.raises(ValueError, match=r"^width must be at least 0, got -1$"):
        as_count("width", -1, minimum=0)
    with pytest.raises(ValueError, match="64 bits"):
        as_count("rows", MAX_COUNT + 1)


def test_a_flag_comes_back_as_a_plain_bool() -> None:
    assert as_bool("resume", True) is True and as_bool("resume", np.bool_(False)) is False


@pytest.mark.parametrize("value", [0, 1, "false", None, 1.0])
def test_anything_but_a_bool_is_a_type_error_naming_it(value: object) -> None:
    with pytest.raises(TypeError, match=r"^mirror must be a bool, got "):
        as_bool("mirror", value)
