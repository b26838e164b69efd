"""A client of the nvector HTTP service (``nvector serve``, API v1).

Standard library only (urllib). Every call raises :class:`ServiceError`
with the service's error code, message and JSON path when the service
answers an error, or status 0 when it cannot be reached.
"""

from __future__ import annotations

import json
import os
import time
import urllib.error
import urllib.parse
import urllib.request
from typing import Any, Iterator, Union, cast

from . import _nvector
from ._errors import JobError, ServiceError
from ._progress import ProgressBar

PathLike = Union[str, "os.PathLike[str]"]

_TERMINAL = ("done", "failed", "cancelled", "deleted")


class Client:
    """A client of one nvector service.

    ``base_url`` is the service's root (``"http://127.0.0.1:8080"``; a
    trailing ``/api/v1`` is accepted too). ``api_key`` is sent as
    ``Authorization: Bearer KEY`` (needed when the service was started with
    ``--api-key-file``). ``timeout`` bounds each request, in seconds.

    Example::

        client = nvector.Client("http://127.0.0.1:8080")
        job = client.submit(nvector.simulate("paper", seed=2), contractor="best")
        result = client.wait(job)          # follows the job's event stream
        svg = client.result(job, format="svg")
    """

    def __init__(self, base_url: str, api_key: str | None = None, timeout: float = 60.0) -> None:
        root = base_url.rstrip("/")
        if root.endswith("/api/v1"):
            root = root[: -len("/api/v1")]
        self.base_url = root
        self.api_key = api_key
        self.timeout = timeout

    def __repr__(self) -> str:
        return f"Client({self.base_url!r})"

    # -- plumbing ---------------------------------------------------------

    def _open(self, method: str, path: str, body: bytes | None = None, accept: str = "application/json") -> Any:
        headers = {"Accept": accept}
        if body is not None:
            headers["Content-Type"] = "application/json"
        if self.api_key:
            headers["Authorization"] = f"Bearer {self.api_key}"
        request = urllib.request.Request(self.base_url + path, data=body, method=method, headers=headers)
        try:
            return urllib.request.urlopen(request, timeout=self.timeout)
        except urllib.error.HTTPError as e:
            raise _service_error(e) from None
        except urllib.error.URLError as e:
            raise ServiceError(0, "unreachable", f"{self.base_url}: {e.reason}") from None
        except OSError as e:
            raise ServiceError(0, "unreachable", f"{self.base_url}: {e}") from None

    def _call(self, method: str, path: str, body: Any = None) -> Any:
        data = None if body is None else _nvector.dumps(body).encode("utf-8")
        with self._open(method, path, data) as response:
            text = response.read()
        return json.loads(text) if text else None

    # -- missions ---------------------------------------------------------

    def upload(self, mission: dict[str, Any] | PathLike) -> dict[str, Any]:
        """Stores a mission (a dict or a mission file) and returns its summary
        ``{"id", "name", "steps", "detections"}``. A mission the service
        refuses raises :class:`ServiceError` naming the JSON path."""
        if isinstance(mission, (str, os.PathLike)):
            with open(os.fspath(mission), "rb") as f:
                body = f.read()
        else:
            body = _nvector.dumps(mission).encode("utf-8")
        with self._open("POST", "/api/v1/missions", body) as response:
            return cast("dict[str, Any]", json.loads(response.read()))

    def missions(self, limit: int = 100) -> list[dict[str, Any]]:
        """Every stored mission's summary (``id``, ``name``, ``steps``,
        ``detections``, ``created_ms``, ``bytes``: the size of the stored
        JSON), oldest first, fetched ``limit`` a page."""
        out: list[dict[str, Any]] = []
        after: str | None = None
        while True:
            query = {"limit": str(limit)}
            if after:
                query["after"] = after
            page = self._call("GET", "/api/v1/missions?" + urllib.parse.urlencode(query))
            out.extend(page["missions"])
            after = page.get("next")
            if not after:
                return out

    def mission(self, mission_id: str) -> dict[str, Any]:
        """A stored mission, as uploaded."""
        return cast("dict[str, Any]", self._call("GET", f"/api/v1/missions/{_quote(mission_id)}"))

    def delete_mission(self, mission_id: str) -> None:
        """Deletes a mission and its jobs."""
        self._call("DELETE", f"/api/v1/missions/{_quote(mission_id)}")

    # -- jobs -------------------------------------------------------------

    def create_job(
        self,
        mission_id: str,
        contractor: str | None = None,
        max_rounds: int | None = None,
        time_limit_s: float | None = None,
    ) -> str:
        """Queues a SLAM job on a stored mission and returns the job id.
        ``contractor`` None: the service's default (best when the mission has
        a landmark_count, none otherwise)."""
        body: dict[str, Any] = {"mission": mission_id}
        if contractor is not None:
            body["contractor"] = contractor
        if max_rounds is not None:
            body["max_rounds"] = max_rounds
        if time_limit_s is not None:
            body["time_limit_s"] = time_limit_s
        return str(self._call("POST", "/api/v1/jobs", body)["id"])

    def submit(
        self,
        mission: dict[str, Any] | PathLike,
        contractor: str | None = None,
        max_rounds: int | None = None,
        time_limit_s: float | None = None,
    ) -> str:
        """Uploads a mission (dict or file) and queues a SLAM job on it:
        ``POST /api/v1/missions`` then ``POST /api/v1/jobs``. Returns the
        job id (the mission's id is in :meth:`job`'s ``"mission"``)."""
        stored = self.upload(mission)
        return self.create_job(stored["id"], contractor, max_rounds, time_limit_s)

    def submit_tdoa(
        self,
        problem: dict[str, Any] | PathLike,
        contractor: str | None = None,
        max_rounds: int | None = None,
        time_limit_s: float | None = None,
    ) -> str:
        """Stores a TDOA problem (``nvector-tdoa/1``: a dict or a file) and
        queues a job on it (``POST /api/v1/tdoa``); returns the job id. Follow
        it with :meth:`wait` (its result is ``nvector-tdoa-result/1``, the
        same as :func:`nvector.tdoa` with the default budget) or
        :meth:`cancel`. ``contractor`` None: the service's default, best. A
        problem the service refuses raises :class:`ServiceError` naming the
        JSON path."""
        if isinstance(problem, (str, os.PathLike)):
            with open(os.fspath(problem), "rb") as f:
                body = f.read()
        else:
            body = _nvector.dumps(problem).encode("utf-8")
        options = {"contractor": contractor, "max_rounds": max_rounds, "time_limit_s": time_limit_s}
        query = urllib.parse.urlencode({k: str(v) for k, v in options.items() if v is not None})
        with self._open("POST", "/api/v1/tdoa" + ("?" + query if query else ""), body) as response:
            return str(json.loads(response.read())["id"])

    def job(self, job_id: str) -> dict[str, Any]:
        """The job: ``id``, ``mission``, ``state`` (queued, running, done,
        failed, cancelled), ``progress`` (round, max_trajectory_diameter,
        fraction), ``error`` when it failed."""
        return cast("dict[str, Any]", self._call("GET", f"/api/v1/jobs/{_quote(job_id)}"))

    def cancel(self, job_id: str) -> None:
        """Cancels a queued or running job (a job that has ended raises
        :class:`ServiceError` with code ``job_ended``)."""
        self._call("DELETE", f"/api/v1/jobs/{_quote(job_id)}")

    def events(self, job_id: str) -> Iterator[tuple[str, dict[str, Any]]]:
        """The job's Server-Sent Events, as ``(event, job)`` pairs: ``event``
        is ``"progress"`` or, last, ``"end"``; ``job`` is the job as
        :meth:`job` gives it. Ends when the service closes the stream."""
        response = self._open("GET", f"/api/v1/jobs/{_quote(job_id)}/events", accept="text/event-stream")
        with response:
            event, data = "message", cast("list[str]", [])
            for raw in response:
                line = raw.decode("utf-8").rstrip("\r\n")
                if not line:
                    if data:
                        yield event, json.loads("\n".join(data))
                    event, data = "message", cast("list[str]", [])
                elif line.startswith(":"):
                    continue  # keep-alive comment
                else:
                    name, _, value = line.partition(":")
                    value = value[1:] if value.startswith(" ") else value
                    if name == "event":
                        event = value
                    elif name == "data":
                        data.append(value)

    def wait(self, job_id: str, progress: bool = True, timeout: float | None = None) -> dict[str, Any]:
        """Follows the job's event stream until it ends and returns its
        result (``nvector-result/1`` dict; ``nvector-tdoa-result/1`` for a
        TDOA job). ``progress`` draws a progress bar
        on stderr (tqdm when installed, else a text bar) of the job's
        ``progress.fraction``: the service's estimate of the share of the
        work done (docs/api.md), not of the rounds. A job that failed
        or was cancelled raises :class:`JobError`; past ``timeout`` seconds,
        :class:`TimeoutError` (the job goes on)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        bar = ProgressBar(f"job {job_id}") if progress else None
        try:
            job = self._follow(job_id, bar, deadline)
            if job.get("state") != "done":
                raise JobError(job)
            result = cast("dict[str, Any]", self.result(job_id))
            if bar is not None:
                # The bar ends on the result's figures, not on the last
                # progress event (which may be rounds behind).
                bar.update(1.0, final_message(result))
        finally:
            if bar is not None:
                bar.close()
        return result

    def _follow(self, job_id: str, bar: ProgressBar | None, deadline: float | None) -> dict[str, Any]:
        def check_deadline(job: dict[str, Any]) -> None:
            if deadline is not None and time.monotonic() > deadline:
                raise TimeoutError(f"job {job_id} still {job.get('state')} after the time given")

        while True:
            try:
                for event, job in self.events(job_id):
                    _show(bar, job)
                    if event == "end" or job.get("state") in _TERMINAL:
                        return job
                    check_deadline(job)
            except (ConnectionError, ValueError, urllib.error.URLError):
                pass  # a dropped connection or a cut line: ask again below
            except TimeoutError:
                if deadline is not None and time.monotonic() > deadline:
                    raise
            # The stream ended without its end event: read the job's state.
            job = self.job(job_id)
            _show(bar, job)
            if job.get("state") in _TERMINAL:
                return job
            check_deadline(job)
            time.sleep(0.5)

    def result(self, job_id: str, format: str = "json") -> Any:
        """The result of a finished job: ``"json"`` -> the result dict,
        ``"csv"`` -> the trajectory as CSV text, ``"svg"`` -> the figure as
        SVG text. A job not yet done raises :class:`ServiceError` (409)."""
        query = urllib.parse.urlencode({"format": format})
        accept = {"json": "application/json", "csv": "text/csv", "svg": "image/svg+xml"}.get(format, "*/*")
        with self._open("GET", f"/api/v1/jobs/{_quote(job_id)}/result?{query}", accept=accept) as response:
            body = response.read()
        return json.loads(body) if format == "json" else body.decode("utf-8")

    # -- service ----------------------------------------------------------

    def health(self) -> bool:
        """True when the service answers ``/healthz``."""
        try:
            with self._open("GET", "/healthz", accept="*/*") as response:
                return bool(response.status == 200)
        except ServiceError:
            return False


def _quote(part: str) -> str:
    return urllib.parse.quote(str(part), safe="")


def _show(bar: ProgressBar | None, job: dict[str, Any]) -> None:
    if bar is None:
        return
    p = job.get("progress") or {}
    fraction = p.get("fraction") or 0.0
    if job.get("state") == "done":
        fraction = 1.0
    diameter = p.get("max_trajectory_diameter")
    text = f"{job.get('state')}, round {p.get('round', 0)}"
    if isinstance(diameter, (int, float)):
        text += f", max trajectory diameter {metres(diameter)}"
    bar.update(fraction, text)


def metres(x: Any) -> str:
    """A length in metres rounded as the figures' titles show it
    (``nvector_core::figure::metres``): "73.0 m", "0.412 m", "612 m"."""
    if x == "inf" or (isinstance(x, float) and x == float("inf")):
        return "unbounded"
    if not isinstance(x, (int, float)) or x != x:
        return "?"
    a = abs(x)
    if a >= 1e7:
        return _exp(x)
    if a >= 100:
        return f"{x:.0f} m"
    if a >= 1:
        return f"{x:.1f} m"
    if x == 0:
        return "0 m"
    if a >= 0.01:
        return f"{x:.3f} m"
    return _exp(x)


def _exp(x: float) -> str:
    """Two decimals and an exponent as Rust's `{:.2e}` writes them:
    "4.00e-3 m", "1.00e308 m" (Python's own would be "4.00e-03")."""
    mantissa, exponent = f"{x:.2e}".split("e")
    return f"{mantissa}e{int(exponent)} m"


def final_message(result: dict[str, Any]) -> str:
    """The progress bar's last words: the result's status, rounds and
    diameters (what the job ended on)."""
    m = result.get("metrics") or {}
    if result.get("format") == "nvector-tdoa-result/1":
        return (
            f"{result.get('status')}, {m.get('rounds', '?')} rounds, {len(result.get('matching') or [])} "
            f"emitters proved, max pulse diameter {metres(m.get('max_pulse_diameter'))}"
        )
    return (
        f"{result.get('status')}, {m.get('rounds', '?')} rounds, max trajectory diameter "
        f"{metres(m.get('max_trajectory_diameter'))} (mean {metres(m.get('mean_trajectory_diameter'))})"
    )


def _service_error(e: urllib.error.HTTPError) -> ServiceError:
    try:
        body = e.read()
    except OSError:
        body = b""
    try:
        err = json.loads(body)["error"]
        return ServiceError(e.code, str(err.get("code", "error")), str(err.get("message", "")), err.get("path"))
    except (ValueError, KeyError, TypeError):
        text = body.decode("utf-8", "replace").strip() or str(e.reason)
        return ServiceError(e.code, "error", text)
