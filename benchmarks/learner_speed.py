"""Where a PPO training run's time goes, per map encoder and setting: the update, the
rollout's inference and the environment, per trained probe, side by side in one process.

Each variant is a training recipe (``agents/hyperparams/ppo.yml`` or an ablation's file)
with its ``policy_kwargs`` and optional overrides, trained by SB3's own ``learn`` on the
Rust batch (``agents.sb3.training_env.make_training_env``), exactly as ``agents.train``
trains it. After one excluded warm-up rollout and update per model, every variant in turn
learns ``--timesteps`` probes per round (the order rotating each round, so the shared
machine's load swings hit them alike), while a callback and a ``VecEnv`` wrapper split the
round's wall-clock into

- ``env``: the environment's ``step`` (the batch of probes, resets included);
- ``infer``: the rest of the rollout (the policy's forward pass for each step's actions,
  the rollout buffer, SB3's bookkeeping);
- ``update``: the PPO update after each rollout (``n_epochs`` passes of minibatches).

It prints each round, then per variant the medians: trained probes/s, its ratio to the
``recipe`` variant's in the same rounds, each part in ms per trained probe, the update's
cost per sample pass (µs: the update's time over ``n_epochs`` x probes), parameters and the
map grid the encoder keeps. With gymnasium's MuJoCo envs installed (the ``bench`` extra),
each round also runs ``Pusher-v5`` with random actions for a few seconds and prints the
trained probes/s over Pusher-v5's steps/s (the budgets of ``docs/DESIGN.md`` §5 are such
ratios). The header says whether the CPU computes bfloat16 natively (AMX or AVX-512's
bfloat16): a variant with ``bfloat16_updates=true`` runs its update under bfloat16 autocast
only there (``agents.sb3.bfloat16``).

Variants are named ``NAME`` or ``NAME:key=value,key=value`` (recipe keys, values in YAML;
``env_kwargs.KEY`` sets one environment setting), e.g. ``space_to_depth:n_epochs=5``,
``recipe:bfloat16_updates=true`` or ``recipe:env_kwargs.fast_free_motion=false`` (the
environment before its fast path of free motion). Run from the repo root::

    python -m benchmarks.learner_speed       # recipe, impala_factorised, space_to_depth
    python -m benchmarks.learner_speed --variants recipe impala_factorised nature_cnn \\
        spatial_softmax mlp_no_map --timesteps 2048 --rounds 3 --torch-threads 1
    python -m benchmarks.learner_speed --variants recipe recipe:bfloat16_updates=true \\
        recipe:bfloat16_updates=true,n_epochs=5

``--json PATH`` writes the summary's figures (for ``docs/PERFORMANCE.md``,
``benchmarks.performance_page``). Like ``agents/train.py``, it sets ``OMP_WAIT_POLICY=PASSIVE``
(unless set) before torch loads. ``--torch-threads 1 --env-threads 1`` is how the ``full``
budget trains each seed.
"""

from __future__ import annotations

import os

# Before torch loads (stable_baselines3 imports it): see agents/train.py.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse
import importlib.util
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from agents.sb3.bfloat16 import cpu_has_native_bf16
from agents.sb3.recipes import load_hyperparams, new_model, training_class
from agents.sb3.training_env import make_training_env
from benchmarks.arguments import positive_int
from benchmarks.performance_page import write_json
from tactile_search.networks.encoders import MapExtractor, map_feature_shape

