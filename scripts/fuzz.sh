#!/usr/bin/env bash
# The OpenAPI step of `make test`: a live `nvector serve` (the test-profile
# binary, a fresh SQLite file, small limits so generated missions stay
# small), its document validated (openapi-spec-validator), then fuzzed from
# the document for a bounded time (schemathesis, every check, plus the
# spec's rules in scripts/fuzz/hooks.py): 0 server errors, no schema-valid
# request refused, no invalid one accepted. Python tools in the project's
# venv (scripts/venv.sh).
# Usage: scripts/fuzz.sh [SECONDS]   (default 60; FUZZ_SEED=N to replay;
# NVECTOR_BIN=PATH fuzzes that binary instead of building the tree's)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
scripts/venv.sh
bin=${NVECTOR_BIN:-}
if [ -z "$bin" ]; then
  # The selection of `cargo test --workspace` (scripts/test_rust.py and
  # the end-to-end harness build the same): after `make test`'s Rust step a
  # no-op. `-p nvector-server` alone resolves other features (no
  # dev-dependencies) and built the server and its dependencies a second
  # time, over the binary the other steps use.
  cargo build --quiet --workspace --bins --tests --profile test
  bin=target/debug/nvector
fi

tmp=$(mktemp -d)
server_pid=""
cleanup() {
  if [ -n "$server_pid" ]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
  rm -rf "$tmp"
}
trap cleanup EXIT

RUST_LOG=warn "$bin" serve --addr 127.0.0.1:0 \
  --database "sqlite://$tmp/nvector.db" --static-dir "$tmp/www" --workers 2 \
  --max-steps 20000 --max-detections 2000 --job-time-limit 5 --max-queue 100000 \
  >"$tmp/out" 2>"$tmp/err" &
server_pid=$!
for _ in $(seq 100); do
  grep -q "serving on" "$tmp/out" 2>/dev/null && break
  sleep 0.1
done
url=$(sed -n 's/^nvector serving on //p' "$tmp/out" | head -1)
if [ -z "$url" ]; then echo "fuzz: the service did not start" >&2; cat "$tmp/err" >&2; exit 1; fi

curl -fsS "$url/api/v1/openapi.json" -o "$tmp/openapi.json"
.venv/bin/openapi-spec-validator "$tmp/openapi.json"

# Every field of the judged request bodies must have its rules in the
# oracle (scripts/fuzz/hooks.py, RULED) before it is fuzzed.
PYTHONPATH=scripts/fuzz .venv/bin/python - "$tmp/openapi.json" <<'EOF'
import json, sys
import hooks
missing = hooks.unruled(json.load(open(sys.argv[1])))
if missing:
    sys.exit("fuzz: these request fields have no rules in scripts/fuzz/hooks.py"
             " (implement them from docs/formats.md, then list them in RULED): "
             + ", ".join(missing))
EOF

seed=${FUZZ_SEED:-$RANDOM}
echo "fuzz: schemathesis against $url for ${seconds}s (seed $seed)"
status=0
SCHEMATHESIS_HOOKS=hooks PYTHONPATH=scripts/fuzz .venv/bin/schemathesis \
  --config-file scripts/fuzz/schemathesis.toml run "$url/api/v1/openapi.json" \
  --max-time "$seconds" --seed "$seed" --workers 2 \
  --suppress-health-check too_slow,filter_too_much,data_too_large \
  --report junit --report-dir target/fuzz || status=$?
if grep -q "panicked" "$tmp/err"; then
  echo "fuzz: the service panicked:" >&2; grep -A3 panicked "$tmp/err" >&2; status=1
fi
exit $status
