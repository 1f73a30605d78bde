"""rl-baselines3-zoo config: agents/hyperparams/recurrent_ppo.yml's recipe for the none map
(see agents/sb3/zoo.py; run rl_zoo3.train from the repository's root)."""

from agents.sb3.zoo import zoo_hyperparams

hyperparams = zoo_hyperparams("recurrent_ppo", "none")