ABLATIONS = Path("docs/results/ablations_speed")
#: name -> (the map mode, the recipe file (None: agents/hyperparams/ppo.yml), the
#: features extractor put in its policy_kwargs: "keep" the recipe's, None for SB3's default
#: CombinedExtractor, or a dotted class path with default kwargs).
#: The encoder variants compare against ``impala_factorised`` (the IMPALA encoder with SB3's
#: factorised action head, in place of the recipe's spatial probe head), so that they differ
#: from it only in the encoder.
FACTORISED = ABLATIONS / "impala_factorised.yml"
VARIANTS: dict[str, tuple[str, Path | None, str | None]] = {
    "recipe": ("gpis", None, "keep"),
    "impala_factorised": ("gpis", FACTORISED, "keep"),
    "space_to_depth": ("gpis", ABLATIONS / "space_to_depth.yml", "keep"),
    "nature_cnn": ("gpis", FACTORISED, None),
    "spatial_softmax": (
        "gpis",
        FACTORISED,
        "tactile_search.networks.encoders.SpatialSoftmaxMapExtractor",
    ),
    "mlp_no_map": ("none", None, "keep"),
}
REFERENCE_VARIANT = "recipe"
PUSHER_ID = "Pusher-v5"
#: How long Pusher-v5 runs after each round, s.
PUSHER_SECONDS = 5.0


def variant_spec(text: str) -> tuple[str, dict[str, Any]]:
    """argparse type: ``NAME`` or ``NAME:key=value,...`` -> (name, recipe overrides)."""
    name, _, overrides = text.partition(":")
    if name not in VARIANTS:
        raise argparse.ArgumentTypeError(f"variant must be one of {sorted(VARIANTS)}, got {name!r}")
    parsed: dict[str, Any] = {}
    for item in filter(None, overrides.split(",")):
        key, eq, value = item.partition("=")
        if not eq or not key:
            raise argparse.ArgumentTypeError(f"expected key=value in {text!r}, got {item!r}")
        parsed[key] = yaml.safe_load(value)
    return text, parsed


@dataclass
class Measured:
    """One variant's model and what each round measured (seconds, probes)."""

    label: str
    model: Any
    recipe: dict[str, Any]
    probes: list[int] = field(default_factory=list)
    total: list[float] = field(default_factory=list)
    env: list[float] = field(default_factory=list)
    rollout: list[float] = field(default_factory=list)
    pusher_rate: list[float] = field(default_factory=list)

    def per_probe_ms(self, part: str) -> float:
        """The median over rounds of ``part`` (env, infer, update, total) in ms per probe."""
        values = []
        for probes, total, env, rollout in zip(
            self.probes, self.total, self.env, self.rollout, strict=True
        ):
            seconds = {
                "env": env,
                "infer": rollout - env,
                "update": total - rollout,
                "total": total,
            }[part]
            values.append(1e3 * seconds / probes)
        return statistics.median(values)

    def rates(self) -> list[float]:
        return [p / t for p, t in zip(self.probes, self.total, strict=True)]


def variant_recipe(name: str, overrides: dict[str, Any]) -> dict[str, Any]:
    """The recipe a variant trains with: its file's, its extractor, then the overrides."""
    map_mode, path, extractor = VARIANTS[name]
    recipe = load_hyperparams("ppo", map_mode, path=path)
    if extractor != "keep":
        policy_kwargs = dict(recipe.get("policy_kwargs") or {})
        policy_kwargs.pop("features_extractor_kwargs", None)
        policy_kwargs.pop("features_extractor_class", None)
        if extractor is not None:
            policy_kwargs["features_extractor_class"] = extractor
        recipe["policy_kwargs"] = policy_kwargs
    for key, value in overrides.items():
        section, dot, setting = key.partition(".")
        if dot and section == "env_kwargs":  # one env setting, the recipe's others kept
            recipe["env_kwargs"] = {**recipe.get("env_kwargs", {}), setting: value}
        elif dot:
            raise ValueError(f"only env_kwargs.KEY overrides one key of a section, got {key!r}")
        else:
            recipe[key] = value
    return recipe


def build_model(recipe: dict[str, Any], env_threads: int | None) -> Any:
    """The recipe's PPO on its own training env (seed 0), the env wrapped to time its steps."""
    from stable_baselines3.common.vec_env import VecEnvWrapper

    class TimedVecEnv(VecEnvWrapper):
        """Adds the wall-clock spent in the wrapped env's ``step_wait`` to ``seconds``."""

        seconds = 0.0

        def reset(self) -> Any:
            return self.venv.reset()

        def step_wait(self) -> Any:
            start = time.perf_counter()
            result = self.venv.step_wait()
            self.seconds += time.perf_counter() - start
            return result

    env = make_training_env(
        recipe["env_kwargs"], n_envs=recipe["n_envs"], seed=0, threads=env_threads
    )
    return new_model(training_class("ppo", recipe), recipe, TimedVecEnv(env), seed=0)


