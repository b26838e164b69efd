"""Shared fixtures: the `nvector` binary the package is compared with, and a
live `nvector serve` on a free loopback port with a temporary SQLite file.

The binary is $NVECTOR_BIN, else the newest of target/release/nvector and
target/debug/nvector at the repository root; `make test` builds it and sets
NVECTOR_BIN. Without one, the session fails: nothing here is skipped.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Iterator

import pytest

import nvector

ROOT = Path(__file__).resolve().parents[2]


def _find_bin() -> Path:
    env = os.environ.get("NVECTOR_BIN")
    if env:
        return Path(env)
    found = [p for p in (ROOT / "target/release/nvector", ROOT / "target/debug/nvector") if p.exists()]
    if not found:
        raise RuntimeError(
            "no nvector binary: build it (cargo build -p nvector-server) or set NVECTOR_BIN"
        )
    return max(found, key=lambda p: p.stat().st_mtime)


@pytest.fixture(scope="session")
def nvector_bin() -> Path:
    return _find_bin()


class Cli:
    """Runs the `nvector` binary."""

    def __init__(self, binary: Path) -> None:
        self.binary = binary

    def run(self, *args: str, stdin: str | None = None, check: bool = True) -> subprocess.CompletedProcess[str]:
        done = subprocess.run(
            [str(self.binary), *args],
            input=stdin,
            capture_output=True,
            text=True,
            timeout=600,
        )
        if check and done.returncode != 0:
            raise AssertionError(f"nvector {' '.join(args)} exited {done.returncode}: {done.stderr}")
        return done

    def json(self, *args: str, stdin: str | None = None) -> str:
        """The command's JSON output, as text (one line)."""
        return self.run(*args, stdin=stdin).stdout.strip()


@pytest.fixture(scope="session")
def cli(nvector_bin: Path) -> Cli:
    return Cli(nvector_bin)


def canonical(obj: Any, clock: tuple[str, str] | None = None) -> str:
    """The JSON text of ``obj`` as the binary writes it (serde_json: sorted
    keys, shortest round-trip floats), with the timing field ``clock``
    (e.g. ("metrics", "elapsed_ms")) set to 0. Two objects with the same
    text hold the same numbers bit for bit (-0.0 and 0.0 differ in text)."""
    if clock is not None:
        obj = json.loads(json.dumps(obj))
        obj[clock[0]][clock[1]] = 0
    return nvector.dumps(obj)


class Service:
    """A running `nvector serve`."""

    def __init__(self, process: subprocess.Popen[str], url: str, directory: Path) -> None:
        self.process = process
        self.url = url
        self.directory = directory


def start_service(binary: Path, directory: Path, *extra: str, workers: int = 2) -> Service:
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "www").mkdir(exist_ok=True)
    process = subprocess.Popen(
        [
            str(binary),
            "serve",
            "--addr",
            "127.0.0.1:0",
            "--database",
            f"sqlite://{directory / 'x.db'}",
            "--static-dir",
            str(directory / "www"),
            "--workers",
            str(workers),
            *extra,
        ],
        stdout=subprocess.PIPE,
        stderr=sys.stderr,
        text=True,
        env={**os.environ, "RUST_LOG": "warn"},
    )
    assert process.stdout is not None
    line = process.stdout.readline().strip()
    prefix = "nvector serving on "
    if not line.startswith(prefix):
        process.kill()
        raise RuntimeError(f"nvector serve did not start: {line!r}")
    url = line[len(prefix) :]
    deadline = time.monotonic() + 30
    while not nvector.Client(url).health():
        if time.monotonic() > deadline or process.poll() is not None:
            process.kill()
            raise RuntimeError("nvector serve never became healthy")
        time.sleep(0.05)
    return Service(process, url, directory)


def stop_service(service: Service) -> None:
    service.process.terminate()
    try:
        service.process.wait(timeout=20)
    except subprocess.TimeoutExpired:
        service.process.kill()
        service.process.wait()


@pytest.fixture(scope="session")
def service(nvector_bin: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Service]:
    s = start_service(nvector_bin, tmp_path_factory.mktemp("serve"))
    yield s
    stop_service(s)
