"""nvector.Client against a live `nvector serve` (temporary SQLite file)."""

from __future__ import annotations

import io
import json
from pathlib import Path

import pytest
from conftest import Cli, Service, canonical, start_service, stop_service

import nvector

CLOCK = ("metrics", "elapsed_ms")


@pytest.fixture(scope="module")
def mission() -> dict:
    return nvector.simulate("paper", seed=4, steps=2500)


def test_submit_wait_result_equals_local_run_and_cli(service: Service, cli: Cli, tmp_path: Path, mission: dict) -> None:
    client = nvector.Client(service.url)
    job = client.submit(mission, contractor="best")
    assert job.startswith("j-")
    result = client.wait(job, progress=False, timeout=120)
    local = nvector.run(mission, contractor="best")
    assert canonical(result, CLOCK) == canonical(local, CLOCK)
    path = tmp_path / "m.json"
    path.write_text(nvector.dumps(mission), encoding="utf-8")
    assert canonical(result, CLOCK) == canonical(json.loads(cli.json("run", str(path), "--contractor", "best")), CLOCK)
    # The same result again, and as CSV and SVG.
    assert canonical(client.result(job), CLOCK) == canonical(result, CLOCK)
    csv = client.result(job, format="csv")
    lines = csv.strip().splitlines()
    # A row per position: its step, its time (step x dt), then its box.
    assert lines[0] == "step,t,x_lo,x_hi,y_lo,y_hi"
    assert len(lines) == mission["steps"] + 2
    assert [float(x) for x in lines[2].split(",")[:2]] == [1.0, mission["dt"]]
    first = [float(x) for x in lines[1].split(",")[2:]]
    assert first == [b for axis in result["trajectory"][0] for b in axis]
    svg = client.result(job, format="svg")
    assert svg.lstrip().startswith("<svg") and "x (m)" in svg and "Legend" in svg
    # The job as the service reports it.
    state = client.job(job)
    assert state["state"] == "done" and state["contractor"] == "best"
    assert state["progress"]["fraction"] == 1.0 or state["progress"]["round"] >= 1


def test_submit_a_file_with_the_default_contractor(service: Service, tmp_path: Path, mission: dict) -> None:
    client = nvector.Client(service.url + "/api/v1/")
    path = tmp_path / "m.json"
    path.write_text(nvector.dumps(mission), encoding="utf-8")
    job = client.submit(path)
    result = client.wait(job, progress=False, timeout=120)
    assert canonical(result, CLOCK) == canonical(nvector.run(path), CLOCK)
    mission_id = client.job(job)["mission"]
    assert canonical(client.mission(mission_id)) == canonical(mission)
    assert mission_id in [m["id"] for m in client.missions(limit=1)]


def test_events_and_progress_bar(service: Service, mission: dict, capsys: pytest.CaptureFixture[str]) -> None:
    client = nvector.Client(service.url)
    job = client.submit(mission, contractor="projection")
    result = client.wait(job, progress=True, timeout=120)
    assert result["options"]["contractor"] == "projection"
    err = capsys.readouterr().err
    assert job in err
    # The bar ends on the result's own figures (not on a stale progress
    # event): status, rounds, diameters in metres.
    from nvector._client import final_message, metres

    last = [seg for seg in err.replace("\n", "\r").split("\r") if seg.strip()][-1]
    final = final_message(result)
    assert final in last, (final, last)
    assert f"{result['metrics']['rounds']} rounds" in final
    assert metres(result["metrics"]["max_trajectory_diameter"]) in final
    events = list(client.events(job))  # a finished job: one end event
    assert events[-1][0] == "end" and events[-1][1]["state"] == "done"


def test_plain_text_bar() -> None:
    from nvector._progress import ProgressBar

    out = io.StringIO()
    bar = ProgressBar("job j-1", stream=out, plain=True)
    bar.update(0.5, "running, round 3")
    bar.close()
    text = out.getvalue()
    assert "job j-1: [" in text and " 50.0% running, round 3" in text and text.endswith("\n")
    assert "#" * 15 + "-" * 15 in text


@pytest.fixture(scope="module")
def one_worker(nvector_bin: Path, tmp_path_factory: pytest.TempPathFactory):
    """A service with one job worker."""
    s = start_service(nvector_bin, tmp_path_factory.mktemp("one"), workers=1)
    yield s
    stop_service(s)


