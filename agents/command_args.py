"""argparse types the agents' commands share."""

from __future__ import annotations

import argparse
import json
from collections.abc import Mapping
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


def settings_label(settings: Mapping[str, Any]) -> str:
    """``{"fast_free_motion": True}`` -> ``"fast_free_motion=true"`` (keys sorted, values as
    JSON, which ``parse_setting`` reads back): how an agent or a benchmark's subject run under
    changed settings is named."""
    return ", ".join(f"{key}={json.dumps(settings[key])}" for key in sorted(settings))
