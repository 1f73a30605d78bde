"""The probe-grid command: the planner on each grid, paired against the first."""

from __future__ import annotations

import argparse

import pytest

from agents.probe_grid import main, parse_grid


def test_the_command_runs_the_planner_on_each_grid_and_pairs_them(capsys) -> None:
    main(["--episodes", "2", "--grids", "default", "probe_sweeps=5,probe_depths=4"])
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("| ")][1:]  # past the header
    assert [row.split(" | ")[0] for row in rows] == ["| default", "| probe_sweeps=5,probe_depths=4"]
    assert rows[0].endswith("| 0 / 0 |"), "a grid against itself has no discordant layouts"


def test_a_grid_is_default_or_settings() -> None:
    assert parse_grid("default") == {}
    assert parse_grid("probe_sweeps=21,probe_lanes=57") == {"probe_sweeps": 21, "probe_lanes": 57}
    for bad in ["probe_sweeps", "=3", "probe_sweeps=many"]:
        with pytest.raises(argparse.ArgumentTypeError):
            parse_grid(bad)


def test_a_setting_the_core_does_not_know_is_refused() -> None:
    with pytest.raises(TypeError, match="did you mean 'probe_sweeps'"):
        main(["--episodes", "1", "--grids", "probe_sweep=21"])