def rollout_timer() -> Any:
    """An SB3 callback adding each rollout's wall-clock (collection, not the update) to
    ``seconds``."""
    from stable_baselines3.common.callbacks import BaseCallback

    class RolloutTimer(BaseCallback):
        seconds = 0.0

        def _on_rollout_start(self) -> None:
            self.started = time.perf_counter()

        def _on_rollout_end(self) -> None:
            self.seconds += time.perf_counter() - self.started

        def _on_step(self) -> bool:
            return True

    return RolloutTimer()


def learn_round(measured: Measured, timesteps: int) -> None:
    """``timesteps`` more probes of ``measured.model``'s training, split into its parts."""
    model = measured.model
    env = model.get_env()
    env_before, done = env.seconds, model.num_timesteps
    timer = rollout_timer()
    start = time.perf_counter()
    model.learn(total_timesteps=timesteps, reset_num_timesteps=False, callback=timer)
    measured.total.append(time.perf_counter() - start)
    measured.probes.append(model.num_timesteps - done)
    measured.env.append(env.seconds - env_before)
    measured.rollout.append(timer.seconds)


def pusher_rate(seconds: float) -> float | None:
    """Pusher-v5's random-action steps/s over about ``seconds`` (None without MuJoCo)."""
    if importlib.util.find_spec("mujoco") is None:
        return None
    import gymnasium as gym

    from benchmarks.peer_envs import Subject, run_steps

    subject = Subject(PUSHER_ID, gym.make(PUSHER_ID), False)
    subject.env.action_space.seed(0)
    steps, elapsed_ns = 0, 0
    while elapsed_ns < seconds * 1e9:
        ns, _, _ = run_steps(subject, 1000)
        steps, elapsed_ns = steps + 1000, elapsed_ns + ns
    subject.env.close()
    return steps / (elapsed_ns * 1e-9)


def describe(model: Any) -> dict[str, Any]:
    """Parameter counts and the kept map grid of ``model``'s policy."""
    extractor = model.policy.features_extractor
    grid = map_feature_shape(extractor) if isinstance(extractor, MapExtractor) else None
    return {
        "params": sum(p.numel() for p in model.policy.parameters()),
        "grid": "x".join(map(str, grid)) if grid else "-",
    }


def summary(measured: list[Measured], pusher: list[float]) -> list[dict[str, Any]]:
    """Per variant, the medians over rounds: trained probes/s, its ratio to the reference
    variant's in the same rounds, each part in ms per trained probe, the update's µs per
    sample pass, parameters, the kept map grid and the ratio to Pusher-v5 (None without)."""
    reference = next((m for m in measured if m.label == REFERENCE_VARIANT), measured[0])
    rows = []
    for m in measured:
        ratios = [a / b for a, b in zip(m.rates(), reference.rates(), strict=True)]
        info = describe(m.model)
        rows.append({
            "label": m.label,
            "reference": reference.label,
            "probes_per_s": statistics.median(m.rates()),
            "probes_per_s_rounds": m.rates(),
            "ratio_to_reference": statistics.median(ratios),
            "env_ms": m.per_probe_ms("env"),
            "infer_ms": m.per_probe_ms("infer"),
            "update_ms": m.per_probe_ms("update"),
            "update_us_per_sample": 1e3 * m.per_probe_ms("update") / m.recipe["n_epochs"],
            "params": info["params"],
            "grid": info["grid"],
            "ratio_to_pusher": (
                statistics.median(r / p for r, p in zip(m.rates(), pusher, strict=True))
                if pusher
                else None
            ),
        })  # fmt: skip
    return rows


