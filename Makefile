# tactile_search: `make demo` and `make test` are all a new machine needs (they create .venv).
# `make help` lists the targets.

SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
export VIRTUAL_ENV := $(abspath $(VENV))
export PATH := $(abspath $(VENV))/bin:$(PATH)

.DEFAULT_GOAL := help
.PHONY: help demo results test test-env rust-test build build-dev bench performance fuzz lint rust-lint python-lint format clean paper stubs wheel wheel-check docs

help: ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  %-10s %s\n", $$1, $$2}'

$(VENV)/bin/python:
	python3 -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip "maturin>=1.16,<2"

# One stamp per extra, so a second run installs nothing new.
$(VENV)/.extra-%: pyproject.toml | $(VENV)/bin/python
	$(PIP) install --quiet "maturin>=1.16,<2" $$($(PY) -c "import tomllib; d = tomllib.load(open('pyproject.toml', 'rb'))['project']; print(' '.join(d['dependencies'] + d['optional-dependencies']['$*']))")
	touch $@

build: $(VENV)/.extra-plots ## compile the Rust core (release) and install the package into .venv
	PIP_QUIET=1 $(VENV)/bin/maturin develop --release --quiet

build-dev: $(VENV)/.extra-dev $(VENV)/.extra-agents build ## build, plus the test, lint and agent tools (torch, SB3)

demo: $(VENV)/.extra-agents build ## build, install, train two agents briefly, evaluate with the baselines (results/)
	$(PY) -m experiments.demo --out results/demo_gpis.png
	$(PY) -m agents.pipeline --budget demo

results: $(VENV)/.extra-agents $(VENV)/.extra-scale build ## the documented budget: train every agent, evaluate, write docs/RESULTS.md
	$(PY) -m agents.pipeline --budget full

# Two tracks side by side, each in order: the Rust lints (in their own target dir, so they
# neither wait for the extension's build nor undo it) and the environment (venv, extras,
# release build); then the Python lints beside cargo test (release: on the build's
# dependencies), and pytest on every core. docs/DESIGN.md §12 says where the time goes.
test: ## cargo fmt/clippy, ruff, cargo test and pytest (Ray tests on a local cluster)
	$(MAKE) --no-print-directory -j2 --output-sync=target rust-lint test-env
	$(MAKE) --no-print-directory -j2 --output-sync=target python-lint rust-test
	$(PY) -m pytest -q -n auto --dist loadfile --durations=15

rust-test: ## cargo test, every crate of the workspace, release
	cargo test --workspace --release

test-env: ## the venv with every extra the tests need, and the release build, one step at a time
	$(MAKE) --no-print-directory -j1 build-dev $(VENV)/.extra-scale $(VENV)/.extra-docs $(VENV)/.extra-datasets

# The wheel anyone installs: abi3 (one wheel for CPython 3.10 and later), linked by zig
# against glibc 2.28 (the manylinux_2_28 tag; a plain build here takes this machine's newer
# glibc's tag), from the working tree, in its own target dir: it neither waits for the
# extension's build nor undoes it. (Not `build --sdist`, which builds from the unpacked
# sdist: its files' fixed timestamps would let cargo reuse a stale core in that dir.)
wheel: $(VENV)/.extra-release ## the abi3 wheel (manylinux_2_28, linked by zig) and the sdist, into dist/
	rm -f dist/tactile_search-*
	CARGO_TARGET_DIR=$(abspath target/wheel) $(VENV)/bin/maturin build --release --zig --compatibility manylinux_2_28 --out dist
	$(VENV)/bin/maturin sdist --out dist
	$(VENV)/bin/auditwheel show dist/tactile_search-*.whl

wheel-check: wheel ## install the wheel into a fresh venv of each Python here, no Rust on PATH: check_env and the benchmark on every id
	$(PY) scripts/wheel_install_check.py

# Every warning is an error (-W) and every reference is checked (-n): a broken link fails it.
# SPHINXOPTS="-D repository_url=URL" links repository files to their web view (docs/site/conf.py).
SPHINXOPTS ?=
docs: $(VENV)/.extra-docs build ## the documentation site (docs/site/: Sphinx, MyST, furo) into docs/_build/html
	$(PY) -m sphinx -W --keep-going -n -q $(SPHINXOPTS) -c docs/site docs docs/_build/html

