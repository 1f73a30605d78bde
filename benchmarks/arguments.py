"""argparse types the benchmark commands share."""

from __future__ import annotations

import argparse

from tactile_search._validation import as_count


def positive_int(text: str) -> int:
    """argparse type: an int >= 1 (the project's one count check, ``as_count``)."""
    try:
        return as_count("the value", int(text))
    except ValueError as err:
        raise argparse.ArgumentTypeError(f"expected a positive int, got {text!r}: {err}") from err
