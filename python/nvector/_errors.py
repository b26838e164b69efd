"""The exceptions of the nvector package."""

from __future__ import annotations

import os
from typing import Any, Callable


class InputError(ValueError):
    """Invalid input, with the JSON path of the bad value.

    ``path`` is a JSON path such as ``detections[12].range`` (``""`` for the
    whole document), ``message`` says what is wrong, ``file`` names the file
    it was read from, if any. ``str(error)`` reads like the CLI's message:
    ``"mission.json: detections[12].range: lower bound 5 is above upper bound 4"``.
    """

    def __init__(self, path: str, message: str, file: str | None = None) -> None:
        super().__init__(path, message, file)
        self.path = path
        self.message = message
        self.file = file

    def __str__(self) -> str:
        text = f"{self.path}: {self.message}" if self.path else self.message
        return f"{self.file}: {text}" if self.file else text


class ServiceError(RuntimeError):
    """An error answered by an nvector service (or the failure to reach it).

    ``status`` is the HTTP status (0 when the service could not be reached),
    ``code`` the service's error code (``"invalid_mission"``, ``"not_found"``
    ...), ``path`` the JSON path it names, if any, ``message`` its text.
    """

    def __init__(self, status: int, code: str, message: str, path: str | None = None) -> None:
        super().__init__(status, code, message, path)
        self.status = status
        self.code = code
        self.message = message
        self.path = path

    def __str__(self) -> str:
        where = f" at {self.path}" if self.path else ""
        status = f"HTTP {self.status} " if self.status else ""
        return f"{status}{self.code}{where}: {self.message}"


class JobError(RuntimeError):
    """A job that ended without a result (``state`` ``failed`` or ``cancelled``).

    ``job`` is the job as the service last reported it.
    """

    def __init__(self, job: dict[str, Any]) -> None:
        self.job = job
        self.state = str(job.get("state"))
        detail = job.get("error")
        super().__init__(f"job {job.get('id')} {self.state}" + (f": {detail}" if detail else ""))


def read_with_file(read: Callable[[Any], Any], source: Any) -> Any:
    """``read(source)`` where ``source`` is a document or the path of a file
    (read as UTF-8 text first): an :class:`InputError` from a file names it
    (``file``)."""
    file = None
    if isinstance(source, (str, os.PathLike)):
        file = os.fspath(source)
        with open(file, encoding="utf-8") as f:
            source = f.read()
    try:
        return read(source)
    except InputError as e:
        if file is None:
            raise
        raise InputError(e.path, e.message, file=file) from None
