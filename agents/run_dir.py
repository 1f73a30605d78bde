"""The run-folder contract: what a training run's directory holds, read and written here only.

A run directory ``<out>/<algo>_<map>_seed<seed>/`` holds ``config.yml`` (the resolved recipe,
seed, versions, the code's git commit, the machine, checkpoints and resumes), ``model.zip``
(written last: a run is finished when both exist and the config records ``timesteps_done``),
``progress.csv`` and TensorBoard events, and ``checkpoints/rl_model_<timesteps>_steps.zip``.
A run cloned from a teacher (``agents.imitation``) also holds ``demonstrations.npz`` (what
its last clone learned from) and ``rounds/round<k>/`` (the student before each DAgger round,
a run directory each); a PPO run that fine-tunes such a clone keeps it in ``imitation/``
(a run directory of its own, with the teacher's demonstrations it cloned).
Every file is replaced atomically (a temporary file renamed over it), so a kill leaves the old
file or the new one. ``model_digest`` hashes what a ``model.zip`` holds, not its bytes (the
package's ``tactile_search.benchmark.model_digest``, which the benchmark checks a model
against before loading it); a published run also holds ``model.digest`` (that digest) and
``MODEL_CARD.md`` (``agents.grid.model_card``).

Other modules name a run's files through the functions here (``config_path``,
``model_path``, ``checkpoint_dir``...), never by typing them (``tests/test_run_dir.py``).
"""

from __future__ import annotations

import contextlib
import csv
import os
import platform
import re
import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

import gymnasium as gym
import yaml

import tactile_search
from tactile_search.benchmark.model_digest import digest_path
from tactile_search.benchmark.model_digest import model_digest as model_digest  # re-exported
from tactile_search.benchmark.policies import RUN_CONFIG_FILE
from tactile_search.envs.config import MAP_MODES

# Where the published models are trained (agents.pipeline's full budget), from the repo root.
PUBLISHED_RUNS = "docs/results/models"
#: The algorithms a run may record as its ``algo`` (``agents.sb3.recipes`` gives each its
#: SB3 class).
ALGORITHMS = ("ppo", "recurrent_ppo")
#: The files of a run directory (the config's name is the benchmark's, which reads it too).
CONFIG_FILE = RUN_CONFIG_FILE
MODEL_FILE = "model.zip"
PROGRESS_FILE = "progress.csv"
#: A published run's card (``agents.grid.model_card``).
MODEL_CARD_FILE = "MODEL_CARD.md"


CHECKPOINT_DIR = "checkpoints"


CHECKPOINT_PREFIX = "rl_model"


CHECKPOINT_NAME = re.compile(rf"{CHECKPOINT_PREFIX}_(\d+)_steps\.zip")
#: A checkpoint's file name, as messages show it.
CHECKPOINT_PATTERN = f"{CHECKPOINT_PREFIX}_<timesteps>_steps.zip"
#: Where a PPO run whose recipe has an ``imitation`` section keeps the clone it fine-tunes
#: (``agents.imitation.clone_stage``), a run directory of its own inside the PPO run's.
CLONE_DIR = "imitation"
#: Where an imitation run keeps the student before each DAgger round, as runs of their own
#: (``round0`` is behaviour cloning alone).
ROUNDS_DIR = "rounds"
#: What an imitation run's last clone learned from (``agents.sb3.anchor`` anchors PPO
#: fine-tuning to it).
DEMONSTRATIONS_FILE = "demonstrations.npz"
#: The teacher's demonstrations a clone stage keeps in its clone's directory, so that a stage
#: started again after a kill clones the same demonstrations without recording them again.
TEACHER_DEMONSTRATIONS_FILE = "teacher_demonstrations.npz"
#: The files an evaluation of a run reads (``agents.sb3.learned.LearnedAgent``).
EVALUATED_FILES = (MODEL_FILE, CONFIG_FILE)
#: The record of a run kept beside published results (the model stays out).
RECORD_FILES = (CONFIG_FILE, PROGRESS_FILE)


def config_path(run_dir: Path) -> Path:
    """The run's ``config.yml``."""
    return Path(run_dir) / CONFIG_FILE


