"""nvector.run against `nvector run`, bit for bit (elapsed time aside)."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from conftest import Cli, canonical

import nvector

CLOCK = ("metrics", "elapsed_ms")


def write(path: Path, obj: object) -> Path:
    path.write_text(nvector.dumps(obj) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def paper() -> dict:
    return nvector.simulate("paper", seed=3, steps=2000)


@pytest.mark.parametrize("contractor", [None, "none", "nvalue", "projection", "independent", "best"])
def test_paper_agrees_with_the_cli(cli: Cli, tmp_path: Path, paper: dict, contractor: str | None) -> None:
    path = write(tmp_path / "m.json", paper)
    flags = [] if contractor is None else ["--contractor", contractor]
    text = cli.json("run", str(path), *flags)
    result = nvector.run(paper, contractor=contractor)
    assert canonical(result, CLOCK) == canonical(json.loads(text), CLOCK)
    assert result["format"] == "nvector-result/1"
    assert result["score"]["truth_inside"] is True
    # From the file, the same answer.
    assert canonical(nvector.run(path, contractor=contractor), CLOCK) == canonical(result, CLOCK)
    assert canonical(nvector.run(str(path), contractor=contractor), CLOCK) == canonical(result, CLOCK)


def test_default_contractor_is_the_clis(paper: dict) -> None:
    assert nvector.run(paper)["options"]["contractor"] == "best"
    no_count = dict(paper)
    del no_count["landmark_count"]
    assert nvector.run(no_count)["options"]["contractor"] == "none"


@pytest.mark.parametrize(
    "kwargs,flags",
    [
        ({"seed": 8, "steps": 2500, "layout": "ring", "operator": True}, ["--max-rounds", "3"]),
        ({"seed": 6, "steps": 2500, "range_only": True}, ["--tolerance", "1e-6"]),
        ({"seed": 5, "steps": 2500, "false_detections": 2}, []),
    ],
)
def test_variants_agree_with_the_cli(cli: Cli, tmp_path: Path, kwargs: dict, flags: list[str]) -> None:
    mission = nvector.simulate("paper", **kwargs)
    path = write(tmp_path / "m.json", mission)
    options: dict = {}
    if "--max-rounds" in flags:
        options["max_rounds"] = int(flags[1])
    if "--tolerance" in flags:
        options["tolerance"] = float(flags[1])
    result = nvector.run(mission, **options)
    assert canonical(result, CLOCK) == canonical(json.loads(cli.json("run", str(path), *flags)), CLOCK)


def test_auv_agrees_with_the_cli(cli: Cli, tmp_path: Path) -> None:
    mission = nvector.simulate("auv", seed=1, steps=3000)
    path = write(tmp_path / "auv.json", mission)
    result = nvector.run(path)
    assert canonical(result, CLOCK) == canonical(json.loads(cli.json("run", str(path))), CLOCK)
    assert len(result["trajectory"][0]) == 3


def test_stopped_after_max_rounds(paper: dict) -> None:
    result = nvector.run(paper, max_rounds=1)
    assert result["status"] == "stopped"
    assert result["metrics"]["rounds"] == 1


def test_progress_callback_sees_the_rounds(paper: dict) -> None:
    seen: list[tuple[int, float, float]] = []
    result = nvector.run(paper, progress=lambda r, d, f: seen.append((r, d, f)))
    assert seen, "no progress reported"
    assert all(0.0 <= f <= 1.0 for _, _, f in seen)
    assert [r for r, _, _ in seen] == sorted(r for r, _, _ in seen)
    assert max(r for r, _, _ in seen) <= result["metrics"]["rounds"]


def test_an_exception_in_the_callback_stops_the_run(paper: dict) -> None:
    class Stop(Exception):
        pass

    calls = []

    def progress(r: int, d: float, f: float) -> None:
        calls.append(r)
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        nvector.run(paper, progress=progress)
    assert len(calls) == 1


def test_progress_bar_on_stderr(paper: dict, capsys: pytest.CaptureFixture[str]) -> None:
    nvector.run(paper, progress=True)
    err = capsys.readouterr().err
    assert "round" in err and "max trajectory diameter" in err


def test_a_signal_stops_the_run_and_raises() -> None:
    """Ctrl-C in a notebook: SIGINT arriving while the core runs (without the
    GIL) stops the propagation at its next report and raises there."""
    import signal
    import threading

    mission = nvector.simulate("paper", seed=5, steps=100_000)

    class Interrupted(Exception):
        pass

    stop = threading.Event()

    def handler(signum: int, frame: object) -> None:
        if not stop.is_set():  # the first signal only: later ones are dropped
            stop.set()
            raise Interrupted()

    main = threading.main_thread().ident
    assert main is not None

    def sender() -> None:
        while not stop.wait(0.005):
            signal.pthread_kill(main, signal.SIGINT)

    thread = threading.Thread(target=sender, daemon=True)
    reports = []

    def progress(r: int, d: float, f: float) -> None:
        reports.append(f)
        if not thread.is_alive() and not stop.is_set() and thread.ident is None:
            thread.start()

    old = signal.signal(signal.SIGINT, handler)
    try:
        with pytest.raises(Interrupted):
            nvector.run(mission, progress=progress)
    finally:
        stop.set()
        if thread.ident is not None:
            thread.join()
        time.sleep(0.05)  # a last signal in flight lands on the handler, which drops it
        signal.signal(signal.SIGINT, old)
    assert reports
