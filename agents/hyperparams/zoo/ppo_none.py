"""rl-baselines3-zoo config: agents/hyperparams/ppo.yml's recipe for the none map
(see agents/sb3/zoo.py; run rl_zoo3.train from the repository's root).

Evaluate its agent sampled, ``python -m rl_zoo3.enjoy ... --stochastic``: the most likely
probe of an agent trained from scratch repeats until the time limit (agents/sb3/zoo.py)."""

from agents.sb3.zoo import zoo_hyperparams

hyperparams = zoo_hyperparams("ppo", "none")
