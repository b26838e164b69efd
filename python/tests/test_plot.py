"""nvector.plot draws the CLI's picture (one description, nvector.figure),
each panel at its own scale, and the example runs."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import to_rgba

import nvector

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "simulate_run_plot.py"


@pytest.fixture(scope="module")
def solved() -> tuple[dict, dict]:
    mission = nvector.simulate("paper", seed=3, steps=2000)
    return mission, nvector.run(mission, contractor="best")


def test_plot_draws_the_shared_description(solved: tuple[dict, dict], tmp_path: Path) -> None:
    mission, result = solved
    desc = nvector.figure(result, mission)
    names = [layer["name"] for layer in desc["layers"]]
    assert names[0] == "trajectory" and names[-2:] == ["truth_path", "truth_landmarks"]
    # 2001 boxes: drawn as their envelope, under the truth.
    assert "envelope of the 2001 position boxes" in desc["layers"][0]["label"]
    groups = next(layer for layer in desc["layers"] if layer["name"] == "groups")
    assert groups["label"].startswith(f"{len(result['matching'])} proved group")
    assert "of at most 4 landmarks" in groups["label"]

    fig, ax = plt.subplots()
    assert nvector.plot(result, mission, ax=ax) is ax
    rect_layers = [layer for layer in desc["layers"] if layer["kind"] == "rects"]
    assert [len(c.get_paths()) for c in ax.collections[: len(rect_layers)]] == [len(layer["rects"]) for layer in rect_layers]
    trajectory = ax.collections[0]
    assert tuple(trajectory.get_facecolor()[0][:3]) == pytest.approx(to_rgba(_plot_colour(desc, "trajectory"))[:3])
    assert trajectory.get_facecolor()[0][3] == pytest.approx(desc["layers"][0]["fill_alpha"])
    # The truth path on top of every box, every point of the description.
    (line,) = ax.lines
    path = next(layer for layer in desc["layers"] if layer["name"] == "truth_path")
    assert len(line.get_xdata()) == len(path["points"])
    assert line.get_zorder() > max(c.get_zorder() for c in ax.collections[: len(rect_layers)])
    # Axes in metres, the diameters in metres in the title, a legend of every layer.
    assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
    d = result["metrics"]["max_trajectory_diameter"]
    assert f"max trajectory diameter {d:.1f} m" in ax.get_title() or f"{d:.3f} m" in ax.get_title()
    assert "best" in ax.get_title()
    legend = ax.get_legend()
    assert legend is not None
    assert [t.get_text().replace("\n", " ") for t in legend.get_texts()] == [layer["label"] for layer in desc["layers"]]
    fig.savefig(tmp_path / "fig.png")
    assert (tmp_path / "fig.png").stat().st_size > 1000
    plt.close(fig)


def _inside(inner: Any, outer: Any, slack: float = 0.5) -> bool:
    return bool(inner.x0 >= outer.x0 - slack and inner.x1 <= outer.x1 + slack and inner.y0 >= outer.y0 - slack and inner.y1 <= outer.y1 + slack)


@pytest.mark.parametrize("layout", ["new figure", "two panels, no layout", "two panels, constrained", "small figure"])
def test_legend_and_labels_inside_the_canvas(solved: tuple[dict, dict], tmp_path: Path, layout: str) -> None:
    """As a person sees the PNG: every legend, axis label and title lies
    inside the figure (nothing cut at its edges), no legend lies over an
    axes (its own or a neighbour panel's), and both axes say metres."""
    mission, best = solved
    if layout == "new figure":
        axes = [nvector.plot(best, mission)]
        fig = axes[0].figure
    else:
        size, kw = ((6, 4), {}) if layout == "small figure" else ((12, 5), {"layout": "constrained"} if "constrained" in layout else {})
        fig, grid = plt.subplots(1, 1 if layout == "small figure" else 2, figsize=size, **kw)
        axes = list(np.atleast_1d(grid))
        basic = nvector.run(mission, contractor="none")
        for ax, result in zip(axes, [basic, best]):
            nvector.plot(result, mission, ax=ax)
    png = tmp_path / "fig.png"
    fig.savefig(png, dpi=100)
    assert png.stat().st_size > 1000
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    canvas = fig.bbox
    for ax in axes:
        assert ax.get_xlabel() == "x (m)" and ax.get_ylabel() == "y (m)"
        legend = ax.get_legend()
        assert legend is not None
        parts = {
            "legend": legend.get_window_extent(renderer),
            "x label": ax.xaxis.label.get_window_extent(renderer),
            "y label": ax.yaxis.label.get_window_extent(renderer),
            "title": ax.title.get_window_extent(renderer),
        }
        for name, box in parts.items():
            assert box.width > 0 and box.height > 0, f"{layout}: {name} not drawn"
            assert _inside(box, canvas), f"{layout}: the {name} {box} lies outside the figure {canvas}"
        for other in fig.axes:
            assert not parts["legend"].overlaps(other.get_window_extent(renderer)), f"{layout}: a legend over an axes"
    plt.close(fig)


def _plot_colour(desc: dict, name: str) -> str:
    return str(next(layer for layer in desc["layers"] if layer["name"] == name)["colour"])


def test_each_panel_at_its_own_scale(solved: tuple[dict, dict]) -> None:
    mission, best = solved
    basic = nvector.run(mission, contractor="none")
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    nvector.plot(basic, mission, ax=left)
    nvector.plot(best, mission, ax=right)
    fig.canvas.draw()
    for ax, result in ((left, basic), (right, best)):
        x0, x1, y0, y1 = nvector.figure(result, mission)["view"]
        lo, hi = ax.get_xlim()
        assert lo <= x0 + 1e-9 and x1 - 1e-9 <= hi
        # Fitted: no more than twice the result's own span (one scale on x
        # and y may widen one axis).
        assert hi - lo <= 2.5 * max(x1 - x0, y1 - y0)
    span = lambda ax: ax.get_xlim()[1] - ax.get_xlim()[0]  # noqa: E731
    assert basic["metrics"]["max_trajectory_diameter"] > best["metrics"]["max_trajectory_diameter"]
    assert span(left) != pytest.approx(span(right))
    plt.close(fig)


def test_python_and_cli_figures_share_their_description(solved: tuple[dict, dict], cli: Any, tmp_path: Path) -> None:
    mission, result = solved
    (tmp_path / "m.json").write_text(nvector.dumps(mission), encoding="utf-8")
    (tmp_path / "r.json").write_text(nvector.dumps(result), encoding="utf-8")
    cli.run("plot", str(tmp_path / "r.json"), "--mission", str(tmp_path / "m.json"), "--out", str(tmp_path / "f.svg"))
    svg = (tmp_path / "f.svg").read_text(encoding="utf-8")
    desc = nvector.figure(tmp_path / "r.json", tmp_path / "m.json")
    assert desc["title"] in svg and desc["subtitle"] in svg
    assert desc["x_label"] in svg and desc["y_label"] in svg


def test_plot_from_files_without_truth(solved: tuple[dict, dict], tmp_path: Path) -> None:
    _, result = solved
    path = tmp_path / "r.json"
    path.write_text(nvector.dumps(result), encoding="utf-8")
    ax = nvector.plot(path)
    assert len(ax.lines) == 0
    labels = [t.get_text().replace("\n", " ") for t in ax.get_legend().get_texts()]
    assert "true path" not in labels and any("proved group" in t for t in labels)
    plt.close(ax.figure)


def whole(fields: dict[str, Any]) -> dict[str, Any]:
    """A result (``nvector-result/1``, all its required fields): ``fields``
    over one with no boxes; ``metrics`` entries set one by one."""
    result: dict[str, Any] = {
        "format": "nvector-result/1",
        "mission": "m",
        "status": "consistent",
        "options": {"contractor": "best", "max_rounds": 10, "tolerance": 0.0},
        "metrics": {
            "contractions": 0,
            "elapsed_ms": 0.0,
            "matched_detections": 0,
            "max_detection_diameter": 0.0,
            "max_trajectory_diameter": 0.0,
            "mean_trajectory_diameter": 0.0,
            "rounds": 0,
        },
        "detections": [],
        "landmarks": [],
        "matching": [],
    }
    for k, v in fields.items():
        if k == "metrics":
            result["metrics"].update(v)
        else:
            result[k] = v
    return result


def test_plot_skips_unbounded_and_empty_boxes() -> None:
    result = whole({"trajectory": [[[0, 1], [0, 1]], [["-inf", 1], [0, 1]], "empty"]})
    ax = nvector.plot(result)
    assert len(ax.collections[0].get_paths()) == 1
    plt.close(ax.figure)


def test_plot_huge_values_and_nothing_to_draw(tmp_path: Path) -> None:
    result = whole(
        {
            "mission": "u",
            "trajectory": [[["-inf", "inf"], ["-inf", "inf"]], [[-1e308, 1e308], [0, 1]], [[1e300, 1.7e308], [-1.7e308, -1e300]]],
            "detections": [[[-1e308, 1e308], [5, 6]]],
            "landmarks": [[[0, 0], [0, 0]]],
            "matching": [[0]],
            "metrics": {"max_trajectory_diameter": "inf", "mean_trajectory_diameter": "inf"},
        }
    )
    mission = {"truth": {"positions": [[0, 0], [1e308, -1e308], [-1.7e308, 1.7e308]], "landmarks": [[0, 0]]}}
    ax = nvector.plot(result, mission)
    assert "unbounded" in ax.get_title()
    ax.figure.savefig(tmp_path / "huge.png")
    plt.close(ax.figure)
    ax = nvector.plot(whole({"trajectory": ["empty"]}))
    ax.figure.savefig(tmp_path / "empty.png")
    assert ax.get_legend() is None
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
