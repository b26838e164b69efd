"""nvector.tdoa: the same result as `nvector tdoa` (bit for bit, the clock
aside), and bad input named by its JSON path."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import Cli, canonical

import nvector

CLOCK = ("metrics", "elapsed_ms")


def test_tdoa_equals_the_cli(cli: Cli, tmp_path: Path) -> None:
    problem = tmp_path / "radar.json"
    cli.run("simulate", "--scenario", "radar", "--seed", "2", "--emitters", "3", "--pulses", "40", "--out", str(problem))
    out = tmp_path / "result.json"
    cli.run("tdoa", str(problem), "--out", str(out), "--budget", "48")
    from_cli = json.loads(out.read_text(encoding="utf-8"))
    local = nvector.tdoa(problem, budget=48)
    assert local["format"] == "nvector-tdoa-result/1"
    assert local["score"]["truth_inside"] is True
    assert local["score"]["matching_errors"] == 0
    assert canonical(local, CLOCK) == canonical(from_cli, CLOCK)
    as_dict = nvector.tdoa(json.loads(problem.read_text(encoding="utf-8")), budget=48)
    assert canonical(as_dict, CLOCK) == canonical(from_cli, CLOCK)


def test_tdoa_bad_input_names_the_path() -> None:
    bad = {"format": "nvector-tdoa/1", "propagation_speed": [1, 2], "receivers": [],
           "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 1]}]}]}
    with pytest.raises(nvector.InputError) as e:
        nvector.tdoa(bad)
    assert e.value.path == "pulses[0].arrivals[0].receiver"
    with pytest.raises(nvector.InputError) as e:
        nvector.tdoa({**bad, "pulses": []}, contractor="bogus")
    assert e.value.path == "contractor"
