"""nvector.plot draws what the CLI's figures draw, and the example runs."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest
from matplotlib.colors import to_rgba

import nvector
from nvector import _plot

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "simulate_run_plot.py"


@pytest.fixture(scope="module")
def solved() -> tuple[dict, dict]:
    mission = nvector.simulate("paper", seed=3, steps=2000)
    return mission, nvector.run(mission, contractor="best")


def test_plot_draws_every_kind_of_box(solved: tuple[dict, dict], tmp_path: Path) -> None:
    mission, result = solved
    fig, ax = plt.subplots()
    assert nvector.plot(result, mission, ax=ax) is ax
    collections = ax.collections
    sizes = [len(c.get_paths()) for c in collections]
    # Trajectory: every box (2001 > 1500, so every 2nd and the last).
    assert sizes[0] == len(result["trajectory"][::2]) + 1
    assert collections[0].get_edgecolor()[0].tolist() == list(to_rgba(_plot.TRAJECTORY))
    # Detections by group colour, then the landmarks in red.
    grouped = {i for g in result["matching"] for i in g}
    assert sum(sizes[1:-2]) == len(result["detections"])
    group_colours = {to_rgba(_plot.PALETTE[g]) for g in range(len(result["matching"]))}
    drawn = {tuple(c.get_edgecolor()[0]) for c in collections[1:-2]}
    assert group_colours <= drawn
    assert (len(grouped) == len(result["detections"])) == (to_rgba(_plot.UNGROUPED) not in drawn)
    landmarks = collections[-2]
    assert len(landmarks.get_paths()) == len(result["landmarks"])
    assert tuple(landmarks.get_facecolor()[0]) == pytest.approx(_plot.LANDMARK_FILL)
    # Truth: the path and the landmarks in black.
    assert len(ax.lines) == 1 and len(ax.lines[0].get_xdata()) == len(mission["truth"]["positions"])
    assert len(collections[-1].get_offsets()) == len(mission["truth"]["landmarks"])
    assert "best" in ax.get_title()
    fig.savefig(tmp_path / "fig.png")
    assert (tmp_path / "fig.png").stat().st_size > 1000
    plt.close(fig)


def test_plot_from_files_without_truth(solved: tuple[dict, dict], tmp_path: Path) -> None:
    _, result = solved
    path = tmp_path / "r.json"
    path.write_text(nvector.dumps(result), encoding="utf-8")
    ax = nvector.plot(path)
    assert len(ax.lines) == 0
    plt.close(ax.figure)


def test_plot_skips_unbounded_and_empty_boxes() -> None:
    result = {
        "trajectory": [[[0, 1], [0, 1]], [["-inf", 1], [0, 1]], "empty"],
        "detections": [],
        "landmarks": [],
        "matching": [],
    }
    ax = nvector.plot(result)
    assert len(ax.collections[0].get_paths()) == 1
    plt.close(ax.figure)


def test_example_script(tmp_path: Path) -> None:
    out = tmp_path / "slam.png"
    done = subprocess.run(
        [sys.executable, str(EXAMPLE), "--steps", "1500", "--seed", "2", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert done.returncode == 0, done.stderr
    assert "none:" in done.stdout and "best:" in done.stdout and "truth inside: True" in done.stdout
    assert out.stat().st_size > 10_000