def model_path(run_dir: Path) -> Path:
    """The run's ``model.zip`` (there once the run finished)."""
    return Path(run_dir) / MODEL_FILE


def model_card_path(run_dir: Path) -> Path:
    """The run's ``MODEL_CARD.md`` (a published run's, ``agents.grid.model_card``)."""
    return Path(run_dir) / MODEL_CARD_FILE


def model_digest_path(run_dir: Path) -> Path:
    """Where the digest of the run's ``model.zip`` is recorded, which the benchmark checks
    the model against before loading it (``tactile_search.benchmark.model_digest``)."""
    return digest_path(model_path(run_dir))


def progress_path(run_dir: Path) -> Path:
    """The run's ``progress.csv`` (SB3's logger writes it)."""
    return Path(run_dir) / PROGRESS_FILE


def checkpoint_dir(run_dir: Path) -> Path:
    """The directory of the run's checkpoints."""
    return Path(run_dir) / CHECKPOINT_DIR


def clone_dir(run_dir: Path) -> Path:
    """The directory of the clone a PPO run fine-tunes (``CLONE_DIR``)."""
    return Path(run_dir) / CLONE_DIR


def round_dir(run_dir: Path, index: int) -> Path:
    """The directory of an imitation run's student before DAgger round ``index + 1``."""
    return Path(run_dir) / ROUNDS_DIR / f"round{index}"


def demonstrations_path(run_dir: Path) -> Path:
    """An imitation run's ``demonstrations.npz`` (``DEMONSTRATIONS_FILE``)."""
    return Path(run_dir) / DEMONSTRATIONS_FILE


def run_name(algo: str, map_mode: str, seed: int) -> str:
    """The run directory's name."""
    return f"{algo}_{map_mode}_seed{seed}"


def task_folder(env_id: str) -> str:
    """The folder the runs and results of registered id ``env_id`` keep under a budget's
    runs and results (``docs/results/models/IdentifyByTouch-v0/``): the id's name without
    its namespace, or none (``""``) for the default id, ``tactile_search.ENV_ID``, whose
    runs and results came first."""
    from tactile_search import ENV_ID, ENV_IDS

    if env_id not in ENV_IDS:
        raise ValueError(f"env_id must be one of {list(ENV_IDS)}, got {env_id!r}")
    return "" if env_id == ENV_ID else env_id.split("/")[-1]


def versions() -> dict[str, str]:
    """Versions of what produced a run."""
    import stable_baselines3
    import torch

    return {
        "tactile_search": tactile_search.__version__,
        "stable_baselines3": stable_baselines3.__version__,
        "torch": str(torch.__version__),
        "gymnasium": gym.__version__,
        "python": platform.python_version(),
    }


def machine() -> dict[str, Any]:
    """The machine a run trained on, as ``config.yml`` records it."""
    import torch

    return {
        "cpus": os.cpu_count(),
        "processor": platform.processor() or platform.machine(),
        "system": platform.platform(),
        "gpu": torch.cuda.get_device_name(0) if torch.cuda.is_available() else None,
    }


def code_version(repo: Path | None = None) -> dict[str, Any]:
    """The code that produced a run: the git commit of ``repo`` (default: the checkout this
    ``agents`` package sits in) and whether its tree differed from the commit (``dirty``:
    changed or new files that git does not ignore). Both ``None`` outside a git checkout,
    e.g. in a Ray worker's copy of ``agents``: there the driver's version is passed in."""
    repo = Path(__file__).resolve().parents[1] if repo is None else Path(repo)

    def git(*args: str) -> str:
        done = subprocess.run(
            ["git", "-C", str(repo), *args], capture_output=True, text=True, timeout=30
        )
        if done.returncode != 0:
            raise subprocess.SubprocessError(done.stderr.strip())
        return done.stdout.strip()

    try:
        commit = git("rev-parse", "HEAD")
        dirty = bool(git("status", "--porcelain", "--", ".", f":(exclude){PUBLISHED_RUNS}"))
    except (OSError, subprocess.SubprocessError):
        return {"commit": None, "dirty": None}
    return {"commit": commit, "dirty": dirty}


