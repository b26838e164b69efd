# nvector — the two commands: `make run` and `make test`.
SHELL := /bin/bash
.SHELLFLAGS := -euo pipefail -c

.PHONY: run test setup lint wasm test-rust

setup:
	@scripts/setup.sh

run: setup
	cargo build --release -p nvector-server
	./target/release/nvector serve --addr 127.0.0.1:8080

lint:
	cargo fmt --all -- --check
	cargo clippy --workspace --all-targets -- -D warnings
	cargo clippy -p nvector-core -p nvector-web --target wasm32-unknown-unknown -- -D warnings

test-rust:
	cargo test --workspace

test: setup lint test-rust
