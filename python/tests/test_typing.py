"""The package's type hints and stubs hold together: mypy --strict over the
package and the example. scripts/python.sh installs mypy (pinned in
scripts/requirements-test.txt); without it the test is skipped, loudly, and
under CI (CI=true) it fails: a check that cannot run is not a check that
passed."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parents[1]


def test_mypy_strict() -> None:
    if importlib.util.find_spec("mypy") is None:
        message = f"mypy is not installed in {sys.executable} (scripts/python.sh installs it)"
        if os.environ.get("CI") == "true":
            pytest.fail(message + "; under CI=true a skipped check fails")
        pytest.skip(message)
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--python-version", "3.10", "--no-incremental", "nvector", "examples"],
        cwd=HERE,
        capture_output=True,
        text=True,
        timeout=300,
        env={"MYPYPATH": str(HERE), "PATH": "/usr/bin:/bin"},
    )
    assert done.returncode == 0, done.stdout + done.stderr
