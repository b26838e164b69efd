#!/usr/bin/env bash
# Builds the wasm facade and the page (`build`) and runs the browser tests
# (`test`). OWNER: helper D.
set -euo pipefail
cd "$(dirname "$0")/.."
case "${1:-}" in
  build) ;;
  test) ;;
  *) echo "usage: scripts/web.sh build|test" >&2; exit 2 ;;
esac
