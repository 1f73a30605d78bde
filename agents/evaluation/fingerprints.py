"""What produced an evaluation row: a hash of the installed package, the agents' code and a
learned agent's model and settings. Rows of another fingerprint are not reused."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import tactile_search  # also registers the environment
from agents.evaluation.agent_specs import _deterministic
from agents.evaluation.ensemble import ensemble_members
from agents.run_dir import model_digest, model_path, read_run_config
from agents.sb3.learned import evaluation_env_kwargs
from agents.scripted import SCRIPTED_AGENTS

# What the evaluation-time variants of an agent (a blanked map, mode_unstuck) are built on.
WRAPPER_FILE = "wrapped_agent.py"


def _digest(paths: Sequence[Path], root: Path) -> bytes:
    sha = hashlib.sha256()
    for path in sorted(paths):
        sha.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return sha.digest()


def code_fingerprints(
    agent_specs: Sequence[str],
    actions: str = "recipe",
    blanked: Sequence[str] = (),
    env_settings: Mapping[str, Any] | None = None,
) -> dict[str, str]:
    """What produced an agent's rows, per spec: a hash of the installed tactile_search
    package (its Python files and compiled core), the agents' code (``agents/scripted/``,
    ``agents/rollout.py`` and ``agents/sb3/learned.py``) and, for a learned agent, its
    ``model.zip``'s contents (``model_digest``), and the map channels it reads blanked
    (``blanked``, with ``agents/evaluation/map_ablation.py``), and the environment's settings
    changed for every agent (``env_settings``). Rows of another fingerprint are not reused."""
    package = Path(tactile_search.__file__).parent
    env_files = [
        p
        for p in package.rglob("*")
        if p.is_file() and p.suffix in (".py", ".so", ".pyd") and "__pycache__" not in p.parts
    ]
    agents_dir = Path(__file__).parents[1]
    agent_files = [
        *(agents_dir / "scripted").glob("*.py"),
        agents_dir / "rollout.py",
        agents_dir / "sb3" / "learned.py",
    ]
    if blanked:
        agent_files += [agents_dir / "evaluation" / f for f in ("map_ablation.py", WRAPPER_FILE)]
    base = _digest(env_files, package) + _digest(agent_files, agents_dir)
    if blanked:
        base += json.dumps(sorted(blanked)).encode()
    if env_settings:
        base += json.dumps(sorted(env_settings.items())).encode()
    fingerprints = {}
    for spec in agent_specs:
        sha = hashlib.sha256(base)
        members = ensemble_members(spec)
        if members is not None:  # every member's model and settings, and how they combine
            sha.update((agents_dir / "evaluation" / "ensemble.py").read_bytes())
            for member in members:
                _add_run(sha, member)
        elif spec not in SCRIPTED_AGENTS:
            config = _add_run(sha, Path(spec))
            # Whether its actions are the policy's mode or samples from it.
            deterministic = _deterministic(actions)
            if deterministic is None:
                deterministic = config["hyperparams"].get("deterministic_evaluation", True)
            sha.update(b"deterministic" if deterministic else b"sampled")
            if actions == "mode_unstuck":
                for name in ("unstuck_mode.py", WRAPPER_FILE):
                    sha.update(b"unstuck" + (agents_dir / "evaluation" / name).read_bytes())
        fingerprints[spec] = sha.hexdigest()[:16]
    return fingerprints


def _add_run(sha: Any, run_dir: Path) -> dict[str, Any]:
    """Adds a learned run's model contents and evaluation env settings to ``sha``; returns
    the run's config."""
    sha.update(model_digest(model_path(run_dir)))
    config = read_run_config(run_dir)
    env_kwargs = evaluation_env_kwargs(config)
    sha.update(json.dumps(env_kwargs, sort_keys=True, default=str).encode())
    return config
