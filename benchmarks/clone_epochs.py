"""How behaviour cloning spends its epochs: the held-out NLL and agreement after each epoch
(is there an epoch after which it stops improving?) and a minibatch's time split into data
(rows, tensors) and the network's forward and backward.

Records the GPIS probe planner's demonstrations on ``--episodes`` training layouts (seed
``--seed``, as a run's clone stage does), holds a tenth of the layouts out, clones the rest
with their mirror images into the GPIS recipe's network for ``--epochs`` epochs (one
optimiser, as the recipe's behaviour cloning runs) and prints one line per epoch::

    python -m benchmarks.clone_epochs --episodes 2000 --epochs 40 --torch-threads 1
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from agents.imitation.batched import record_batched
from agents.imitation.cloning import CloningSettings, _evaluate_actions, _minibatches, agreement
from agents.imitation.training import HELD_OUT, _augmentation, _training_layouts
from benchmarks.arguments import positive_int


def main(argv: list[str] | None = None) -> None:
    import torch

    from agents.imitation.cloning import clone
    from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
    from agents.sb3.training_env import make_training_env

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=positive_int, default=2000)
    parser.add_argument("--epochs", type=positive_int, default=40)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--torch-threads", type=positive_int, default=1)
    args = parser.parse_args(argv)
    torch.set_num_threads(args.torch_threads)
    recipe = load_hyperparams("ppo", "gpis")
    env_kwargs = recipe["env_kwargs"]
    demonstrations = record_batched(
        _training_layouts(args.seed, args.episodes), env_kwargs, float(recipe["gamma"])
    )
    train, held_out = demonstrations.split_by_layout(HELD_OUT, args.seed)
    train = _augmentation(True, env_kwargs)(train)
    env = make_training_env(env_kwargs, recipe["n_envs"], args.seed)
    policy = new_model(algorithm_class("ppo"), recipe, env, args.seed).policy
    env.close()
    section = recipe["imitation"]["cloning"]
    settings = CloningSettings(**{**section, "epochs": args.epochs, "seed": args.seed})

    batches = _minibatches(policy, train, settings.batch_size, np.random.default_rng(0))[:20]
    started = time.perf_counter()
    for index in batches:
        policy.obs_to_tensor(train.rows(index).observations)
    data = (time.perf_counter() - started) / len(batches)
    print(
        f"{len(train)} rows cloned, {len(held_out)} held out; per minibatch of "
        f"{settings.batch_size}: data {1000 * data:.1f} ms"
    )

    epoch, started = 0, time.perf_counter()

    def after_epoch(_: int) -> None:
        nonlocal epoch
        epoch += 1
        with torch.no_grad():
            _, log_prob, _ = _evaluate_actions(policy, held_out)
        matched = agreement(policy, held_out)["probe"]
        policy.set_training_mode(True)
        print(
            f"epoch {epoch:3d}  {time.perf_counter() - started:7.1f} s  held-out NLL "
            f"{-log_prob.mean().item():.3f}  agreement {matched:.3f}",
            flush=True,
        )

    clone(policy, train, settings, progress=after_epoch)


if __name__ == "__main__":
    main()
