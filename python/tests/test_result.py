"""nvector.read_result reads a result through the compiled core's types of
``nvector-result/1`` (what ``nvector plot`` reads): what ``nvector run``
writes comes back as written; each fault is refused, named by its JSON
path (and the file, for a path); the figure reads results the same way."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

import nvector


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory, cli: Any) -> tuple[Path, dict[str, Any]]:
    """A result as the binary writes it (a mission with truth: `score`)."""
    d = tmp_path_factory.mktemp("result")
    mission = d / "mission.json"
    mission.write_text(json.dumps(nvector.simulate("paper", seed=4, steps=300)))
    out = d / "result.json"
    cli.run("run", str(mission), "--out", str(out))
    return out, json.loads(out.read_text())


def test_a_written_result_reads_back_as_written(written: tuple[Path, dict[str, Any]]) -> None:
    path, raw = written
    assert nvector.read_result(path) == raw
    assert nvector.read_result(str(path)) == raw
    assert nvector.read_result(raw) == raw
    assert "score" in raw and raw["format"] == "nvector-result/1"


@pytest.mark.parametrize(
    ("edit", "path", "words"),
    [
        (lambda r: r.update(bogus=1), "bogus", "unknown field"),
        (lambda r: r["trajectory"][0].__setitem__(0, [3, 2]), "trajectory[0][0]", "lower bound 3"),
        (lambda r: r["matching"].append([10**6]), "landmarks", "boxes for"),
        (lambda r: r["metrics"].__setitem__("rounds", "x"), "metrics.rounds", "expected"),
        (lambda r: r.update(status="weird"), "status", "unknown variant"),
    ],
)
def test_each_fault_is_named_by_its_path(
    written: tuple[Path, dict[str, Any]], tmp_path: Path, edit: Any, path: str, words: str
) -> None:
    bad = json.loads(json.dumps(written[1]))
    edit(bad)
    with pytest.raises(nvector.InputError) as e:
        nvector.read_result(bad)
    assert e.value.path == path and words in e.value.message, e.value
    with pytest.raises(nvector.InputError) as e:
        nvector.figure(bad)
    assert e.value.path == path
    file = tmp_path / "bad.json"
    file.write_text(json.dumps(bad))
    with pytest.raises(nvector.InputError) as e:
        nvector.read_result(file)
    assert e.value.path == path and str(file) in str(e.value)
