#!/usr/bin/env bash
# Installs what the build and the tests need, when missing: the wasm32
# target, wasm-bindgen-cli at the Cargo.lock version, Chromium and
# chromedriver, PostgreSQL (server binaries for the storage tests), Node.js
# and npm, brotli (the page's precompressed files), wasm-opt (npm's binaryen, at the version of
# web/tools/package-lock.json) and the Python venv (scripts/venv.sh).
# Idempotent and quick when everything is there.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! rustup target list --installed | grep -q '^wasm32-unknown-unknown$'; then
  echo "setup: adding the wasm32-unknown-unknown target"
  rustup target add wasm32-unknown-unknown
fi

# Debian's packages and the Python venv download while wasm-bindgen-cli
# compiles (the longest step on a fresh machine): each logs to a file, and
# a failure stops the setup with that log.
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
apt_pkgs=()
command -v chromium >/dev/null || apt_pkgs+=(chromium)
command -v chromedriver >/dev/null || apt_pkgs+=(chromium-driver)
ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || apt_pkgs+=(postgresql)
command -v npm >/dev/null || apt_pkgs+=(nodejs npm)
command -v brotli >/dev/null || apt_pkgs+=(brotli)
apt_pid=""
if [ ${#apt_pkgs[@]} -gt 0 ]; then
  echo "setup: installing ${apt_pkgs[*]} from Debian's packages"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO=sudo
  ( $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${apt_pkgs[@]}" ) \
    >"$logs/apt" 2>&1 &
  apt_pid=$!
fi
scripts/venv.sh >"$logs/venv" 2>&1 &
venv_pid=$!

# wasm-bindgen-cli must match the wasm-bindgen crate in Cargo.lock exactly.
want=$(awk '/^name = "wasm-bindgen"$/ {getline; gsub(/[^0-9.]/, ""); print; exit}' Cargo.lock 2>/dev/null || true)
if [ -n "$want" ]; then
  have=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)
  if [ "$have" != "$want" ]; then
    echo "setup: installing wasm-bindgen-cli $want (found '${have:-none}')"
    cargo install wasm-bindgen-cli --version "$want" --force
  fi
fi


finish() { # finish PID NAME: wait for a background step, show its log if it failed
  if ! wait "$1"; then
    echo "setup: $2 failed:" >&2
    cat "$logs/$2" >&2
    exit 1
  fi
}
[ -z "$apt_pid" ] || finish "$apt_pid" apt
finish "$venv_pid" venv
cat "$logs/venv"

# wasm-opt shrinks the page's wasm (scripts/web.sh build); pinned by the
# lock file, installed under web/tools/node_modules.
want=$(awk -F'"' '/"node_modules\/binaryen"/ {getline; print $4; exit}' web/tools/package-lock.json)
have=$(awk -F'"' '/"version"/ {print $4; exit}' web/tools/node_modules/binaryen/package.json 2>/dev/null || true)
if [ "$have" != "$want" ]; then
  echo "setup: installing binaryen $want (wasm-opt) with npm (found '${have:-none}')"
  npm ci --prefix web/tools --no-audit --no-fund --loglevel=error
fi
