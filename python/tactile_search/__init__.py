"""tactile_search: mechanical search by touch, with a GPIS map from vision and touch.

The Rust core (``tactile_search._core``) runs the GPIS, the physics and the episodes; this
package is its Python face.
"""

import gymnasium

from tactile_search._core import __version__
from tactile_search.envs import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.gpis import Gpis

#: The registered id of the environment; import it rather than typing the string.
ENV_ID = "tactile_search/CupboardSearch-v0"

__all__ = ["ENV_ID", "CupboardSearchEnv", "CupboardSearchVectorEnv", "Gpis", "__version__"]

# No max_episode_steps here: the time limit is the episode's own `max_steps` (default from
# the core), reported by the core as `truncated`, so `gymnasium.make(..., max_steps=N)`
# truncates at N in the single and the vector envs alike; a registered limit would make
# `make` add a TimeLimit wrapper, a second limit. Each made env declares its limit in its
# own spec (`spec.max_episode_steps == max_steps`, tactile_search/envs/time_limit.py).
if ENV_ID not in gymnasium.registry:
    gymnasium.register(
        id=ENV_ID,
        entry_point="tactile_search.envs.cupboard_search:CupboardSearchEnv",
        vector_entry_point="tactile_search.envs.vector:CupboardSearchVectorEnv",
    )
