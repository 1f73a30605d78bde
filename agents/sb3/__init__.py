"""stable-baselines3 agents: the recipes, the map encoders, the training env and callbacks,
training itself (``training.train``) and a trained model as an evaluation agent
(``learned.LearnedAgent``)."""

import os

# Torch's OpenMP threads busy-wait between parallel regions by default; where the cores are
# few they then fight the environment batch's worker threads (and other jobs) for them, and
# PPO on the Rust batch runs several times slower. Passive waiting must be set before torch
# loads its OpenMP runtime (`python -m benchmarks.ppo_env_overhead` measures what the env
# costs PPO). A value the user set is kept. Set on importing this package, before any of its
# modules loads torch.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
