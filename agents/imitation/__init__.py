"""Learning from the GPIS probe planner: its demonstrations (``demonstrations``), behaviour
cloning into the PPO recipe's own network (``cloning``) and the imitation run with DAgger
(``training``, under the CLI ``python -m agents.imitate``).

The ``imitation`` library is not used: its releases pin gymnasium 0.29 and
stable-baselines3 2.2, older than the ones this project runs on."""