paper: build ## regenerate docs/paper/ figures and docs/PAPER.md's table (experiments/paper)
	$(PY) -m experiments.paper --out docs/paper

bench: build-dev $(VENV)/.extra-bench $(VENV)/.extra-scale ## every benchmark: prints its figures, writes them to results/*.json, then renders docs/PERFORMANCE.md
	cargo bench -p env_core --bench gpis_append
	cargo bench -p env_core --bench scene
	cargo bench -p env_core --bench probe
	$(PY) -m benchmarks.performance_page --collect-criterion target/criterion --results results
	$(PY) -m benchmarks.gpis_append --out results/gpis_append.png --json results/gpis_append.json
	cargo run --release --quiet -p env_core --example physics_tradeoffs
	cargo run --release --quiet -p env_core --example batch_scaling
	$(PY) -m benchmarks.prior_rows --json results/prior_rows.json
	$(PY) -m benchmarks.peer_envs --json results/peer_envs.json
	$(PY) -m benchmarks.peer_envs --maps gpis --probe-maps gpis --variant threads=1 --json results/peer_envs_threads.json
	$(PY) -m benchmarks.env_threads_side_by_side --json results/env_threads_side_by_side.json
	$(PY) -m benchmarks.learner_speed --json results/learner_speed.json
	$(PY) -m benchmarks.env_throughput --vector-only --action-modes wrist probe --json results/env_throughput.json
	$(PY) -m benchmarks.vector_overhead --json results/vector_overhead.json
	$(PY) -m benchmarks.construction --json results/construction.json
	$(PY) -m benchmarks.soak --out results/soak.png --json results/soak.json
	$(PY) -m benchmarks.ray_grid --json results/ray_grid.json
	$(MAKE) --no-print-directory performance

# The page in the repository is rendered from docs/performance/ (make performance
# PERFORMANCE_RESULTS=docs/performance), whose JSON files are committed beside it.
PERFORMANCE_RESULTS ?= results
performance: | $(VENV)/bin/python ## render docs/PERFORMANCE.md from the benchmarks' JSON in results/ (runs none)
	$(PY) -m benchmarks.performance_page --results $(PERFORMANCE_RESULTS) --out docs/PERFORMANCE.md

fuzz: build-dev ## the long fuzz run: the Rust and Python property tests with many cases (prints counts)
	PROPTEST_CASES=25000 cargo test --release -p env_core --test fuzz_gpis --test fuzz_settings_and_actions
	HYPOTHESIS_PROFILE=long $(PY) -m pytest -q tests/test_fuzz_*.py --hypothesis-show-statistics

stubs: $(VENV)/.extra-dev build ## regenerate the stub's settings part and docs/ENVIRONMENTS.md from the core
	$(PY) scripts/generate_stub.py
	$(PY) scripts/environments_page.py

lint: rust-lint python-lint ## cargo fmt --check, clippy -D warnings, ruff check and format --check, stub up to date, mypy

# Every target without the python feature, then the library with it: the feature adds only
# the bindings (env_core/src/bindings/, no tests of their own there); the tests, benches and
# examples are the same code either way.
rust-lint: ## cargo fmt --check and clippy -D warnings, with and without the python feature
	cargo fmt --all -- --check
	CARGO_TARGET_DIR=target/lint cargo clippy --workspace --all-targets -- -D warnings
	CARGO_TARGET_DIR=target/lint cargo clippy --workspace --lib --features python -- -D warnings

python-lint: $(VENV)/.extra-dev build ## the stub up to date with the core, ruff check and format --check, mypy on the package
	$(PY) scripts/generate_stub.py --check
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy

format: $(VENV)/.extra-dev ## apply cargo fmt and ruff (format and fixes)
	cargo fmt --all
	$(VENV)/bin/ruff check --fix .
	$(VENV)/bin/ruff format .

clean: ## remove build products and the virtual environment
	cargo clean
	rm -rf $(VENV) results
