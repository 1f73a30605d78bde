"""stable-baselines3 agents: the recipes, the map encoders, the training env and callbacks,
training itself (``training.train``) and a trained model as an evaluation agent
(``learned.LearnedAgent``)."""

import os

# Torch's OpenMP threads busy-wait between parallel regions by default; on this 2-core
# machine they then fight the environment batch's worker threads (and other jobs) for the
# cores. Passive waiting, set before torch loads its OpenMP runtime, measured: PPO with the
# GPIS recipe on the Rust batch 417 vs ~100 steps/s (torch threads 2), and 0.81 instead of
# 0.52 of the speed on a zero-cost VecEnv (`python -m benchmarks.ppo_env_overhead`). A value
# the user set is kept. Set on importing this package, before any of its modules loads torch.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
