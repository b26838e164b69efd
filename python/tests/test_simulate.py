"""nvector.simulate against `nvector simulate`, bit for bit."""

from __future__ import annotations

import json

import pytest
from conftest import Cli, canonical

import nvector

CASES = [
    # (python keyword arguments, CLI flags)
    ({"seed": 1, "steps": 1500}, ["--seed", "1", "--steps", "1500"]),
    ({"seed": 7, "steps": 800, "landmarks": 6, "operator": True}, ["--seed", "7", "--steps", "800", "--landmarks", "6", "--operator"]),
    ({"seed": 3, "steps": 1200, "noise": 2.5}, ["--seed", "3", "--steps", "1200", "--noise", "2.5"]),
    ({"seed": 11, "steps": 3000, "layout": "ring", "landmarks": 5}, ["--seed", "11", "--steps", "3000", "--layout", "ring", "--landmarks", "5"]),
    ({"seed": 12, "steps": 3000, "layout": "random"}, ["--seed", "12", "--steps", "3000", "--layout", "random"]),
    ({"seed": 4, "steps": 2000, "range_only": True}, ["--seed", "4", "--steps", "2000", "--range-only"]),
    ({"seed": 5, "steps": 2000, "false_detections": 3}, ["--seed", "5", "--steps", "2000", "--false-detections", "3"]),
    ({"seed": 2**64 - 1, "steps": 500}, ["--seed", str(2**64 - 1), "--steps", "500"]),
]


@pytest.mark.parametrize("kwargs,flags", CASES)
def test_paper_agrees_with_the_cli(cli: Cli, kwargs: dict, flags: list[str]) -> None:
    mission = nvector.simulate("paper", **kwargs)
    text = cli.json("simulate", "--scenario", "paper", *flags)
    assert canonical(mission) == text
    assert mission == json.loads(text)


def test_auv_agrees_with_the_cli(cli: Cli) -> None:
    mission = nvector.simulate("auv", seed=2, steps=4000, operator=True)
    assert mission["model"] == "auv3d"
    assert canonical(mission) == cli.json("simulate", "--scenario", "auv", "--seed", "2", "--steps", "4000", "--operator")


def test_default_paper_mission(cli: Cli) -> None:
    mission = nvector.simulate("paper")
    assert mission["steps"] == 10_000 and mission["landmark_count"] == 4
    assert canonical(mission) == cli.json("simulate", "--scenario", "paper")


def test_deterministic_and_seed_dependent() -> None:
    a = nvector.simulate("paper", seed=9, steps=600)
    assert nvector.simulate("paper", seed=9, steps=600) == a
    assert nvector.simulate("paper", seed=10, steps=600) != a
