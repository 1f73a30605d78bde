"""rl-baselines3-zoo config: agents/hyperparams/ppo.yml's recipe for the gpis map
(see agents/sb3/zoo.py; run rl_zoo3.train from the repository's root).

Evaluate its agent sampled (``python -m rl_zoo3.enjoy ... --stochastic``), not by rl-zoo3's
default, the policy's most likely action: rl-zoo3 trains the recipe's network from scratch,
without the clone of the probe planner that the recipe's ``deterministic_evaluation: true``
is for, and the most likely action of an agent trained from scratch in the probe mode repeats
one probe until the time limit (docs/results/ablations_imitation/ppo_spatial.yml: 63 %
sampled against 47 % on 100 validation layouts). rl-zoo3's evaluations during training
(``--eval-freq``) always take the most likely action, and so does its ``best_model``."""

from agents.sb3.zoo import zoo_hyperparams

hyperparams = zoo_hyperparams("ppo", "gpis")
