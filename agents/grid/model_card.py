"""A published run's model card (``MODEL_CARD.md`` beside its ``model.zip``) and the record of
its model's digest (``model.digest``, which the benchmark checks the model against before
loading it).

The card is generated from the run alone and the evaluations that played it, nothing typed:
the registered id and its task, the map, the algorithm and its recipe (the entry of
``agents/hyperparams/<algo>.yml`` under the id and map, and whether the recorded recipe is
still that entry), the command that trains it again, the training seed, timesteps and
wall-clock, the machine and code, the digest, the versions (``config.yml``), and the
evaluation on each registered id of its task whose results hold rows of the run (the run's
agent name in ``<results>/<id's name>/episodes.csv``, summarised by
``tactile_search.benchmark``; a name says the agent and seed, not the task it learned, so
another task's rows are never read). The same
run and rows give the same bytes.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from agents.evaluation.agent_specs import seeded_name
from agents.evaluation.episodes_csv import EPISODES_FILE, read_episodes_csv
from agents.evaluation.evaluation import task_of
from agents.grid.results_doc import commit_text, machine_text, range_text, wall_clock_text
from agents.run_dir import (
    CONFIG_FILE,
    MODEL_FILE,
    PUBLISHED_RUNS,
    clone_dir,
    config_path,
    is_finished,
    model_card_path,
    model_digest_path,
    model_path,
    read_run_config,
    recorded_config,
    run_label,
    task_folder,
    write_atomically,
)
from agents.sb3.learned import learned_agent_name
from agents.sb3.recipes import HYPERPARAMS_DIR, load_hyperparams
from tactile_search import ENV_ID, ENV_IDS
from tactile_search._core import registered_envs
from tactile_search.benchmark.model_digest import model_digest, write_digest
from tactile_search.benchmark.statistics import summarize
from tactile_search.benchmark.summary_table import markdown_row, summary_cells, summary_columns
from tactile_search.networks.recipe_classes import MOVED_MODULES
from tactile_search.seed_ranges import SPLITS

#: The repository's root: the card names paths from it.
REPO = Path(__file__).resolve().parents[2]
#: Where the published runs' evaluations are (the full budget's results).
PUBLISHED_RESULTS = REPO / "docs" / "results"


def shown_path(path: Path) -> str:
    """``path`` from the repository's root when it is inside it, else as it is."""
    resolved = Path(path).resolve()
    try:
        return resolved.relative_to(REPO).as_posix()
    except ValueError:
        return Path(path).as_posix()


def published_runs(models: Path = REPO / PUBLISHED_RUNS) -> list[Path]:
    """The finished runs under ``models``: its run folders (the default id's) and those of
    each other id's folder (``task_folder``), in that order and by name."""
    folders = [models, *(models / task_folder(env_id) for env_id in ENV_IDS if env_id != ENV_ID)]
    runs = []
    for folder in folders:
        if not folder.is_dir():
            continue
        for run_dir in sorted(p for p in folder.iterdir() if p.is_dir()):
            config = recorded_config(run_dir)
            if isinstance(config, dict) and is_finished(run_dir, config):
                runs.append(run_dir)
    return runs


def evaluated_names(config: dict[str, Any], env_id: str) -> list[str]:
    """The names the run's rows carry in an evaluation on ``env_id``
    (``agents.evaluation.evaluation``): with its training seed when the evaluation had
    several of the agent, else without; the id's name in brackets but for the default id."""
    folder = task_folder(env_id)
    suffix = f" [{folder}]" if folder else ""
    label = run_label(config)
    return [
        seeded_name(label, config["map"], config["seed"]) + suffix,
        learned_agent_name(label, config["map"]) + suffix,
    ]


def split_of(seeds: Sequence[int]) -> str:
    """The held-out split all of ``seeds`` lie in (``tactile_search.seed_ranges``)."""
    for name, (low, high) in SPLITS.items():
        if all(low <= seed < high for seed in seeds):
            return name
    return "mixed"


