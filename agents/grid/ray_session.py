"""One way to reach Ray for everything in ``agents`` that runs on it (the experiment grid,
RLlib): the cluster at an address, or else a fresh Ray on this machine.

With ``address`` or ``RAY_ADDRESS`` set, ``connect`` joins that cluster (``ray start --head``
prints the address); with neither, it starts Ray here with this machine's cores, and never
joins a cluster that happens to run on this machine (``ray.init()`` alone would). The
``agents`` package is shipped to the workers with the job (Ray's ``py_modules``), so they
import the driver's code wherever they run; ``tactile_search`` itself, a compiled extension,
must be installed on every node.
"""

from __future__ import annotations

import os
from pathlib import Path

import ray

import agents


def connect(address: str | None = None, num_cpus: int | None = None) -> bool:
    """Connects this process to Ray unless it is connected already; returns whether this
    call connected it (then the caller may ``ray.shutdown()`` when done).

    ``address``: a cluster's address, or ``"local"`` for a fresh Ray here; default
    ``RAY_ADDRESS``, else ``"local"``. ``num_cpus``: the CPUs of a fresh local Ray (default:
    every core); ignored when joining a cluster."""
    if ray.is_initialized():
        return False
    address = address or os.environ.get("RAY_ADDRESS") or "local"
    ray.init(
        address=address,
        num_cpus=num_cpus if address == "local" else None,
        include_dashboard=False,
        runtime_env={
            "py_modules": [str(Path(agents.__file__).parent)],
            "excludes": ["__pycache__"],
            # Torch's OpenMP threads must wait passively (agents.train says why); set
            # before any worker loads torch. A value set here is kept.
            "env_vars": {"OMP_WAIT_POLICY": os.environ.get("OMP_WAIT_POLICY", "PASSIVE")},
        },
        logging_level="WARNING",
    )
    return True
