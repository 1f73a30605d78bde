"""A trained stable-baselines3 model as an evaluation agent (the ``Agent`` protocol of
``agents/rollout.py``): the policy's mode, or samples from it seeded per episode when
the recipe says ``deterministic_evaluation: false``, with the LSTM state carried across steps
for RecurrentPPO."""

from __future__ import annotations

import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from agents.run_dir import CONFIG_FILE, model_path, read_run_config, run_label
from agents.sb3.recipes import algorithm_class
from tactile_search.benchmark.model_digest import verified_digest
from tactile_search.benchmark.policies import EpisodeActions, evaluation_settings
from tactile_search.networks.recipe_classes import load_objects


def evaluation_env_kwargs(config: dict[str, Any]) -> dict[str, Any]:
    """The settings of the env a run is evaluated in: its recipe's ``env_kwargs`` (the map,
    the grid, the jars, ...) without the reward terms (evaluation scores every agent in the
    environment's default reward), from the run's ``config.yml``."""
    return evaluation_settings(config)


def load_model(model_path: Path, algo: str, recipe: dict[str, Any] | None = None) -> Any:
    """The SB3 model in ``model_path`` (a ``model.zip`` of ``algo``), on the CPU; with the
    ``recipe`` that trained it, its classes are the recipe's (``load_objects``).

    Raises ``ValueError`` naming the file if it is not a complete zip archive or SB3 cannot
    load it (a truncated or corrupt file, another algorithm's model). The file holds pickled
    Python objects: load only files from sources you trust.
    """
    model_path = Path(model_path)
    try:
        with zipfile.ZipFile(model_path) as archive:
            damaged = archive.testzip()  # reads every member and checks its CRC
            members = set(archive.namelist())
    except (zipfile.BadZipFile, OSError, EOFError) as err:
        raise ValueError(
            f"{model_path} is not a readable zip archive (truncated or corrupt?): {err}"
        ) from err
    if damaged is not None:
        raise ValueError(f"{model_path} is corrupt: its member {damaged!r} fails its CRC check")
    if "data" not in members:
        raise ValueError(
            f"{model_path} is not a stable-baselines3 model file (truncated or corrupt?): "
            f"it has no 'data' member, only {sorted(members)}"
        )
    try:
        return algorithm_class(algo).load(
            model_path, device="cpu", custom_objects=load_objects(recipe or {})
        )
    except Exception as err:  # SB3 raises KeyError, pickle and torch errors alike
        raise ValueError(
            f"{model_path} does not load as a {algo} model ({type(err).__name__}: {err})"
        ) from err


def learned_agent_name(algo: str, map_mode: str) -> str:
    """A learned agent's name in tables and plots: ``ppo (gpis map)``."""
    return f"{algo} ({map_mode} map)"


class LearnedAgent:
    """The model in ``run_dir`` (``model.zip`` beside the ``config.yml`` that trained it).

    Raises ``ValueError`` naming the file and what is wrong when ``run_dir`` lacks either
    file, its ``config.yml`` is not a mapping with ``algo``, ``map`` and ``versions``, was
    written by another version of tactile_search, or its ``model.zip`` is truncated,
    corrupt, not the config's algorithm, or expects other observation or action spaces than
    ``CupboardSearchEnv(map=<the config's map>)``, the env it is evaluated in.

    Security: an SB3 ``model.zip`` holds pickled Python objects, and loading one runs code
    the file chooses. Load only models you trained or that come from a source you trust.
    """

    def __init__(
        self, run_dir: Path, name: str | None = None, deterministic: bool | None = None
    ) -> None:
        run_dir = Path(run_dir)
        self.config: dict[str, Any] = read_run_config(run_dir)
        model_file = model_path(run_dir)
        if not model_file.is_file():
            raise ValueError(f"{run_dir} is not a finished training run: {model_file} is missing")
        self.map_mode: str = self.config["map"]
        #: The settings of the env this agent is evaluated in (``evaluation_env_kwargs``).
        self.env_kwargs: dict[str, Any] = evaluation_env_kwargs(self.config)
        #: What tables call the agent: the run's ``label`` (a variant's name), else its algo.
        self.label: str = run_label(self.config)
        self.name = name or learned_agent_name(self.label, self.map_mode)
        # A published model is checked against its recorded digest before it is unpickled
        # (refused if it changed since; a run without a record, such as a fresh one, loads).
        verified_digest(model_file)
        self.model = load_model(model_file, self.config["algo"], self.config.get("hyperparams"))
        self._check_spaces(model_file)
        # The policy's mode (argmax, mean) or a sample from it: the recipe says which
        # (``deterministic_evaluation``, default true). Samples come from torch's generator,
        # seeded with the episode's layout seed at every reset, so an episode's actions do not
        # depend on the episodes before it (a resumed or sharded evaluation repeats exactly).
        if deterministic is None:
            deterministic = bool(self.config["hyperparams"].get("deterministic_evaluation", True))
        self.deterministic = deterministic
        self._actions = EpisodeActions(self.model, recurrent=self.config["algo"] == "recurrent_ppo")

    def _check_spaces(self, model_file: Path) -> None:
        """The model's spaces against those of the env it will be evaluated in."""
        from tactile_search import CupboardSearchEnv

        env = CupboardSearchEnv(**self.env_kwargs)
        try:
            for kind, expected in (
                ("observation", env.observation_space),
                ("action", env.action_space),
            ):
                got = getattr(self.model, f"{kind}_space")
                if got != expected:
                    raise ValueError(
                        f"{model_file} expects the {kind} space {got}, but the env of its "
                        f"{CONFIG_FILE}'s settings {self.env_kwargs} has {expected} "
                        f"({CONFIG_FILE} does not belong to this model?)"
                    )
        finally:
            env.close()

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        if not self.deterministic:
            import torch

            # The samples' stream: torch's generator seeded with the layout seed, kept by
            # this agent (``act`` swaps it in and out), so that copies of the agent playing
            # episodes side by side each draw what one agent alone would.
            self._torch_rng = torch.Generator().manual_seed(env.np_random_seed).get_state()
        self._actions.reset()

    def act(self, observation: dict) -> np.ndarray:
        if self.deterministic:
            return self._predict(observation)
        import torch

        with torch.random.fork_rng(devices=[]):
            torch.set_rng_state(self._torch_rng)
            action = self._predict(observation)
            self._torch_rng = torch.get_rng_state()
        return action

    def _predict(self, observation: dict) -> np.ndarray:
        # One action of the model's space: three entries, four where the task claims.
        action = np.asarray(
            self._actions.predict(observation, deterministic=self.deterministic)
        ).reshape(self.model.action_space.shape)
        # A wrist motion as float32; probe indices stay integers, as the env takes them.
        return action.astype(np.float32) if action.dtype.kind == "f" else action.astype(np.int64)
