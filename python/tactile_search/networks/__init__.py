"""The networks of the published agents, as stable-baselines3 policies and features
extractors: the map encoders (``encoders``), the joint probe head (``joint_probe``), the
spatial probe policy (``spatial_probe``), and the recipe names that load them
(``recipe_classes``). They live in the installed package so that a published ``model.zip``
loads wherever ``tactile_search`` is installed with its ``agents`` extra (torch and SB3),
without this repository on the path.

Importing this package loads no torch (each module does), but refuses, naming the extra,
where torch or SB3 is not installed. It sets ``OMP_WAIT_POLICY`` first (a value the user
set is kept): torch's OpenMP threads busy-wait between parallel regions by default, and
where the cores are few they then fight the env batch's worker threads for them, and PPO
on the Rust batch runs several times slower (``python -m benchmarks.ppo_env_overhead``).
It must be set before torch loads its OpenMP runtime.
"""

import importlib.util
import os

_MISSING = [name for name in ("torch", "stable_baselines3") if not importlib.util.find_spec(name)]
if _MISSING:
    raise ModuleNotFoundError(
        f"tactile_search.networks needs {' and '.join(_MISSING)}, which is not installed: "
        "pip install 'tactile_search[agents]'",
        name=_MISSING[0],
    )

os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