def evaluation_sections(config: dict[str, Any], results: Path) -> list[str]:
    """For each registered id of the task the run was trained on (its own id first: the
    tiers the grid plays it on) whose ``episodes.csv`` under ``results`` holds rows of the
    run: which rows, on which layouts, and their summary. Another task's evaluation is not
    read: its rows of the same name are another task's runs'."""
    trained_on = config.get("env_id", ENV_ID)
    task = task_of(trained_on)
    tiers = [i for i in ENV_IDS if i != trained_on and task_of(i) == task]
    lines: list[str] = []
    for env_id in [trained_on, *tiers]:
        csv_path = results / task_folder(env_id) / EPISODES_FILE
        rows, _ = read_episodes_csv(csv_path)
        found = [
            (name, [row for row in rows if row["agent"] == name])
            for name in evaluated_names(config, env_id)
        ]
        found = [(name, mine) for name, mine in found if mine]
        if not found:
            continue
        name, mine = found[0]
        seeds = sorted(row["seed"] for row in mine)
        summary = dataclasses.asdict(summarize(name, config["map"], mine))
        header = ["layouts", *summary_columns(task)]
        lines += [
            f"### On `{env_id}` (task: {task})",
            "",
            f"The rows of `{name}` in `{shown_path(csv_path)}`: {len(mine)} "
            f"{split_of(seeds)} layouts, seeds {seeds[0]}..{seeds[-1]}.",
            "",
            markdown_row(header),
            "|" + "---|" * len(header),
            markdown_row([f"{len(mine)} {split_of(seeds)}", *summary_cells(task, summary)]),
            "",
        ]
    return lines or ["Not evaluated yet: no evaluation under `" + shown_path(results) + "`.", ""]


def present_names(value: Any) -> Any:
    """``value`` (a recipe, or a part of one) with every class it names by a dotted path
    read at its present module (``MOVED_MODULES``): a moved class is the same class."""
    if isinstance(value, dict):
        return {key: present_names(item) for key, item in value.items()}
    if isinstance(value, list):
        return [present_names(item) for item in value]
    if isinstance(value, str):
        module, dot, name = value.rpartition(".")
        if dot and module in MOVED_MODULES:
            return f"{MOVED_MODULES[module]}.{name}"
    return value


def recipe_changes(config: dict[str, Any]) -> list[str] | None:
    """How the recipe's entry in ``agents/hyperparams/`` differs now from the recipe the run
    recorded (``key: then -> now``, or the key alone for a section); None if the file has
    no such entry any more."""
    try:
        current = present_names(
            load_hyperparams(config["algo"], config["map"], config.get("env_id", ENV_ID))
        )
    except ValueError:
        return None
    recorded = present_names(config.get("hyperparams") or {})
    changes = []
    for key in sorted(set(current) | set(recorded)):
        then, now = recorded.get(key), current.get(key)
        if then == now:
            continue
        plain = all(not isinstance(v, (dict, list)) for v in (then, now))
        changes.append(f"{key}: `{then}` -> `{now}`" if plain else key)
    return changes


def recipe_text(config: dict[str, Any]) -> str:
    """The recipe's entry (file and keys), and what in it has changed since the run."""
    env_id = config.get("env_id", ENV_ID)
    text = (
        f"`{shown_path(HYPERPARAMS_DIR / (config['algo'] + '.yml'))}`, key `{env_id}` -> "
        f"`{config['map']}`"
    )
    changes = recipe_changes(config)
    if changes is None:
        return text + f" (the file has no such entry now; {CONFIG_FILE} holds the recipe trained)"
    if not changes:
        return text + f" (as {CONFIG_FILE} records it)"
    return f"{text} as {CONFIG_FILE} records it; the entry has changed since: " + "; ".join(changes)


def train_command(config: dict[str, Any]) -> str:
    """The command that trains the run again (into ``runs/``)."""
    env_id = config.get("env_id", ENV_ID)
    label = config.get("label")
    return (
        f"python -m agents.train --env-id {env_id} --algo {config['algo']} "
        f"--map {config['map']} --seed {config['seed']}"
        + (f" --label {label}" if label else "")
        + " --out runs"
    )


def warm_start_text(run_dir: Path, init: dict[str, Any]) -> str:
    """The model a run started from (its config's ``init_from``): its clone stage's in
    ``imitation/`` when that model's digest is the one recorded, else the recorded path."""
    recorded = str(init.get("model_digest", ""))
    clone_model = model_path(clone_dir(run_dir))
    if clone_model.is_file() and model_digest(clone_model).hex() == recorded:
        return f"its clone stage, `{shown_path(clone_model)}` (digest `{recorded}`)"
    return f"`{init.get('path')}` (as recorded; digest `{recorded}`)"


