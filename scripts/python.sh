#!/usr/bin/env bash
# The Python package's step of `make test`: in the project's venv (.venv,
# scripts/venv.sh), build and install python/ with pip (maturin, as a
# user's `pip install ./python` builds it, in the python-ci profile), then run its pytest
# suite against the `nvector` binary of the same tree (built here if `cargo
# test` did not; the test profile, as the Rust end-to-end tests use it), or
# the one $NVECTOR_BIN names. Arguments go to pytest. mypy (pinned in
# scripts/requirements-test.txt) must be there: python/tests/test_typing.py
# runs it, and this step fails at once when the venv lacks it rather than
# letting that test skip.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/venv.sh
export PATH="$PWD/.venv/bin:$PATH"
if ! .venv/bin/python -c "import mypy" 2>/dev/null; then
  echo "python: mypy is missing from .venv (scripts/requirements-test.txt pins it);" \
    "remove .venv/.requirements.sha256 and run scripts/venv.sh again" >&2
  exit 1
fi
if [ -z "${NVECTOR_BIN:-}" ]; then
  # The selection of `cargo test --workspace` (scripts/test_rust.py and
  # the end-to-end harness build the same): after `make test`'s Rust step a
  # no-op. `-p nvector-server` alone resolves other features (no
  # dev-dependencies) and built the server and its dependencies a second
  # time, over the binary the other steps use.
  cargo build --quiet --workspace --bins --tests --profile test
  NVECTOR_BIN="$PWD/target/debug/nvector"
fi
export NVECTOR_BIN
# The CI's build of the extension: the python-ci profile (Cargo.toml: the
# test profile's optimisation, no debug info), not the release profile a
# user's `pip install ./python` gets: the same code, a fraction of the cold
# compile time. PYTHON_PROFILE=release builds what a user gets.
MATURIN_PEP517_ARGS="--profile ${PYTHON_PROFILE:-python-ci}" \
  .venv/bin/python -m pip install --quiet --disable-pip-version-check \
  --no-build-isolation --no-deps --force-reinstall ./python
.venv/bin/python -m pytest -q -p no:cacheprovider python/tests "$@"
