"""tactile_search: mechanical search by touch, with a GPIS map from vision and touch.

The Rust core (``tactile_search._core``) runs the GPIS, the physics and the episodes; this
package is its Python face.
"""

from importlib.metadata import version

import gymnasium

from tactile_search._core import registered_envs
from tactile_search.envs import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.gpis import Gpis

#: The installed package's version, from its metadata: maturin writes Cargo.toml's workspace
#: version there, the one place it is typed (CHANGELOG.md says what each version holds).
__version__ = version("tactile_search")
#: The registered id of the search task at the defaults; import it rather than typing the
#: string.
ENV_ID = "tactile_search/CupboardSearch-v0"
#: Every registered id (search, identify and their tiers), from the core's table.
ENV_IDS: tuple[str, ...] = tuple(env["id"] for env in registered_envs())

__all__ = [
    "ENV_ID",
    "ENV_IDS",
    "CupboardSearchEnv",
    "CupboardSearchVectorEnv",
    "Gpis",
    "__version__",
]

# No max_episode_steps here: the time limit is the episode's own `max_steps` (default from
# the core), reported by the core as `truncated`, so `gymnasium.make(..., max_steps=N)`
# truncates at N in the single and the vector envs alike; a registered limit would make
# `make` add a TimeLimit wrapper at it, a second limit. Each made env declares its limit in
# its own spec (`spec.max_episode_steps == max_steps`), and `make(..., max_episode_steps=N)`
# makes the env with `max_steps` N under a TimeLimit at N (tactile_search/envs/time_limit.py).
# Every registered id is the same env class with the settings of its task and tier, from the
# core's table (``_core.registered_envs()``); a user's keyword arguments go over them.
for _env in registered_envs():
    if _env["id"] not in gymnasium.registry:
        gymnasium.register(
            id=_env["id"],
            entry_point="tactile_search.envs.cupboard_search:CupboardSearchEnv",
            vector_entry_point="tactile_search.envs.vector:CupboardSearchVectorEnv",
            kwargs=dict(_env["settings"]),
        )
del _env
