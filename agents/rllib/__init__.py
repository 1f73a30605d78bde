"""RLlib's PPO (new API stack) on the Rust vector env: the env for RLlib's env runners
(``env``), the policy module (``module``) and the training loop (``training``)."""

import os

# As in agents.sb3: torch's OpenMP threads spin between regions by default and then fight
# the env runners for this machine's cores. Set before torch loads; a user's value is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