@contextlib.contextmanager
def replaced_atomically(path: Path, mode: str) -> Iterator[IO[Any]]:
    """A file to write ``path``'s new content into: a temporary file renamed over ``path``
    once written and synced, so a kill leaves either the old file or the new one, never
    half of one."""
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open(mode) as f:
        yield f
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_atomically(path: Path, text: str) -> None:
    """Writes ``text`` to ``path`` atomically (see ``replaced_atomically``)."""
    with replaced_atomically(path, "w") as f:
        f.write(text)


def write_run_config(run_dir: Path, config: dict[str, Any]) -> None:
    """Writes a run's ``config.yml`` atomically, keys in the order given."""
    write_atomically(config_path(run_dir), yaml.safe_dump(config, sort_keys=False))


def save_model_atomically(model: Any, path: Path) -> None:
    """``model.save(path)`` atomically (see ``replaced_atomically``)."""
    with replaced_atomically(path, "wb") as f:
        model.save(f)


def checkpoints(run_dir: Path) -> list[tuple[int, Path]]:
    """The checkpoints of a run as ``(timesteps, path)``, oldest first."""
    found = []
    for path in checkpoint_dir(run_dir).glob(f"{CHECKPOINT_PREFIX}_*_steps.zip"):
        match = CHECKPOINT_NAME.fullmatch(path.name)
        if match:
            found.append((int(match.group(1)), path))
    return sorted(found)


def recorded_config(run_dir: Path) -> Any:
    """What a run's ``config.yml`` holds as YAML, unchecked (``read_run_config`` checks it);
    None if there is no such file."""
    path = config_path(run_dir)
    return yaml.safe_load(path.read_text()) if path.is_file() else None


def read_run_config(run_dir: Path, required: tuple[str, ...] = ("algo", "map", "versions")) -> dict:
    """A run's ``config.yml``, checked: a mapping with the ``required`` keys, a known algo and
    map mode, written by this version of tactile_search. Raises ``ValueError`` naming the
    file and what is wrong."""
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        raise ValueError(f"{run_dir} is not a training run: no such directory")
    path = config_path(run_dir)
    if not path.is_file():
        raise ValueError(f"{run_dir} is not a training run: {path.name} is missing ({path})")
    try:
        config = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as err:
        raise ValueError(f"{path} is not a readable YAML file: {err}") from err
    if not isinstance(config, dict):
        raise ValueError(
            f"{path} must hold a mapping of the run's settings, got {type(config).__name__}"
        )
    missing = [key for key in required if key not in config]
    if missing:
        raise ValueError(f"{path} lacks the keys {missing} (it has {sorted(config)})")
    if "algo" in required and config["algo"] not in ALGORITHMS:
        raise ValueError(f"{path}: algo must be one of {ALGORITHMS}, got {config['algo']!r}")
    if "map" in required and config["map"] not in MAP_MODES:
        raise ValueError(f"{path}: map must be one of {MAP_MODES}, got {config['map']!r}")
    if "versions" in required:
        versions_ = config["versions"]
        if not isinstance(versions_, dict) or "tactile_search" not in versions_:
            raise ValueError(
                f"{path}: versions must be a mapping with a tactile_search entry, got {versions_!r}"
            )
        if str(versions_["tactile_search"]) != tactile_search.__version__:
            raise ValueError(
                f"{path} was written by tactile_search {versions_['tactile_search']}, this is "
                f"tactile_search {tactile_search.__version__}: the environment may differ from "
                "the one the run trained in; retrain it, or install that version"
            )
    label = config.get("label")
    if label is not None and (not isinstance(label, str) or not label or "(" in label):
        raise ValueError(f"{path}: label must be a non-empty name without '(', got {label!r}")
    if "hyperparams" in required:
        recipe = config["hyperparams"]
        needed = ("n_timesteps", "n_envs", "policy", "env_kwargs")
        if not isinstance(recipe, dict) or any(key not in recipe for key in needed):
            raise ValueError(f"{path}: hyperparams must be a mapping with the keys {needed}")
    return config


def run_label(config: dict) -> str:
    """What tables call a run's agent: its config's ``label`` (a variant's name, such as
    ``imitation``), else its ``algo``."""
    return str(config.get("label") or config["algo"])


