"""The settings of the cupboard-search environments, as the Rust core declares them.

``CupboardSearchConfig`` is made from the core's settings table
(``tactile_search._core.EpisodeConfig.settings()``): one frozen dataclass field per setting,
with the core's type, default, range and doc (in the field's ``metadata``). Nothing is typed
here: adding a setting in Rust adds it to this class, to the environments' signatures and
to their docs. Building a config checks every value once, in the core, which keeps the
checked config (``core``) for the batches made from it: ``TypeError`` for a key that is no
setting or a wrong type, ``ValueError`` for a value out of range, each naming the key.
"""

from __future__ import annotations

import dataclasses
import inspect
import operator
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any, cast

from tactile_search import _core

#: The core's settings table: one dict per setting (key, type, default, range, choices, doc).
SETTINGS: tuple[dict[str, Any], ...] = tuple(_core.EpisodeConfig.settings())
#: The map modes, as the core names them (``gpis``, ``occupancy``, ``none``).
MAP_MODES: tuple[str, ...] = next(s["choices"] for s in SETTINGS if s["key"] == "map")
#: The action modes, as the core names them (``wrist``, ``probe``).
ACTION_MODES: tuple[str, ...] = next(s["choices"] for s in SETTINGS if s["key"] == "action_mode")
#: The reward terms' settings (the core names them ``reward_*``).
REWARD_KEYS: frozenset[str] = frozenset(
    s["key"] for s in SETTINGS if s["key"].startswith("reward_")
)
#: The keys that configure the physical scene (a subset of ``SETTINGS``).
SCENE_KEYS: frozenset[str] = frozenset(s["key"] for s in _core.Scene.settings())


def _plain(value: Any) -> bool:
    """A built-in scalar, or a tuple of them: hashable and equal to what it means."""
    if isinstance(value, tuple):
        return all(_plain(item) for item in value)
    return value is None or type(value) in (bool, int, float, str)


def _check(config: Any) -> None:
    """Checks every value once, in the core, and keeps the checked config as ``core``."""
    given = config.settings_dict()
    _keep(config, given, _core.EpisodeConfig(given, caller="CupboardSearchConfig"))


def _keep(config: Any, given: dict[str, Any], core: _core.EpisodeConfig) -> None:
    """Keeps ``core`` (the checked ``given`` settings) in ``config``; a value given as
    another kind of sequence or as a numpy scalar (a list from YAML, an array,
    ``np.float32``) is replaced by the core's reading of it, so that the frozen config stays
    hashable and equal to one built from tuples and Python numbers."""
    object.__setattr__(config, "core", core)
    if not all(_plain(value) for value in given.values()):
        resolved: dict[str, Any] = dict(core.as_dict())
        for key, value in given.items():
            if not _plain(value):
                object.__setattr__(config, key, resolved[key])


def settings_dict(self: Any) -> dict[str, Any]:
    """Every setting by key."""
    return {s["key"]: getattr(self, s["key"]) for s in SETTINGS}


def scene_dict(self: Any) -> dict[str, Any]:
    """The scene's settings by key (what ``_core.Scene(seed, config=...)`` takes)."""
    return {key: value for key, value in self.settings_dict().items() if key in SCENE_KEYS}


def make_batch(self: Any, num_envs: int, threads: int | None = None) -> _core.EpisodeBatch:
    """The Rust batch of ``num_envs`` episodes of these settings, none started (a reset
    starts each)."""
    return _core.EpisodeBatch(self.core, num_envs, threads=threads)


if TYPE_CHECKING:

    class CupboardSearchConfig:
        """For type checkers: the class is made at run time from the core's settings table
        (below), so its fields are read as ``Any``."""

        core: _core.EpisodeConfig

        def __init__(self, **settings: Any) -> None: ...
        def __getattr__(self, key: str) -> Any: ...
        def settings_dict(self) -> dict[str, Any]: ...
        def scene_dict(self) -> dict[str, Any]: ...
        def make_batch(self, num_envs: int, threads: int | None = None) -> _core.EpisodeBatch: ...

else:
    CupboardSearchConfig = dataclasses.make_dataclass(
        "CupboardSearchConfig",
        [
            (
                s["key"],
                s["type"],
                dataclasses.field(
                    default=s["default"],
                    metadata={"doc": s["doc"], "range": s["range"], "choices": s["choices"]},
                ),
            )
            for s in SETTINGS
        ],
        frozen=True,
        kw_only=True,
        namespace={
            "__doc__": (
                "Every setting of a cupboard-search environment (the core's settings table)."
            ),
            "__post_init__": _check,
            "settings_dict": settings_dict,
            "scene_dict": scene_dict,
            "make_batch": make_batch,
            "__module__": __name__,
        },
    )


def config_for(owner: str, settings: dict[str, Any]) -> Any:
    """``CupboardSearchConfig(**settings)`` for the class the user made (``owner``): the
    core's ``TypeError`` for a keyword that is no setting names ``owner`` and the closest
    settings, not the config class the user never named."""
    core = _core.EpisodeConfig(cast("_core.EpisodeSettings", settings), caller=owner)
    # The dataclass's fields without its __init__ (which would check them again).
    config: Any = object.__new__(CupboardSearchConfig)
    for s in SETTINGS:
        object.__setattr__(config, s["key"], settings.get(s["key"], s["default"]))
    _keep(config, settings, core)
    return config


def checked_layout_seeds(layout_seeds: Any) -> tuple[int, int]:
    """``layout_seeds`` as ``(low, high)`` ints: the range ``[low, high)`` within
    ``[0, 2**64)`` that a vector env draws its episodes' layout seeds from."""
    try:
        low, high = (operator.index(bound) for bound in layout_seeds)
    except (TypeError, ValueError):
        raise TypeError(
            f"layout_seeds must be a pair of ints (low, high), got {layout_seeds!r}"
        ) from None
    if not 0 <= low < high <= 2**64:
        raise ValueError(
            f"layout_seeds must be (low, high) with 0 <= low < high <= 2**64, got {layout_seeds}"
        )
    return low, high


def settings_parameters() -> list[inspect.Parameter]:
    """One keyword-only parameter per setting, with the core's default and type."""
    return [
        inspect.Parameter(
            s["key"], inspect.Parameter.KEYWORD_ONLY, default=s["default"], annotation=s["type"]
        )
        for s in SETTINGS
    ]


def with_settings_signature(function: Callable[..., Any]) -> Callable[..., Any]:
    """Gives ``function`` (which takes ``**settings``) a signature that lists its own
    parameters and then every setting with the core's default, so ``help()`` and
    ``inspect.signature`` show them all."""
    own = [
        p
        for p in inspect.signature(function).parameters.values()
        if p.kind is not inspect.Parameter.VAR_KEYWORD
    ]
    function.__signature__ = inspect.Signature([*own, *settings_parameters()])  # type: ignore[attr-defined]
    return function


def markdown_table(header: list[str], rows: Iterable[list[object]]) -> str:
    """A Markdown table (for the generated docstring tables); ``|`` in a cell is escaped."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        lines.append("| " + " | ".join(str(cell).replace("|", "\\|") for cell in row) + " |")
    return "\n".join(lines)


def arguments_table() -> str:
    """A Markdown table of every setting: key, type, default, range and meaning."""

    def valid(s: dict[str, Any]) -> str:
        return s["range"] or " / ".join(repr(c) for c in s["choices"])

    return markdown_table(
        ["argument", "type", "default", "range", "meaning"],
        (
            [f"``{s['key']}``", f"``{s['type']}``", f"``{s['default']!r}``", valid(s), s["doc"]]
            for s in SETTINGS
        ),
    )
