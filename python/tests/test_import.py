"""nvector.import_dataset and nvector.import_csv against `nvector import`,
bit for bit, and their errors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import ROOT, Cli, canonical

import nvector

PLAZA = ROOT / "data" / "cmu-plaza1"


@pytest.mark.parametrize(
    "kwargs,flags",
    [
        ({}, []),
        ({"operator": True}, ["--operator"]),
        ({"false_detections": 20, "seed": 3, "outlier_share": 0.02}, ["--false-detections", "20", "--seed", "3", "--outlier-share", "0.02"]),
    ],
)
def test_plaza_agrees_with_the_cli(cli: Cli, kwargs: dict, flags: list[str]) -> None:
    mission = nvector.import_dataset("cmu-plaza", PLAZA, **kwargs)
    text = cli.json("import", "--cmu-plaza", str(PLAZA), *flags)
    assert canonical(mission) == text
    assert mission == json.loads(text)
    assert mission["model"] == "unicycle2d"
    # The directory's own name reads the same data set.
    if not kwargs:
        assert nvector.import_dataset("cmu-plaza1", str(PLAZA)) == mission


def test_locards_agrees_with_the_cli(cli: Cli) -> None:
    problem = nvector.import_dataset("locards-mlat", ROOT / "data" / "locards-mlat", set=3)
    assert problem["format"] == "nvector-tdoa/1"
    assert canonical(problem) == cli.json("import", "--locards-mlat", str(ROOT / "data" / "locards-mlat"), "--set", "3")


def _pair(tmp_path: Path) -> tuple[Path, Path]:
    log = tmp_path / "log.csv"
    log.write_text("t,speed,turn_rate,note\n0,1,0.1,7\n0.5,1,0.1,8\n1.0,1.2,0,9\n1.5,1,0,10\n")
    det = tmp_path / "det.csv"
    det.write_text("t,range_lo,range_hi,bearing_lo,bearing_hi,scan,landmark\n0.5,3,3.5,0.1,0.2,1,0\n1.0,2,2.5,-0.2,-0.1,2,1\n")
    return log, det


def test_a_csv_pair_agrees_with_the_cli(cli: Cli, tmp_path: Path) -> None:
    log, det = _pair(tmp_path)
    with pytest.warns(UserWarning, match="ignoring column"):
        mission = nvector.import_csv(
            "odometry2d",
            log,
            det,
            errors={"speed": 0.02, "turn_rate": 0.0},
            heading_error=0.01,
            initial=[(-0.01, 0.01), (-0.01, 0.01)],
            initial_heading=(-0.01, 0.01),
            sensor_offset=(0.2, 0.0),
            landmark_count=17,
            landmark_min_separation=1.2,
        )
    text = cli.json(
        "import", "--model", "odometry2d", "--log", str(log), "--detections", str(det),
        "--error", "speed=0.02", "--error", "turn_rate=0", "--heading-error", "0.01",
        "--initial", "-0.01,0.01,-0.01,0.01", "--initial-heading", "-0.01,0.01",
        "--sensor-offset", "0.2,0", "--landmark-count", "17", "--landmark-min-separation", "1.2",
    )
    assert canonical(mission) == text
    assert mission["steps"] == 4 and len(mission["detections"]) == 2


def test_errors_name_the_setting_or_the_file_and_line(cli: Cli, tmp_path: Path) -> None:
    log, det = _pair(tmp_path)
    with pytest.raises(nvector.InputError) as e:
        nvector.import_csv("odometry2d", log, det, errors={"speed": 0.1, "turn_rate": 0.0})
    assert e.value.path == "initial_heading"
    assert "required for odometry2d" in e.value.message
    log.write_text("t,speed,turn_rate\n0,1,0\n0.5,fast,0\n")
    with pytest.raises(nvector.InputError) as e:
        nvector.import_csv("odometry2d", log, det, errors={"speed": 0.1, "turn_rate": 0.0}, initial_heading=(0, 0))
    message = str(e.value)
    assert message.endswith("log.csv:3: column 2 (speed): 'fast' is not a finite number"), message
    done = cli.run("import", "--model", "odometry2d", "--log", str(log), "--detections", str(det), "--error", "speed=0.1",
                   "--error", "turn_rate=0", "--initial-heading", "0,0", check=False)
    assert done.stderr.strip() == f"nvector: {message}"
    with pytest.raises(FileNotFoundError, match="Plaza1_DR.txt"):
        nvector.import_dataset("cmu-plaza", tmp_path)
    with pytest.raises(nvector.InputError) as e:
        nvector.import_dataset("plaza", PLAZA)
    assert e.value.path == "name"
    with pytest.raises(nvector.InputError) as e:
        nvector.import_dataset("cmu-plaza", PLAZA, outlier_share=0.5)
    assert e.value.path == "outlier_share"
