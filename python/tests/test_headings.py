"""odometry2d through Python: nvector.simulate("woods") equals
`nvector simulate --scenario woods`, nvector.run accepts its new fields
(scan, sensor_offset, landmark_min_separation, null truth entries) and
returns headings, and nvector.plot draws them."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest
from conftest import Cli, canonical

import nvector


@pytest.fixture(scope="module")
def woods() -> tuple[dict, dict]:
    mission = nvector.simulate("woods", seed=2, steps=150)
    return mission, nvector.run(mission, contractor="none")


def test_woods_agrees_with_the_cli_and_has_the_new_fields(cli: Cli) -> None:
    mission = nvector.simulate("woods", seed=2, steps=150, landmarks=9, operator=True)
    assert canonical(mission) == cli.json("simulate", "--scenario", "woods", "--seed", "2", "--steps", "150", "--landmarks", "9", "--operator")
    assert mission["model"] == "odometry2d" and mission["landmark_count"] == 9
    assert mission["landmark_min_separation"] > 0
    assert len(mission["sensor_offset"]) == 2
    assert all("scan" in d and "landmark" in d for d in mission["detections"])
    assert len(mission["truth"]["headings"]) == 151


def test_woods_false_detections_agree_with_the_cli(cli: Cli) -> None:
    mission = nvector.simulate("woods", seed=3, steps=150, operator=True, false_detections=4)
    assert canonical(mission) == cli.json("simulate", "--scenario", "woods", "--seed", "3", "--steps", "150", "--operator", "--false-detections", "4")
    assert mission["max_outliers"] == 4 and mission["meta"]["false_detections"] == 4
    assert sum(1 for j in mission["truth"]["matching"] if j is None) == 4
    with pytest.raises(nvector.InputError) as info:
        nvector.simulate("woods", false_detections=100_001)
    assert info.value.path == "false_detections"


def test_woods_refuses_the_paper_only_options() -> None:
    for kwargs, path in [({"layout": "ring"}, "layout"), ({"range_only": True}, "range_only"), ({"noise": 2.0}, "noise"), ({"steps": 2_000_001}, "steps")]:
        with pytest.raises(nvector.InputError) as info:
            nvector.simulate("woods", **kwargs)
        assert info.value.path == path


def test_run_returns_headings_that_hold_the_truth(woods: tuple[dict, dict]) -> None:
    mission, result = woods
    headings = result["headings"]
    assert len(headings) == len(result["trajectory"]) == 151
    assert result["metrics"]["max_heading_width"] == pytest.approx(max(h[1] - h[0] for h in headings))
    assert result["score"]["truth_inside"] is True
    # The true heading lies in its interval at every step (checked here,
    # not only by the score).
    for t, (lo, hi) in zip(mission["truth"]["headings"], headings):
        assert lo <= t <= hi


def test_null_truth_entries_are_not_scored(woods: tuple[dict, dict]) -> None:
    mission, result = woods
    m = {**mission, "truth": {**mission["truth"]}}
    m["truth"]["positions"] = list(m["truth"]["positions"])
    m["truth"]["headings"] = list(m["truth"]["headings"])
    # A true heading far outside its interval, but null: not scored.
    m["truth"]["positions"][40] = None
    m["truth"]["headings"][40] = None
    r = nvector.run(m, contractor="none")
    assert r["trajectory"] == result["trajectory"] and r["headings"] == result["headings"]
    assert r["score"]["truth_inside"] is True
    m["truth"]["headings"][40] = result["headings"][40][1] + 1.0
    assert nvector.run(m, contractor="none")["score"]["truth_inside"] is False


def test_plot_draws_the_headings(woods: tuple[dict, dict]) -> None:
    mission, result = woods
    desc = nvector.figure(result, mission)
    heads = [layer for layer in desc["layers"] if layer["name"].startswith("headings")]
    assert heads and heads[0]["label"].startswith("heading (interval)")
    assert sum(len(layer["polygons"]) for layer in heads) >= 30
    fig, ax = plt.subplots()
    nvector.plot(result, mission, ax=ax)
    # Every layer is one collection or line, in order: the heading layers'
    # collections hold one path per wedge.
    for layer in heads:
        k = [x["name"] for x in desc["layers"] if x["kind"] != "path"].index(layer["name"])
        assert len(ax.collections[k].get_paths()) == len(layer["polygons"])
        # A wedge's first vertex is its apex, at a position box's centre.
        verts = ax.collections[k].get_paths()[0].vertices
        box = result["trajectory"][0]
        if layer["name"] == "headings":
            assert verts[0][0] == pytest.approx((box[0][0] + box[0][1]) / 2)
            assert verts[0][1] == pytest.approx((box[1][0] + box[1][1]) / 2)
    labels = [t.get_text().replace("\n", " ") for t in ax.get_legend().get_texts()]
    assert any(label.startswith("heading (interval)") for label in labels)
    assert "true heading" in labels
    plt.close(fig)


def test_a_unicycle2d_figure_has_no_headings() -> None:
    mission = nvector.simulate("paper", seed=3, steps=300)
    result = nvector.run(mission, contractor="none")
    desc = nvector.figure(result, mission)
    assert "headings" not in result
    assert not [layer for layer in desc["layers"] if "heading" in layer["label"]]
    assert not math.isnan(result["metrics"]["max_trajectory_diameter"])