def print_summary(rows: list[dict[str, Any]], pusher: list[float]) -> None:
    print(
        f"\n{'variant':>28} {'probes/s':>8} {'vs ' + rows[0]['reference']:>10} {'env':>6} "
        f"{'infer':>6} {'update':>7} {'us/sample':>9} {'params':>8} {'grid':>8}"
        f"{'  vs Pusher-v5':>14}"
    )
    print(f"{'':>28} {'':>8} {'':>10} {'(ms per trained probe)':>21}")
    for r in rows:
        vs_pusher = (
            f"{'-':>14}" if r["ratio_to_pusher"] is None else f"{r['ratio_to_pusher']:14.4f}"
        )
        print(
            f"{r['label']:>28} {r['probes_per_s']:8.1f} {r['ratio_to_reference']:10.2f} "
            f"{r['env_ms']:6.2f} {r['infer_ms']:6.2f} "
            f"{r['update_ms']:7.2f} {r['update_us_per_sample']:9.0f} {r['params']:8,d} "
            f"{r['grid']:>8}{vs_pusher}"
        )
    if pusher:
        print(f"{PUSHER_ID}: median {statistics.median(pusher):,.0f} steps/s (random actions)")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--variants",
        nargs="+",
        type=variant_spec,
        default=[
            variant_spec("recipe"),
            variant_spec("impala_factorised"),
            variant_spec("space_to_depth"),
        ],
        help=f"NAME or NAME:key=value,... with NAME in {sorted(VARIANTS)}",
    )
    parser.add_argument("--timesteps", type=positive_int, default=2048, help="probes per round")
    parser.add_argument("--rounds", type=positive_int, default=3, help="alternating rounds")
    parser.add_argument("--torch-threads", type=positive_int, default=1)
    parser.add_argument("--env-threads", type=positive_int, default=1)
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    import torch

    torch.set_num_threads(args.torch_threads)
    measured = []
    for label, overrides in args.variants:
        recipe = variant_recipe(label.partition(":")[0], overrides)
        measured.append(Measured(label, build_model(recipe, args.env_threads), recipe))
    print(
        f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}, torch threads "
        f"{args.torch_threads}, env threads {args.env_threads}; {args.timesteps} probes per "
        f"variant per round, {args.rounds} rounds; torch {torch.__version__}, CPU capability "
        f"{torch.backends.cpu.get_cpu_capability()}, native bfloat16 "
        f"{'yes' if cpu_has_native_bf16() else 'no'}",
        flush=True,
    )
    for m in measured:  # warm-up: the first rollout and update, excluded
        rollout = m.recipe["n_steps"] * m.recipe["n_envs"]
        m.model.learn(total_timesteps=rollout)
    pusher: list[float] = []
    for round_index in range(args.rounds):
        shift = round_index % len(measured)
        for m in measured[shift:] + measured[:shift]:
            learn_round(m, args.timesteps)
            print(
                f"  round {round_index} {m.label:>28}: {m.rates()[-1]:6.1f} probes/s "
                f"(env {1e3 * m.env[-1] / m.probes[-1]:.2f}, update "
                f"{1e3 * (m.total[-1] - m.rollout[-1]) / m.probes[-1]:.2f} ms per probe)",
                flush=True,
            )
        rate = pusher_rate(PUSHER_SECONDS)
        if rate is not None:
            pusher.append(rate)
            print(f"  round {round_index} {PUSHER_ID:>28}: {rate:,.0f} steps/s", flush=True)
    rows = summary(measured, pusher)
    print_summary(rows, pusher)
    for m in measured:
        m.model.get_env().close()
    if args.json is not None:
        figures = {
            "timesteps": args.timesteps, "rounds": args.rounds,
            "torch_threads": args.torch_threads, "env_threads": args.env_threads,
            "torch": torch.__version__, "native_bf16": cpu_has_native_bf16(),
            "reference": rows[0]["reference"],
            "pusher_steps_per_s": statistics.median(pusher) if pusher else None,
            "variants": rows,
        }  # fmt: skip
        write_json(args.json, "benchmarks.learner_speed", argv, figures)


if __name__ == "__main__":
    main()
