"""Map channels blanked at evaluation (agents.evaluation.map_ablation): the agent reads the
chosen channels held at their value, every other channel and the episode itself unchanged."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from agents.evaluation.map_ablation import MapChannelsBlanked, blanked_agent, parse_blanking
from agents.rollout import run_episodes
from tactile_search.envs.observation import MAP_CHANNELS

SEED = 1_000_004
PROBE_ENV = {"map": "gpis", "action_mode": "probe"}


class RecordingAgent:
    """Probes the same lane every step and keeps every map it was shown."""

    name = "recorder"

    def __init__(self) -> None:
        self.maps: list[np.ndarray] = []

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self.action = np.zeros(env.action_space.shape, dtype=np.int64)
        self.maps.append(observation["map"])

    def act(self, observation: dict) -> np.ndarray:
        self.maps.append(observation["map"])
        return self.action


def test_the_blanked_channel_reads_its_value_and_the_rest_of_the_episode_is_unchanged():
    plain, recorded = RecordingAgent(), RecordingAgent()
    blanked = MapChannelsBlanked(recorded, "gpis", {"std": 7})
    (plain_row,) = run_episodes(plain, [SEED], max_steps=4, **PROBE_ENV)
    (blanked_row,) = run_episodes(blanked, [SEED], max_steps=4, **PROBE_ENV)
    assert blanked_row == plain_row  # the env and its metrics are the agent's own
    std, mean = MAP_CHANNELS["gpis", "std"], MAP_CHANNELS["gpis", "mean"]
    assert len(recorded.maps) == len(plain.maps) > 1
    for seen, real in zip(recorded.maps, plain.maps, strict=True):
        assert np.all(seen[std] == 7)
        assert np.array_equal(seen[mean], real[mean])
        assert not np.all(real[std] == 7)  # the blanking changed what the agent saw
    assert blanked.name == "recorder [std=7]"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("std", "NAME=VALUE"),
        ("=3", "NAME=VALUE"),
        ("std=half", "an int in"),
        ("std=256", "pixel value in"),
        ("std=-1", "pixel value in"),
    ],
)
def test_a_malformed_blanking_is_refused_naming_the_expected_form(text: str, message: str):
    with pytest.raises(ValueError, match=message):
        parse_blanking(text)


def test_a_channel_the_map_mode_lacks_or_a_repeated_channel_is_refused():
    agent = RecordingAgent()
    with pytest.raises(ValueError, match="the 'occupancy' map has the channels"):
        blanked_agent(agent, "occupancy", ["std=0"])
    with pytest.raises(ValueError, match="the 'none' map has the channels \\[\\]"):
        blanked_agent(agent, "none", ["mean=128"])
    with pytest.raises(ValueError, match="blank each channel once"):
        blanked_agent(agent, "gpis", ["std=0", "std=255"])
    assert blanked_agent(agent, "gpis", []) is agent


def test_an_evaluation_with_a_blanked_map_names_its_agents_and_keeps_their_rows_apart(
    tmp_path: Path,
):
    from agents.evaluation.evaluation import evaluate

    kwargs = {"out": tmp_path, "episodes": 1, "gifs": False}
    (plain,) = evaluate(["gpis_probe_planner"], **kwargs)
    (blanked,) = evaluate(["gpis_probe_planner"], blanked=["std=255"], **kwargs)
    assert plain.agent == "gpis_probe_planner"
    assert blanked.agent == "gpis_probe_planner [std=255]"
    assert "gpis_probe_planner [std=255]" in (tmp_path / "episodes.csv").read_text()
