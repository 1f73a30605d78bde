"""``benchmarks.env_threads_side_by_side``: its processes really run side by side and step,
each setting gets its machine rate, and the summary compares the two."""

from __future__ import annotations

import re

import pytest

from benchmarks import env_threads_side_by_side


def test_each_process_count_gets_a_positive_rate_for_both_thread_counts(
    capsys: pytest.CaptureFixture[str],
) -> None:
    env_threads_side_by_side.main(["--processes", "2", "--rounds", "1", "--seconds", "0.5"])
    out = capsys.readouterr().out
    rates = {
        int(threads): float(rate)
        for threads, rate in re.findall(r"2 processes, threads=(\d): +([\d.]+) probes/s", out)
    }
    assert set(rates) == {1, 2}
    assert all(rate > 0 for rate in rates.values())
    summary = re.search(r"2 processes: +([\d.]+) +([\d.]+) +([\d.]+)x", out)
    assert summary is not None, out
    one, two, ratio = map(float, summary.groups())
    assert (one, two) == (rates[1], rates[2])
    assert ratio == pytest.approx(two / one, abs=0.01)


def test_a_duration_that_is_not_positive_is_refused() -> None:
    with pytest.raises(SystemExit):
        env_threads_side_by_side.main(["--seconds", "0"])
