#!/usr/bin/env bash
# Creates the project's Python virtual environment .venv at the repository
# root when missing and installs the pinned packages of
# scripts/requirements-test.txt into it (never system-wide). Idempotent and
# quick when the environment is there: a stamp holding the requirements'
# checksum skips pip when nothing changed.
# Usage: scripts/venv.sh  (then .venv/bin/python ...)
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON=${PYTHON:-python3}
req=scripts/requirements-test.txt
stamp=.venv/.requirements.sha256

if [ ! -x .venv/bin/python ]; then
  echo "venv: creating .venv with $($PYTHON --version 2>&1)"
  "$PYTHON" -m venv .venv
fi
want=$(sha256sum "$req" | awk '{print $1}')
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  echo "venv: installing $req"
  .venv/bin/python -m pip install --quiet --disable-pip-version-check -r "$req"
  echo "$want" >"$stamp"
fi
