"""PPO training speed with each map encoder of ``agents/sb3/encoders.py`` against SB3's default.

Trains the documented GPIS recipe (``agents/hyperparams/ppo.yml``, its ``policy_kwargs``
kept and the encoder's merged in) on the Rust batch (``agents.sb3.training_env.make_training_env``)
with each encoder: SB3's ``MultiInputPolicy`` default (NatureCNN on the map),
``ImpalaMapExtractor``, ``SpatialSoftmaxMapExtractor``, and for reference the no-map recipe
(proprio only: an MLP). After one excluded warm-up rollout and update per model, it measures
``--timesteps`` of ``learn`` per encoder, alternating the encoders over ``--repeats`` rounds
so the shared machine's load hits them alike, and prints each round, then per encoder the
median steps/s, its ratio to NatureCNN, the parameter counts (the whole policy and its
features extractor), ``features_dim`` and the map grid the extractor keeps. Run from the
repo root::

    python -m benchmarks.encoder_speed [--timesteps 8192] [--repeats 2] [--torch-threads 2]
    python -m benchmarks.encoder_speed --encoders nature_cnn impala --timesteps 4096 \\
        --impala-kwargs '{"channels": [8, 16, 16], "res_blocks": 1}'

Like ``agents/train.py``, it sets ``OMP_WAIT_POLICY=PASSIVE`` (unless set) before torch
loads.
"""

from __future__ import annotations

import os

# Before torch loads (stable_baselines3 imports it): see agents/train.py.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse
import json
import statistics
import time
from typing import Any

from agents.sb3.encoders import (
    ImpalaMapExtractor,
    MapExtractor,
    SpatialSoftmaxMapExtractor,
    map_feature_shape,
)
from agents.sb3.recipes import RUN_KEYS, algorithm_class, load_hyperparams
from agents.sb3.training_env import make_training_env
from tactile_search._validation import as_count

# name -> (the recipe's map mode, the features extractor merged into policy_kwargs or None
# for SB3's default CombinedExtractor).
ENCODERS: dict[str, tuple[str, type[MapExtractor] | None]] = {
    "nature_cnn": ("gpis", None),
    "impala": ("gpis", ImpalaMapExtractor),
    "spatial_softmax": ("gpis", SpatialSoftmaxMapExtractor),
    "mlp_no_map": ("none", None),
}
BASELINE = "nature_cnn"


def positive_int(text: str) -> int:
    """argparse type: an int >= 1 (the project's one count check, ``as_count``)."""
    try:
        return as_count("the value", int(text))
    except ValueError as err:
        raise argparse.ArgumentTypeError(f"expected a positive int, got {text!r}: {err}") from err


