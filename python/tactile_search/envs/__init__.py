"""Gymnasium environments of tactile_search (registered on ``import tactile_search``)."""

from tactile_search.envs.config import CupboardSearchConfig
from tactile_search.envs.cupboard_search import CupboardSearchEnv
from tactile_search.envs.vector import CupboardSearchVectorEnv

__all__ = ["CupboardSearchConfig", "CupboardSearchEnv", "CupboardSearchVectorEnv"]
