"""The package's type hints and stubs hold together: mypy --strict over the
package and the example (when mypy is installed)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parents[1]


def test_mypy_strict() -> None:
    pytest.importorskip("mypy")
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--python-version", "3.10", "--no-incremental", "nvector", "examples"],
        cwd=HERE,
        capture_output=True,
        text=True,
        timeout=300,
        env={"MYPYPATH": str(HERE), "PATH": "/usr/bin:/bin"},
    )
    assert done.returncode == 0, done.stdout + done.stderr