def json_object(text: str) -> dict[str, Any]:
    """argparse type: a JSON object (keyword arguments)."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as err:
        raise argparse.ArgumentTypeError(f"expected a JSON object, got {text!r}: {err}") from err
    if not isinstance(value, dict):
        raise argparse.ArgumentTypeError(f"expected a JSON object, got {type(value).__name__}")
    return value


def build_model(
    name: str,
    n_envs: int | None,
    env_threads: int | None,
    extractor_kwargs: dict[str, Any] | None = None,
) -> tuple[Any, dict]:
    """The PPO model of encoder ``name`` (with ``extractor_kwargs`` for a map extractor of
    ``agents/sb3/encoders.py``) on its own training env, and its recipe."""
    map_mode, extractor = ENCODERS[name]
    recipe = load_hyperparams("ppo", map_mode)
    n_envs = n_envs or recipe["n_envs"]
    env = make_training_env(recipe["env_kwargs"], n_envs=n_envs, seed=0, threads=env_threads)
    algo_kwargs = {key: value for key, value in recipe.items() if key not in RUN_KEYS}
    policy_kwargs = dict(algo_kwargs.pop("policy_kwargs", None) or {})
    if extractor is not None:
        policy_kwargs["features_extractor_class"] = extractor
        policy_kwargs["features_extractor_kwargs"] = dict(extractor_kwargs or {})
    model = algorithm_class("ppo")(
        recipe["policy"],
        env,
        seed=0,
        device="cpu",
        policy_kwargs=policy_kwargs,
        **algo_kwargs,
    )
    return model, {**recipe, "n_envs": n_envs}


def describe(model: Any) -> dict[str, Any]:
    """Parameter counts, features_dim and the kept map grid of ``model``'s policy."""
    import torch
    from stable_baselines3.common.torch_layers import CombinedExtractor, NatureCNN

    policy = model.policy
    extractor = policy.features_extractor
    grid = None
    if isinstance(extractor, MapExtractor):
        grid = map_feature_shape(extractor)
    elif isinstance(extractor, CombinedExtractor) and "map" in extractor.extractors:
        nature = extractor.extractors["map"]
        if isinstance(nature, NatureCNN):
            shape = policy.observation_space["map"].shape
            with torch.no_grad():  # the convs before NatureCNN's Flatten
                grid = tuple(nature.cnn[:-1](torch.zeros((1, *shape))).shape[1:])
    return {
        "policy_params": sum(p.numel() for p in policy.parameters()),
        "extractor_params": sum(p.numel() for p in extractor.parameters()),
        "features_dim": extractor.features_dim,
        "grid": "x".join(map(str, grid)) if grid else "-",
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--timesteps", type=positive_int, default=8192, help="timesteps per measurement"
    )
    parser.add_argument("--repeats", type=positive_int, default=2, help="alternating rounds")
    parser.add_argument("--torch-threads", type=positive_int, default=2)
    parser.add_argument("--encoders", nargs="+", choices=tuple(ENCODERS), default=list(ENCODERS))
    parser.add_argument(
        "--impala-kwargs",
        type=json_object,
        default={},
        help="features_extractor_kwargs of impala as JSON, e.g. '{\"res_blocks\": 1}'",
    )
    parser.add_argument(
        "--spatial-softmax-kwargs",
        type=json_object,
        default={},
        help="features_extractor_kwargs of spatial_softmax as JSON, e.g. '{\"strides\": [2,2,1]}'",
    )
    parser.add_argument("--n-envs", type=positive_int, default=None, help="default: recipe's")
    parser.add_argument(
        "--env-threads", type=positive_int, default=None, help="default: every core"
    )
    args = parser.parse_args(argv)
    import torch

    torch.set_num_threads(args.torch_threads)
    models: dict[str, Any] = {}
    for name in args.encoders:
        extractor_kwargs = {
            "impala": args.impala_kwargs,
            "spatial_softmax": args.spatial_softmax_kwargs,
        }.get(name)
        model, recipe = build_model(name, args.n_envs, args.env_threads, extractor_kwargs)
        models[name] = model
    rollout = recipe["n_steps"] * recipe["n_envs"]
    print(
        f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}, torch threads "
        f"{args.torch_threads}; PPO gpis recipe: {recipe['n_envs']} envs x "
        f"{recipe['n_steps']} steps = {rollout} per rollout, batch {recipe['batch_size']}, "
        f"{recipe['n_epochs']} epochs; {args.timesteps} timesteps per measurement, "
        f"{args.repeats} rounds",
        flush=True,
    )
    for model in models.values():  # warm-up: the first rollout and update, excluded
        model.learn(total_timesteps=rollout)
    rates: dict[str, list[float]] = {name: [] for name in models}
    for round_index in range(args.repeats):
        for name, model in models.items():
            done = model.num_timesteps
            start = time.perf_counter()
            model.learn(total_timesteps=args.timesteps, reset_num_timesteps=False)
            rates[name].append((model.num_timesteps - done) / (time.perf_counter() - start))
            print(f"  round {round_index} {name:>15}: {rates[name][-1]:6.0f} steps/s", flush=True)
    base = statistics.median(rates[BASELINE]) if BASELINE in rates else None
    print(
        f"\n{'encoder':>15} {'median steps/s':>14} {'vs nature':>9} {'policy params':>13} "
        f"{'extractor params':>16} {'features_dim':>12} {'map grid':>9}"
    )
    for name, model in models.items():
        median = statistics.median(rates[name])
        info = describe(model)
        ratio = f"{median / base:.2f}" if base else "-"
        print(
            f"{name:>15} {median:14.0f} {ratio:>9} {info['policy_params']:13,d} "
            f"{info['extractor_params']:16,d} {info['features_dim']:12d} {info['grid']:>9}"
        )
    for model in models.values():
        model.get_env().close()


if __name__ == "__main__":
    main()
