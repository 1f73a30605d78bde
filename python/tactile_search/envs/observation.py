"""The observation layout, read from the core (``_core.observation_layout()``): the index of
each proprio entry by name, the map channels, and the docstring tables generated from them.
Decoders index by name (``proprio[PROPRIO["x"]]``), so the core's table is the only copy.
"""

from __future__ import annotations

from typing import Any

from tactile_search import _core
from tactile_search.envs.config import arguments_table, markdown_table

LAYOUT: dict[str, Any] = _core.observation_layout()
#: Index of each proprio entry, by name (``x``, ``y``, ``cos_yaw``, ... ``time_left``).
PROPRIO: dict[str, int] = {field["name"]: field["index"] for field in LAYOUT["proprio"]}
PROPRIO_LEN = len(PROPRIO)
#: Channel index of each map channel, by (map mode, channel name).
MAP_CHANNELS: dict[tuple[str, str], int] = {
    (c["mode"], c["name"]): c["channel"] for c in LAYOUT["map_channels"]
}
#: Every key of ``info``: name -> (numpy dtype, doc).
STEP_INFO: dict[str, tuple[str, str]] = {
    f["name"]: (f["dtype"], f["doc"]) for f in _core.step_info_fields()
}


def proprio_table() -> str:
    """The proprio entries as a markdown table (for the env's docstring)."""
    return markdown_table(
        ["index", "name", "scale", "meaning"],
        ([f["index"], f"``{f['name']}``", f["scale"], f["meaning"]] for f in LAYOUT["proprio"]),
    )


def map_channel_table() -> str:
    """The map channels as a markdown table (for the env's docstring)."""
    return markdown_table(
        ["map", "channel", "name", "pixel value"],
        (
            [f"``{c['mode']}``", c["channel"], f"``{c['name']}``", c["encoding"]]
            for c in LAYOUT["map_channels"]
        ),
    )


def fill_docstring(doc: str) -> str:
    """``doc`` with its ``{proprio_table}``, ``{map_channel_table}`` and ``{settings_table}``
    lines replaced by the tables (made from the core's), indented like the lines they
    replace."""
    out = []
    for line in doc.splitlines():
        stripped = line.strip()
        table = {
            "{proprio_table}": proprio_table,
            "{map_channel_table}": map_channel_table,
            "{settings_table}": arguments_table,
        }
        if stripped in table:
            indent = line[: len(line) - len(line.lstrip())]
            out += [indent + row for row in table[stripped]().splitlines()]
        else:
            out.append(line)
    return "\n".join(out)
