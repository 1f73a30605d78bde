"""stable-baselines3 agents: the recipes, the training env and callbacks, training itself
(``training.train``) and a trained model as an evaluation agent (``learned.LearnedAgent``).
The networks they train are the installed package's (``tactile_search.networks``), whose
import also sets torch's OpenMP threads to wait passively before any module here loads
torch."""

import tactile_search.networks  # noqa: F401  (OMP_WAIT_POLICY, before torch loads)