def model_card_markdown(run_dir: Path, config: dict[str, Any], digest: str, results: Path) -> str:
    """The card of the finished run in ``run_dir`` (its ``config``), whose model's digest is
    ``digest`` (hex), evaluated in ``results``."""
    env_id = config.get("env_id", ENV_ID)
    task = task_of(env_id)
    summary = next(env["summary"] for env in registered_envs() if env["id"] == env_id)
    label = run_label(config)
    model = shown_path(model_path(run_dir))
    init = config.get("init_from")
    rows = [
        ("task", f"{task} (`{env_id}`): {summary}"),
        ("map", f"`{config['map']}`"),
        ("algorithm", f"`{config['algo']}`" + (f" (`{label}`)" if label != config["algo"] else "")),
        ("recipe", recipe_text(config)),
        ("training seed", str(config["seed"])),
        ("timesteps", f"{config['timesteps_done']:,}"),
        ("training wall-clock (min): clone stage + PPO", wall_clock_text(run_dir, config)),
        ("training layouts", range_text(config)),
        ("machine", machine_text(config)),
        ("code", commit_text(config)),
        *([("warm start", warm_start_text(run_dir, init))] if isinstance(init, dict) else []),
        ("model digest", f"`{digest}` (in `{model_digest_path(run_dir).name}` beside the model)"),
    ]  # fmt: skip
    versions = config.get("versions") or {}
    lines = [
        f"# Model card: {learned_agent_name(label, config['map'])}, training seed {config['seed']}",
        "",
        "<!-- Generated by `python -m agents.model_cards`: do not edit by hand. -->",
        "",
        f"The model is `{model}`; its run's record is `{shown_path(config_path(run_dir))}`.",
        "",
        "| | |",
        "|---|---|",
        *(markdown_row([key, value]) for key, value in rows),
        "",
        "## Train it again",
        "",
        "```",
        train_command(config),
        "```",
        "",
        *(
            [
                "This trains the recipe's present entry, changed since (above); for the "
                "recipe the run trained with, give `--hyperparams` a file holding its "
                f"{CONFIG_FILE}'s `hyperparams` under `{config.get('env_id', ENV_ID)}` -> "
                f"`{config['map']}`.",
                "",
            ]
            if recipe_changes(config)
            else []
        ),
        "## Evaluation",
        "",
        *evaluation_sections(config, results),
        "Evaluate it yourself (its run's settings, the policy's mode or sampled as the recipe "
        "says; the model is checked against its recorded digest before it is loaded):",
        "",
        "```",
        f"python -m tactile_search.benchmark --policy {model} --json result.json",
        "```",
        "",
        "## Versions",
        "",
        "| package | version |",
        "|---|---|",
        *(markdown_row([str(name), f"`{version}`"]) for name, version in versions.items()),
        "",
        "## Security",
        "",
        f"A `{MODEL_FILE}` holds pickled Python objects: loading it runs code of its author's "
        "choosing. Load it only from a source you trust. The benchmark refuses a model that no "
        "longer matches the digest recorded beside it; the digest tells a changed file, not a "
        "trustworthy one.",
    ]
    return "\n".join(lines) + "\n"


def write_model_card(run_dir: Path, results: Path = PUBLISHED_RESULTS) -> Path:
    """Records the digest of the finished run ``run_dir``'s model beside it and writes its
    card from its config and the evaluations in ``results``; returns the card's path.
    ``ValueError`` naming the run if it is not a finished run."""
    run_dir = Path(run_dir)
    config = read_run_config(run_dir, required=("algo", "map", "seed", "versions"))
    if not is_finished(run_dir, config):
        raise ValueError(f"{run_dir} is not a finished run: it has no model card to write")
    digest = write_digest(model_path(run_dir))
    path = model_card_path(run_dir)
    write_atomically(path, model_card_markdown(run_dir, config, digest, Path(results)))
    return path


def write_model_cards(run_dirs: Sequence[Path], results: Path = PUBLISHED_RESULTS) -> list[Path]:
    """``write_model_card`` for every run of ``run_dirs``."""
    return [write_model_card(run_dir, results) for run_dir in run_dirs]
