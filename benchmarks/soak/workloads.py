"""The workloads that drive the envs, round after round (every round does the same mix):

- one long-lived single env (``gymnasium.make``) per map mode and action kind, reset with a
  new training-range layout seed for every episode (``single_episode``);
- GPIS maps filled to capacity in episodes: the GPIS mode with small values of the core's
  ``max_rows`` setting, ``forward`` actions; the map must never hold more rows than
  ``max_rows`` and some episodes must reach it (``info["contacts_dropped"]`` counts the
  readings dropped at capacity);
- one long-lived vector env (``gymnasium.make_vec``, the package's vector entry point) per
  map mode and size, reset with training-range seeds at the start of each of its segments
  and then autoresetting (the autoreset episodes draw their layout seeds from the env's own
  generator), stepped with every action kind (``vector_segment``);
- a fresh "twin" env for some ``out_of_range`` and ``invalid`` episodes, stepped with the
  clipped valid actions only: its rollout must be bit-identical (``twin_step``);
- a standalone ``Gpis`` per capacity filled with repeated ``add_*`` calls until one raises
  the documented ``ValueError`` (nothing added), then topped up value by value to exactly
  ``max_rows``, checked, cleared and refilled (``fill_gpis``);
- a few envs of every kind built, stepped and closed each round (``churn``).

Every long-lived env is parked when its work is done: reset twice on the same layouts (the
soak's first seeds) before the next memory sample. An env holds its last episode until its
next reset, and a reset GPIS map keeps the storage its previous episode needed (half as
many rows again, rounded up to a power of two, ``Gpis::clear``), so a sample after one reset
still depends on the episode before (before that headroom: 3.1 MiB more after an episode of
129+ rows than after one of 128, default grid). Without parking, or with one reset, the heap
swung by those steps from sample to sample and round to round, with the episodes' lengths
rather than with leaks or fragmentation (the full soak: live heap end of round 168.3-179.2
MiB, per-round peaks 183.7-203.8). After the second reset the map keeps the parking
episode's own storage, so every sample sees every env not in use in the same state.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

from benchmarks.soak.actions import INVALID_RATE, invalid_action, policy_action
from benchmarks.soak.memory import live_heap_bytes, live_rss_bytes
from benchmarks.soak.plan import Config, Scale, capacity_rows, configurations, setting
from benchmarks.soak.records import Records, nonfinite
from tactile_search import ENV_ID, Gpis
from tactile_search.envs.config import MAP_MODES
from tactile_search.seed_ranges import TRAINING

#: Every how many ``out_of_range`` / ``invalid`` episodes gets a twin.
TWIN_EVERY = 8


@dataclasses.dataclass
class Episode:
    """The state of one single-env episode as it runs."""

    where: str
    rng: np.random.Generator
    twin: Any
    obs: Any
    max_steps: int
    max_rows: int | None
    first_record: int
    steps: int = 0
    reached: bool = False
    total_reward: float = 0.0


class Soak(Records):
    """The state of one soak run (see the package docstring)."""

    def __init__(self, scale: Scale, seed_base: int = TRAINING[0], log: Callable = print) -> None:
        rows = capacity_rows(scale)
        super().__init__(scale, configurations(scale, rows), seed_base, log)
        self.rng = np.random.default_rng(seed_base % 2**32)
        self.capacity_rows = rows

    def action(
        self, kind: str, env: Any, shape: tuple[int, ...], rng: np.random.Generator
    ) -> np.ndarray:
        return policy_action(kind, env, shape, rng)

    # ---- single env ----------------------------------------------------------------------
    def single_episode(self, index: int, config: Config, seed: int) -> None:
        """One episode of ``config`` on layout ``seed``: everything it does follows from
        ``(seed, index)``, so a failure's message is its reproducer."""
        episode = self._begin_episode(index, config, seed)
        while not self._single_step(index, config, episode):
            pass
        self._end_episode(index, config, seed, episode)
        self.park(config)
        self.sample()

    def _begin_episode(self, index: int, config: Config, seed: int) -> Episode:
        """Resets ``config``'s env (and makes its twin, one episode in ``TWIN_EVERY`` of the
        clipping and refusing kinds) and checks the first observation."""
        env = config.env
        rng = np.random.default_rng([seed, index])
        twin = None
        if config.kind in ("out_of_range", "invalid") and rng.random() < 1 / TWIN_EVERY:
            twin = gym.make(config.env_id, map=config.mode, **config.settings)
            twin.reset(seed=seed)
            self.episodes["twin"] += 1
        self.episodes[config.name] += 1
        self.episodes["single"] += 1
        obs, info = env.reset(seed=seed)
        where = f"{config.name} (config {index}) seed={seed}"
        self.check_output(where, obs, 0.0, info)
        episode = Episode(
            where, rng, twin, obs, max_steps=env.unwrapped.config.max_steps,
            max_rows=config.settings.get("max_rows"), first_record=self.records,
            steps=info["steps"],
        )  # fmt: skip
        if episode.steps != 0:
            self.fail("steps count", f"{where}: reset gives steps={episode.steps}")
        return episode

    def _single_step(self, index: int, config: Config, episode: Episode) -> bool:
        """One step (or one refused invalid action); True when the episode is over."""
        env, rng = config.env, episode.rng
        if config.kind == "invalid" and rng.random() < INVALID_RATE:
            bad_kind, bad = invalid_action(rng, None)
            self.refuse(f"{episode.where} step {episode.steps}", env, bad_kind, bad)
            return False
        action = self.action(config.kind, env, env.action_space.shape, rng)
        start = time.perf_counter_ns()
        obs, reward, terminated, truncated, info = env.step(action)
        elapsed = time.perf_counter_ns() - start
        self.steps["single"] += 1
        self.record(index, elapsed, episode.steps, info["contacts"] > 0)
        at = f"{episode.where} step {episode.steps}"
        self.check_output(at, obs, reward, info)
        episode.obs = obs
        episode.total_reward += reward
        self._check_single_step(at, episode, action, terminated, truncated, info)
        if episode.twin is not None:
            self.twin_step(at, episode.twin, action, obs, reward, terminated, truncated, info)
        if terminated or truncated:
            return True
        if episode.steps > episode.max_steps:
            self.fail("episode ends", f"{at}: past max_steps={episode.max_steps}")
            return True
        return False

    def _check_single_step(
        self, at: str, episode: Episode, action: Any, terminated: bool, truncated: bool,
        info: dict,
    ) -> None:  # fmt: skip
        """The step counter (a claim makes no motion), the time limit, the clipped flag and
        the map's capacity."""
        steps = episode.steps
        if info["steps"] != steps + info["motions"] or info["motions"] > 1:
            self.fail("steps count", f"{at}: steps {steps} -> {info['steps']}")
        steps = episode.steps = info["steps"]
        if truncated != (steps >= episode.max_steps and not terminated):
            self.fail("truncated at max_steps", f"{at}: truncated={truncated}")
        # Only a motion is clipped: the claim entry is not, and a claim makes none.
        motion = np.asarray(action, dtype=np.float64)[:3]
        clipped = info["motions"] > 0 and bool(np.any(np.abs(motion) > 1))
        if info["clipped"] != clipped:
            self.fail("clipped flag", f"{at}: {action!r} gave clipped={info['clipped']}")
        max_rows = episode.max_rows
        if max_rows is not None:
            if info["gpis_rows"] > max_rows:
                self.fail("max_rows respected", f"{at}: {info['gpis_rows']} > {max_rows}")
            episode.reached |= info["contacts_dropped"] > 0 or info["gpis_rows"] + 3 > max_rows

    def _end_episode(self, index: int, config: Config, seed: int, episode: Episode) -> None:
        """Counts the capacity episodes, marks an episode that touched a jar, closes the
        twin and compares a replayed episode with its first run."""
        if episode.max_rows is not None:
            self.capacity_episodes += 1
            self.capacity_reached += episode.reached
        records = self.step_touch[episode.first_record : self.records]
        if records.any():  # the episode touched a jar: mark all its steps
            records |= 2
        if episode.twin is not None:
            episode.twin.close()
        obs = episode.obs
        maps = obs.get("map")
        digest = (
            episode.steps, episode.total_reward, obs["proprio"].tobytes(),
            maps is None or maps.tobytes(),
        )  # fmt: skip
        key = (index, seed)
        if key in self.digests and self.digests[key] != digest:
            self.fail("replayed episode identical", f"{episode.where}: differs from its first run")
        elif self.round == 0:
            self.digests[key] = digest

    def twin_step(
        self, at: str, twin: Any, action: Any, obs: dict, reward: float, terminated: bool,
        truncated: bool, info: dict,
    ) -> None:  # fmt: skip
        """Steps the twin with the clipped action: it must agree bit for bit."""
        t_obs, t_reward, t_terminated, t_truncated, t_info = twin.step(
            np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        )
        self.steps["twin"] += 1
        same = (
            obs.keys() == t_obs.keys()
            and all(np.array_equal(obs[k], t_obs[k]) for k in obs)
            and reward == t_reward
            and (terminated, truncated) == (t_terminated, t_truncated)
            and {k: v for k, v in info.items() if k != "clipped"}
            == {k: v for k, v in t_info.items() if k != "clipped"}
        )
        if not same:
            self.fail("twin agrees (clipping, refused actions)", f"{at}: {action!r}")

    # ---- vector env ----------------------------------------------------------------------
    def vector_segment(self, index: int, config: Config) -> None:
        """``batch_steps`` batch steps of ``config``'s vector env from a reset with the next
        training-range seeds, autoresetting after that."""
        env, num_envs = config.env, config.num_envs
        seeds = self.take_seeds(num_envs)
        where = f"{config.name} (config {index}) seeds={seeds[0]}.."
        rng = np.random.default_rng([seeds[0], index])
        obs, info = env.reset(seed=seeds)
        self.episodes["vector"] += num_envs
        self.check_output(where, obs, 0.0, info)
        steps = info["steps"].copy()
        done = np.zeros(num_envs, dtype=bool)
        for b in range(self.scale.batch_steps):
            steps, done = self._vector_step(
                index, config, f"{where} batch step {b}", rng, steps, done
            )
        self.park(config)
        self.sample()

    def _vector_step(
        self, index: int, config: Config, at: str, rng: np.random.Generator, steps: np.ndarray,
        done: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """One batch step (after a refused invalid one, now and then) and its checks;
        returns the slots' step counts and which slots ended."""
        env, num_envs = config.env, config.num_envs
        if config.kind == "invalid" and rng.random() < INVALID_RATE:
            bad_kind, bad = invalid_action(rng, num_envs)
            self.refuse(at, env, bad_kind, bad)
        action = self.action(config.kind, env, (num_envs, 3), rng)
        start = time.perf_counter_ns()
        obs, rewards, terminated, truncated, info = env.step(action)
        elapsed = time.perf_counter_ns() - start
        self.steps["vector"] += num_envs
        self.episodes["vector"] += int(done.sum())  # the autoresets of this step
        self.record(index, elapsed, -1)
        self.check_output(at, obs, rewards, info)
        expected = np.where(done, 0, steps + 1)
        if not np.array_equal(info["steps"], expected):
            self.fail("steps count", f"{at}: {steps} -> {info['steps']} (done {done})")
        if np.any(rewards[done] != 0) or np.any(terminated[done] | truncated[done]):
            self.fail("autoreset step", f"{at}: reset slots gave reward or flags")
        clipped = np.any(np.abs(np.asarray(action, dtype=np.float64)) > 1, axis=1)
        if not np.array_equal(info["clipped"][~done], clipped[~done]):
            self.fail("clipped flag", f"{at}: {action!r} gave {info['clipped']}")
        return info["steps"].copy(), terminated | truncated

    # ---- standalone GPIS -----------------------------------------------------------------
    def fill_gpis(self, capacity: int) -> None:
        """Fills a ``Gpis`` to ``max_rows`` with repeated adds, checks it, clears, refills."""
        width = setting("cupboard_width")["default"]
        depth = setting("cupboard_depth")["default"]
        bounds = ((-width / 2, width / 2), (0.0, depth))
        low, high = np.array([bounds[0][0], bounds[1][0]]), np.array([bounds[0][1], bounds[1][1]])
        gpis = Gpis(bounds=bounds, shape=setting("grid_shape")["default"], max_rows=capacity)
        where = f"Gpis(max_rows={capacity})"
        for cycle in range(2):
            self._add_until_refused(gpis, capacity, where, low, high)
            self._top_up(gpis, capacity, where, low, high)
            self._check_full(gpis, where, low, high)
            gpis.clear()
            if gpis.n_rows != 0 or gpis.free_rows != capacity:
                self.fail("Gpis clears", f"{where} cycle {cycle}: n_rows={gpis.n_rows}")
        self.sample()

    def _add_until_refused(
        self, gpis: Gpis, capacity: int, where: str, low: np.ndarray, high: np.ndarray
    ) -> None:
        """Repeated mixed adds until one would exceed max_rows (it must add nothing)."""
        rng = self.rng
        for _ in range(100 * capacity):
            before = gpis.n_rows
            try:
                choice = rng.integers(3)
                if choice == 0:
                    points = rng.uniform(low, high, (int(rng.integers(1, 9)), 2))
                    noise = 0.0 if rng.random() < 0.2 else 0.002
                    if noise == 0.0:  # exact duplicates: rejected as degenerate
                        points = np.vstack([points, points[:1]])
                    gpis.add_values(points, noise_std=noise)
                elif choice == 1:
                    count = int(rng.integers(1, 4))
                    normals = rng.normal(size=(count, 2)) + 1e-3
                    gpis.add_contacts(rng.uniform(low, high, (count, 2)), normals)
                else:
                    gpis.add_circle_prior(rng.uniform(low + 0.05, high - 0.05))
            except ValueError as error:
                what = "capacity" if "capacity" in str(error) else str(error)[:60]
                self.expected[f"ValueError: Gpis {what}"] += 1
                if gpis.n_rows != before:
                    self.fail("Gpis adds nothing at capacity", f"{where}: {error}")
                break
            except Exception as error:
                self.unexpected[type(error).__name__] += 1
                self.fail("only documented exceptions", f"{where}: {error!r}")
                break

    def _top_up(
        self, gpis: Gpis, capacity: int, where: str, low: np.ndarray, high: np.ndarray
    ) -> None:
        """Adds value by value to exactly max_rows, then one more (which must be refused)."""
        rng = self.rng
        for _ in range(10 * capacity):
            if gpis.free_rows == 0:
                break
            gpis.add_values(rng.uniform(low, high, (1, 2)))
        self.gpis["rows added"] += gpis.n_rows
        if gpis.n_rows != capacity or gpis.free_rows != 0:
            self.fail("Gpis fills to max_rows", f"{where}: n_rows={gpis.n_rows}")
        try:
            gpis.add_values(rng.uniform(low, high, (1, 2)))
        except ValueError:
            self.expected["ValueError: Gpis capacity"] += 1
        else:
            self.fail("Gpis refuses past max_rows", f"{where}: a value was added")
        if gpis.n_rows > capacity:
            self.fail("Gpis fills to max_rows", f"{where}: n_rows={gpis.n_rows}")

    def _check_full(self, gpis: Gpis, where: str, low: np.ndarray, high: np.ndarray) -> None:
        """The full map and its predictions are finite, with no negative variance."""
        mean, variance = gpis.predict(self.rng.uniform(low, high, (64, 2)))
        if nonfinite([gpis.mean, gpis.variance, mean, variance]):
            self.fail("all finite", f"{where}: the full map holds NaN or inf")
        if gpis.variance.min() < 0 or variance.min() < 0:
            self.fail("Gpis variance >= 0", f"{where}: negative variance")
        self.gpis["fills"] += 1

    # ---- construction churn --------------------------------------------------------------
    def churn(self) -> None:
        """Builds, steps and closes an env of every kind (a leak per env would show)."""
        for mode in MAP_MODES:
            env = gym.make(ENV_ID, map=mode)
            (seed,) = self.take_seeds(1)
            env.reset(seed=seed)
            self.episodes["churn"] += 1
            for _ in range(5):
                obs, reward, _, _, info = env.step(self.action("random", env, (3,), self.rng))
                self.check_output(f"churn {mode} seed={seed}", obs, reward, info)
                self.steps["churn"] += 1
            env.close()
            for size in self.scale.vector_sizes:
                vector = gym.make_vec(
                    ENV_ID, num_envs=size, vectorization_mode="vector_entry_point", map=mode
                )
                vector.reset(seed=self.take_seeds(size))
                self.episodes["churn"] += size
                for _ in range(5):
                    vector.step(self.action("random", vector, (size, 3), self.rng))
                    self.steps["churn"] += size
                vector.close()
        self.sample()

    # ---- parking -------------------------------------------------------------------------
    def park(self, config: Config) -> None:
        """Resets ``config``'s env twice on the parking layouts (the soak's first seeds, one
        per sub-env), so that it holds the same episode and storage at every memory sample
        (see the module docstring)."""
        for _ in range(2):
            if config.num_envs is None:
                config.env.reset(seed=self.seed_base)
            else:
                seeds = list(range(self.seed_base, self.seed_base + config.num_envs))
                config.env.reset(seed=seeds)

    # ---- the run -------------------------------------------------------------------------
    def build_envs(self) -> None:
        """Makes every long-lived env and parks it."""
        for config in self.configs:
            if config.num_envs is None:
                config.env = gym.make(config.env_id, map=config.mode, **config.settings)
            else:
                config.env = self.vector_env(config)
            self.park(config)

    def vector_env(self, config: Config) -> Any:
        """One env per (mode, size, copy), shared by the action kinds."""
        for other in self.configs:
            if (
                other.env is not None
                and other.num_envs == config.num_envs
                and other.mode == config.mode
                and other.copy == config.copy
            ):
                return other.env
        return gym.make_vec(
            ENV_ID,
            num_envs=config.num_envs,
            vectorization_mode="vector_entry_point",
            copy=config.copy,
            map=config.mode,
        )

    def run(self) -> None:
        """Every round, with the parallel reference workload running beside them."""
        self.reference.start_vector()
        try:
            self._run()
        finally:
            self.reference.stop_vector()

    def _run(self) -> None:
        self.sample()
        self.rss_start, self.live_start = live_rss_bytes(), live_heap_bytes()
        self.build_envs()
        first_seed = self.next_seed
        references: dict[int, int] = {}
        for round_ in range(self.scale.rounds):
            self.round = round_
            if self.scale.replay:
                self.next_seed = first_seed
            self._round(references)
            if self.round == self.scale.warm_rounds - 1:
                self.warm_steps = self.total_steps()
                self.warm_time = time.perf_counter() - self.start
            self._log_round()
        self.elapsed = time.perf_counter() - self.start
        for config in self.configs:
            if config.env is not None:
                config.env.close()
                config.env = None

    def _round(self, references: dict[int, int]) -> None:
        """One round: every configuration, the standalone fills and the churn."""
        for index, config in enumerate(self.configs):
            if config.num_envs is None:
                for episode in range(self.scale.episodes):
                    self.single_episode(
                        index, config, self._episode_seed(index, episode, references)
                    )
            else:
                self.vector_segment(index, config)
        for capacity in self.scale.gpis_capacities:
            self.fill_gpis(capacity)
        self.churn()
        self.sample()  # the end of the round: the same point every round

    def _episode_seed(self, index: int, episode: int, references: dict[int, int]) -> int:
        """The layout seed of a single-env episode: a configuration's first episode of every
        round replays its first seed (the reference episode); the others take new ones."""
        if episode == 0 and index in references and not self.scale.replay:
            return references[index]  # the reference episode, replayed
        (seed,) = self.take_seeds(1)
        references.setdefault(index, seed)
        return seed

    def _log_round(self) -> None:
        """The round's line: time, steps, episodes and memory at its end."""
        _, _, trimmed, _, live, _, _ = self.mem[self.mem_count - 1]
        self.log(
            f"  round {self.round + 1}/{self.scale.rounds}"
            f"{' (warm-up)' if self.round < self.scale.warm_rounds else ''}: "
            f"{time.perf_counter() - self.start:7.1f} s, {self.total_steps():,} steps, "
            f"{sum(self.episodes[k] for k in ('single', 'vector', 'churn')):,} episodes, "
            f"RSS after trim {trimmed / 2**20:.1f} MiB"
            + (f", live heap {live / 2**20:.1f} MiB" if live >= 0 else "")
            + (f", {sum(self.failures.values())} failures" if self.failures else "")
        )
