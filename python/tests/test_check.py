"""nvector.check: the constraints a mission's truth breaks, as `nvector check --json`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import Cli

import nvector


@pytest.fixture(scope="module")
def paper() -> dict:
    return nvector.simulate("paper", seed=4, steps=500, operator=True)


def test_a_simulated_mission_breaks_nothing(cli: Cli, tmp_path: Path, paper: dict) -> None:
    assert nvector.check(paper) == []
    path = tmp_path / "m.json"
    path.write_text(nvector.dumps(paper), encoding="utf-8")
    assert nvector.check(path) == []
    done = cli.run("check", str(path), "--json")
    assert json.loads(done.stdout)["violations"] == []


def test_a_planted_range_is_found_as_the_cli_finds_it(cli: Cli, tmp_path: Path, paper: dict) -> None:
    mission = json.loads(nvector.dumps(paper))
    lo, hi = (float(x) for x in mission["detections"][1]["range"])
    # Moved 2 m beyond the truth's distance, which is within [lo, hi].
    mission["detections"][1]["range"] = [hi + 2.0, hi + 3.0]
    found = nvector.check(mission)
    assert [v["path"] for v in found] == ["detections[1].range"]
    v = found[0]
    assert v["kind"] == "range" and v["unit"] == "m" and v["relation"] == "within"
    assert 2.0 <= v["excess"] <= 2.0 + (hi - lo) + 1e-9
    assert v["bound"] == [hi + 2.0, hi + 3.0]
    assert v["detection"] == 1 and v["outlier"] is False
    path = tmp_path / "bad.json"
    path.write_text(nvector.dumps(mission), encoding="utf-8")
    done = cli.run("check", str(path), "--json", check=False)
    assert done.returncode == 1
    assert json.loads(done.stdout)["violations"] == found
    assert "breaks 1 constraint" in done.stderr


def test_a_mission_without_truth_is_an_input_error(tmp_path: Path, paper: dict) -> None:
    mission = dict(paper)
    del mission["truth"]
    with pytest.raises(nvector.InputError) as e:
        nvector.check(mission)
    assert e.value.path == "truth"
    path = tmp_path / "m.json"
    path.write_text(nvector.dumps(mission), encoding="utf-8")
    with pytest.raises(nvector.InputError) as e:
        nvector.check(path)
    assert e.value.file == str(path)
