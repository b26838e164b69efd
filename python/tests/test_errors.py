"""Bad input raises a Python exception naming the JSON path, as the CLI's
message does; nothing crashes the interpreter."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
from conftest import Cli

import nvector


@pytest.fixture(scope="module")
def mission() -> dict:
    return nvector.simulate("paper", seed=2, steps=2000)


def cli_message(cli: Cli, *args: str, stdin: str | None = None) -> str:
    done = cli.run(*args, stdin=stdin, check=False)
    assert done.returncode == 1, done.stderr
    return done.stderr


@pytest.mark.parametrize(
    "change,path",
    [
        (lambda m: m["detections"][0].__setitem__("range", [5, 4]), "detections[0].range"),
        (lambda m: m["detections"][1].__setitem__("rnage", [1, 2]), "detections[1].rnage"),
        (lambda m: m.__setitem__("dt", "fast"), "dt"),
        (lambda m: m["inputs"]["speed"].__setitem__("error", -1), "inputs.speed.error"),
        (lambda m: m.__setitem__("initial_position", [[0, 1]]), "initial_position"),
        (lambda m: m.__setitem__("format", "nvector-mission/9"), "format"),
    ],
)
def test_bad_mission_names_the_path_like_the_cli(cli: Cli, tmp_path: Path, mission: dict, change, path: str) -> None:
    bad = copy.deepcopy(mission)
    change(bad)
    with pytest.raises(nvector.InputError) as info:
        nvector.run(bad)
    assert info.value.path == path
    assert str(info.value).startswith(path + ": ")
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(bad), encoding="utf-8")
    # The CLI says the same thing after the file name.
    assert f"{file}: {info.value}" in cli_message(cli, "run", str(file))
    with pytest.raises(nvector.InputError) as from_file:
        nvector.run(file)
    assert from_file.value.path == path and from_file.value.file == str(file)
    assert str(from_file.value) == f"{file}: {info.value}"
    # InputError is a ValueError.
    assert isinstance(info.value, ValueError)


def test_values_without_json_form_name_the_path(mission: dict) -> None:
    cases = [
        (lambda m: m["detections"][2].__setitem__("range", [1.0, float("nan")]), "detections[2].range[1]", "NaN"),
        (lambda m: m["meta"].__setitem__(3, "x"), "meta", "keys must be strings"),
        (lambda m: m["meta"].__setitem__("s", {1, 2}), "meta.s", "set"),
        (lambda m: m["meta"].__setitem__("big", 2**70), "meta.big", "integer out of range"),
        (lambda m: m["detections"][0].__setitem__("step", object()), "detections[0].step", "object"),
    ]
    for change, path, words in cases:
        bad = copy.deepcopy(mission)
        change(bad)
        with pytest.raises(nvector.InputError) as info:
            nvector.run(bad)
        assert info.value.path == path, path
        assert words in info.value.message


def test_deep_nesting_is_an_error_not_a_crash(mission: dict) -> None:
    deep: list = []
    for _ in range(100_000):
        deep = [deep]
    bad = dict(mission, meta={"deep": deep})
    with pytest.raises(nvector.InputError, match="nested more than"):
        nvector.run(bad)
    with pytest.raises(nvector.InputError):
        nvector.contract(deep, 1)


def test_invalid_json_file(tmp_path: Path) -> None:
    file = tmp_path / "broken.json"
    file.write_text('{"format": "nvector-mission/1",', encoding="utf-8")
    with pytest.raises(nvector.InputError, match="invalid JSON") as info:
        nvector.run(file)
    assert info.value.file == str(file)
    with pytest.raises(FileNotFoundError):
        nvector.run(tmp_path / "missing.json")


def test_bad_run_options(mission: dict) -> None:
    with pytest.raises(nvector.InputError) as info:
        nvector.run(mission, contractor="fastest")
    assert info.value.path == "contractor" and "unknown contractor" in info.value.message
    with pytest.raises(nvector.InputError, match="contractor"):
        nvector.run(mission, contractor="exact")  # exponential: refused in SLAM, as by the CLI
    with pytest.raises(nvector.InputError) as info:
        nvector.run(mission, tolerance=float("nan"))
    assert info.value.path == "tolerance"
    with pytest.raises(OverflowError):
        nvector.run(mission, max_rounds=-1)
    with pytest.raises(TypeError, match="progress"):
        nvector.run(mission, progress=5)  # type: ignore[arg-type]
    with pytest.raises(nvector.InputError, match="expected an object") as info:
        nvector.run(42)  # type: ignore[arg-type]
    assert info.value.path == ""


@pytest.mark.parametrize(
    "boxes,n,contractor,path",
    [
        ([[[0, 1]], [[3, 2]]], 1, "best", "boxes[1][0]"),
        ([[[0, 1]], [[0, 1], [0, 1]]], 1, "best", "boxes[1]"),
        ([[[0, 1]]], 0, "best", "n"),
        ([[[0, 1]]], 1, "fast", "contractor"),
        ([], 1, "best", "boxes"),
        ([[[0, "x"]]], 1, "best", "boxes[0][0][1]"),
        ([[[0, 1]]] * 41, 2, "exact", ""),
    ],
)
def test_bad_contract_requests_like_the_cli(cli: Cli, boxes: list, n: int, contractor: str, path: str) -> None:
    with pytest.raises(nvector.InputError) as info:
        nvector.contract(boxes, n, contractor)
    if path:
        assert info.value.path == path
    request = {"format": "nvector-contract/1", "n": n, "boxes": boxes, "contractor": contractor}
    assert str(info.value) in cli_message(cli, "contract", stdin=json.dumps(request))


def test_bad_simulate_options(cli: Cli) -> None:
    for kwargs, path in [
        ({"scenario": "moon"}, "scenario"),
        ({"scenario": "paper", "noise": -1.0}, "noise"),
        ({"scenario": "paper", "noise": float("inf")}, "noise"),
        ({"scenario": "paper", "landmarks": 65}, "landmarks"),
        ({"scenario": "paper", "steps": 2_000_001}, "steps"),
        ({"scenario": "paper", "landmarks": 10**9}, "landmarks"),
        ({"scenario": "paper", "layout": "spiral"}, "layout"),
        ({"scenario": "auv", "range_only": True}, "range_only"),
        ({"scenario": "paper", "false_detections": 10**6}, "false_detections"),
    ]:
        with pytest.raises(nvector.InputError) as info:
            nvector.simulate(**kwargs)
        assert info.value.path == path, kwargs
    with pytest.raises(OverflowError):
        nvector.simulate("paper", seed=-1)


def test_errors_pickle_and_print() -> None:
    import pickle

    e = nvector.InputError("detections[3].range", "lower bound 5 is above upper bound 4", file="m.json")
    again = pickle.loads(pickle.dumps(e))
    assert (again.path, again.message, again.file) == (e.path, e.message, e.file)
    assert str(again) == "m.json: detections[3].range: lower bound 5 is above upper bound 4"