def is_finished(run_dir: Path, config: dict) -> bool:
    """Whether a run finished: its ``model.zip`` exists and its config records the timesteps
    done (the config is written first, then the model, each atomically)."""
    return model_path(run_dir).is_file() and "timesteps_done" in config


def holds_unfinished_run(run_dir: Path) -> bool:
    """Whether ``run_dir`` holds checkpoints of a run that did not finish (to resume, not to
    start afresh over)."""
    if not checkpoints(run_dir):
        return False
    config = recorded_config(run_dir)
    return not (isinstance(config, dict) and is_finished(run_dir, config))


def progress_rows(run_dir: Path) -> list[dict[str, str]]:
    """The rows of a run's ``progress.csv`` by column; none for a run without one (a run
    cloned from a teacher trains no RL)."""
    path = progress_path(run_dir)
    if not path.is_file():
        return []
    with path.open() as f:
        return list(csv.DictReader(f))


def kept_progress(run_dir: Path, timesteps: int) -> tuple[list[str], list[str]] | None:
    """The header and the complete rows of a run's ``progress.csv`` logged at or before
    ``timesteps`` (the later rows belong to work a resumed run redoes; a row cut short by a
    kill is dropped). None if there is no usable file."""
    path = progress_path(run_dir)
    if not path.is_file():
        return None
    lines = path.read_text().splitlines(keepends=True)
    if not lines or not lines[0].endswith("\n"):
        return None
    header = next(csv.reader([lines[0]]))
    if "time/total_timesteps" not in header:
        return header, []
    column = header.index("time/total_timesteps")
    kept = []
    for line in lines[1:]:
        if not line.endswith("\n"):
            break
        row = next(csv.reader([line]), [])
        if len(row) != len(header):
            continue
        try:
            done = float(row[column])
        except ValueError:
            continue
        if done <= timesteps:
            kept.append(line)
    return header, kept


def model_file(path: Path) -> Path:
    """``path`` if it is a model file, else ``<path>/model.zip``; ``ValueError`` if neither is."""
    candidate = model_path(path) if path.is_dir() else path
    if not candidate.is_file():
        raise ValueError(
            f"init_from must be a run directory with {MODEL_FILE} or a model file, got {path}"
        )
    return candidate


def config_beside(model: Path) -> Any:
    """What the ``config.yml`` beside the model file ``model`` holds (``recorded_config`` of
    its directory), None without one: the recipe that trained a warm start's source."""
    return recorded_config(Path(model).parent)


def demonstrations_beside(model: Path) -> Path:
    """The ``demonstrations.npz`` beside the model file ``model`` (an imitation run's)."""
    return demonstrations_path(Path(model).parent)


def evaluated_files(run_dir: Path) -> dict[str, bytes]:
    """The files of ``run_dir`` an evaluation reads (``EVALUATED_FILES``), to send to a
    machine that may not see ``run_dir``; ``ValueError`` if the run has not finished."""
    run_dir = Path(run_dir)
    missing = [name for name in EVALUATED_FILES if not (run_dir / name).is_file()]
    if missing:
        raise ValueError(f"{run_dir} is not a finished training run: it lacks {missing}")
    return {name: (run_dir / name).read_bytes() for name in EVALUATED_FILES}


def write_evaluated_files(run_dir: Path, files: dict[str, bytes]) -> None:
    """Writes ``files`` (from ``evaluated_files``) into ``run_dir``, a run an evaluation
    reads; ``ValueError`` for a name that is not one of ``EVALUATED_FILES``."""
    unknown = sorted(set(files) - set(EVALUATED_FILES))
    if unknown:
        raise ValueError(f"a run's evaluated files are {EVALUATED_FILES}, got {unknown}")
    for name, content in files.items():
        (Path(run_dir) / name).write_bytes(content)


def copy_record(run_dir: Path, into: Path) -> None:
    """Copies the record of a run (``RECORD_FILES``: its config and training log) into
    ``into``, which is created."""
    into = Path(into)
    into.mkdir(parents=True, exist_ok=True)
    for name in RECORD_FILES:
        shutil.copyfile(Path(run_dir) / name, into / name)
