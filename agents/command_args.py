"""argparse types the agents' commands share."""

from __future__ import annotations

import argparse
from typing import Any

import yaml


def parse_setting(text: str) -> tuple[str, Any]:
    """``key=value`` with the value read as YAML (``max_steps=64``, ``grid_shape=[36,72]``,
    ``cloning={epochs: 10}``); a list is returned as a tuple."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"expected key=value, got {text!r}")
    parsed = yaml.safe_load(value)
    return key, tuple(parsed) if isinstance(parsed, list) else parsed
