"""A recipe keyed by a registered id trains, imitates and is evaluated in that id's
settings: ``load_hyperparams`` puts the id's own (its task and tier) under the recipe's
``env_kwargs``, as plain YAML."""

from __future__ import annotations

import gymnasium
import pytest
import yaml

from agents.sb3.recipes import HYPERPARAMS_DIR, load_hyperparams
from tactile_search import ENV_ID

RECIPES = [
    (algo, env_id, map_mode)
    for algo in ("ppo", "recurrent_ppo")
    for env_id, by_map in yaml.safe_load((HYPERPARAMS_DIR / f"{algo}.yml").read_text()).items()
    for map_mode in by_map
]


@pytest.mark.parametrize(("algo", "env_id", "map_mode"), RECIPES)
def test_a_recipe_runs_in_its_ids_settings(algo: str, env_id: str, map_mode: str) -> None:
    settings = load_hyperparams(algo, map_mode, env_id)["env_kwargs"]
    for key, value in gymnasium.spec(env_id).kwargs.items():
        assert settings[key] == (list(value) if isinstance(value, tuple) else value), key
    assert settings["map"] == map_mode
    yaml.safe_dump(settings)  # a run's config.yml holds them


def test_the_identify_recipes_clone_the_identify_planner_and_claim() -> None:
    recipe = load_hyperparams("ppo", "gpis", "tactile_search/IdentifyByTouch-v0")
    assert recipe["env_kwargs"]["task"] == "identify"
    assert recipe["imitation"]["teacher"] == "identify_planner"


def test_the_search_recipe_has_no_setting_of_another_task() -> None:
    assert "task" not in load_hyperparams("ppo", "gpis", ENV_ID)["env_kwargs"]


def test_the_map_recipes_clone_the_occupancy_mapper_without_approach_shaping() -> None:
    for map_mode in ("gpis", "occupancy", "none"):
        recipe = load_hyperparams("ppo", map_mode, "tactile_search/MapByTouch-v0")
        assert recipe["env_kwargs"]["task"] == "map"
        assert recipe["env_kwargs"]["reward_approach"] == 0.0  # no target to approach
        assert recipe["imitation"]["teacher"] == "occupancy_mapper"


@pytest.mark.parametrize("env_id", sorted({env_id for _, env_id, _ in RECIPES}))
def test_every_agent_of_an_id_gets_the_same_clone_stage_budget_and_reward(env_id: str) -> None:
    recipes = [load_hyperparams(a, m, e) for a, e, m in RECIPES if e == env_id]
    assert len(recipes) == 4  # PPO with each map, and the recurrent no-map agent
    for key in ("imitation", "n_timesteps", "learning_rate", "ent_coef", "n_envs", "n_steps"):
        assert len({repr(recipe[key]) for recipe in recipes}) == 1, key
    settings = [{k: v for k, v in r["env_kwargs"].items() if k != "map"} for r in recipes]
    assert all(s == settings[0] for s in settings)
