#!/usr/bin/env bash
# Checks the interval operations against inari (core/tests/interval_props.rs,
# module inari_reference). inari needs AVX2 and FMA, so this build uses
# `-C target-cpu=haswell`, in its own target directory (below). On a CPU
# without AVX2 or FMA it cannot run: it says so and, under CI (CI=true), fails (a check that
# cannot run is not a check that passed); elsewhere it skips loudly.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! grep -qw avx2 /proc/cpuinfo || ! grep -qw fma /proc/cpuinfo; then
  if [ "${CI:-}" = true ]; then
    echo "inari: FAILED — this CPU has no AVX2/FMA, inari cannot run here (CI=true: a skipped check fails)" >&2
    exit 1
  fi
  echo "inari: SKIPPED — this CPU has no AVX2/FMA, inari cannot run here (under CI=true this fails)" >&2
  exit 0
fi
# Its own target directory: the other builds keep their flags and caches,
# and `make test` runs this step beside the Python and fuzz steps without
# waiting on their directory's lock.
export RUSTFLAGS="-C target-cpu=haswell" CARGO_TARGET_DIR=target/haswell
# Only the inari test: every other target is linted by `make lint`; this
# one has code (the inari module) that only this build compiles.
cargo clippy -q -p nvector-core --test interval_props -- -D warnings
cargo test -p nvector-core --test interval_props inari_reference
