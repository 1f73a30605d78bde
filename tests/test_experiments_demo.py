"""The demo runs, writes its figure, and touch improves the reconstruction."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

from experiments import demo


def test_demo_writes_its_figure_and_touch_improves_iou(tmp_path: Path) -> None:
    out = tmp_path / "demo.png"
    result = demo.run(seed=0, shape=(32, 64), prior_mean=0.01, out=out)
    assert out.stat().st_size > 10_000
    assert result["contacts"] == 15
    assert result["iou_depth_and_touch"] > 0.8
    assert result["iou_depth_and_touch"] > result["iou_depth_only"] + 0.3


def test_demo_cli_prints_both_ious(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    demo.main(["--out", str(tmp_path / "cli.png"), "--grid", "16", "32"])
    printed = capsys.readouterr().out
    assert "depth only:" in printed and "depth + touch:" in printed
    assert (tmp_path / "cli.png").exists()