def test_timeout_and_cancel(one_worker: Service) -> None:
    client = nvector.Client(one_worker.url)
    # A long job (about a second here) holds the only worker, so the next
    # one waits in the queue while the test looks at it.
    big = client.upload(nvector.simulate("paper", seed=5, steps=150_000))
    blocker = client.create_job(big["id"], contractor="best")
    job = client.create_job(big["id"], contractor="best")
    assert client.job(job)["state"] == "queued"
    with pytest.raises(TimeoutError):
        client.wait(job, progress=False, timeout=0.0)
    with pytest.raises(nvector.ServiceError) as err:
        client.result(job)
    assert err.value.status == 409 and err.value.code == "not_done"
    client.cancel(job)
    with pytest.raises(nvector.JobError) as info:
        client.wait(job, progress=False, timeout=60)
    assert info.value.state == "cancelled" and info.value.job["id"] == job
    with pytest.raises(nvector.ServiceError) as err:
        client.cancel(job)
    assert err.value.status == 409 and err.value.code == "job_ended"
    assert client.wait(blocker, progress=False, timeout=120)["status"] == "consistent"


def test_service_errors(service: Service, mission: dict) -> None:
    client = nvector.Client(service.url)
    stored = client.upload(mission)
    assert stored["steps"] == mission["steps"] and stored["detections"] == len(mission["detections"])
    with pytest.raises(nvector.ServiceError) as err:
        client.job("j-nothing")
    assert err.value.status == 404
    with pytest.raises(nvector.ServiceError) as err:
        client.result("j-nothing")
    assert err.value.status == 404
    bad = json.loads(json.dumps(mission))
    bad["detections"][0]["range"] = [5, 4]
    with pytest.raises(nvector.ServiceError) as err:
        client.submit(bad)
    assert err.value.path == "detections[0].range" and 400 <= err.value.status < 500
    with pytest.raises(nvector.ServiceError) as err:
        client.create_job(stored["id"], contractor="fastest")
    assert err.value.path == "contractor"
    client.delete_mission(stored["id"])
    with pytest.raises(nvector.ServiceError) as err:
        client.mission(stored["id"])
    assert err.value.status == 404
    assert stored["id"] not in [m["id"] for m in client.missions()]


def test_unreachable_service() -> None:
    client = nvector.Client("http://127.0.0.1:9", timeout=5)
    assert client.health() is False
    with pytest.raises(nvector.ServiceError) as err:
        client.missions()
    assert err.value.status == 0 and err.value.code == "unreachable"


def test_api_keys(nvector_bin: Path, tmp_path: Path, mission: dict) -> None:
    keys = tmp_path / "keys.txt"
    keys.write_text("key-one\nkey-two\n", encoding="utf-8")
    secured = start_service(nvector_bin, tmp_path / "serve", "--api-key-file", str(keys))
    try:
        with pytest.raises(nvector.ServiceError) as err:
            nvector.Client(secured.url).missions()
        assert err.value.status == 401
        one = nvector.Client(secured.url, api_key="key-one")
        job = one.submit(mission)
        assert one.wait(job, progress=False, timeout=120)["status"] == "consistent"
        # Another key does not see it.
        with pytest.raises(nvector.ServiceError) as err:
            nvector.Client(secured.url, api_key="key-two").result(job)
        assert err.value.status == 404
    finally:
        stop_service(secured)


def test_tdoa_job_equals_the_local_solve(service: Service, cli: Cli, tmp_path: Path) -> None:
    problem = tmp_path / "radar.json"
    cli.run("simulate", "--scenario", "radar", "--seed", "6", "--emitters", "3", "--pulses", "30", "--out", str(problem))
    client = nvector.Client(service.url)
    job = client.submit_tdoa(problem)
    result = client.wait(job, progress=False, timeout=120)
    assert result["format"] == "nvector-tdoa-result/1"
    assert result["score"]["truth_inside"] is True and result["score"]["matching_errors"] == 0
    # The service runs core's solver with nvector.tdoa's defaults: the same bits.
    assert canonical(result, CLOCK) == canonical(nvector.tdoa(problem), CLOCK)
    assert client.job(job)["mission"].startswith("t-")
    # Options travel as the query; a refused problem names its JSON path.
    none = client.wait(client.submit_tdoa(json.loads(problem.read_text(encoding="utf-8")), contractor="none"), progress=False, timeout=120)
    assert none["contractor"] == "none" and none["matching"] == []
    bad = {"format": "nvector-tdoa/1", "propagation_speed": [1, 2], "receivers": [],
           "pulses": [{"arrivals": [{"receiver": 0, "time": [0, 1]}]}]}
    with pytest.raises(nvector.ServiceError) as e:
        client.submit_tdoa(bad)
    assert e.value.status == 422 and e.value.path == "pulses[0].arrivals[0].receiver"
