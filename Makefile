# nvector — the two commands: `make run` and `make test`.
SHELL := /bin/bash
.SHELLFLAGS := -euo pipefail -c

.PHONY: run test setup lint web test-rust test-web test-inari test-python test-fuzz

setup:
	@scripts/setup.sh

web: setup
	scripts/web.sh build

run: setup web
	cargo build --release -p nvector-server
	./target/release/nvector serve --addr 127.0.0.1:8080

# Also: no function over 80 lines without a reason (scripts/long_fns.py);
# the repository lint (scripts/lint_repo.py: nothing names a folder outside
# the repository, no source cites an issue number, every Markdown link
# resolves), after its self-test shows each rule catching a planted case.
lint:
	cargo fmt --all -- --check
	python3 scripts/long_fns.py --check
	python3 scripts/lint_repo.py --self-test > /dev/null
	python3 scripts/lint_repo.py
	cargo clippy --workspace --all-targets -- -D warnings
	cargo clippy -p nvector-core -p nvector-web -p nvector-web-radar --target wasm32-unknown-unknown -- -D warnings

# `cargo test --workspace`, with the test executables run two at a time
# (scripts/test_rust.py: same build, same tests; the long ones no longer
# leave a core idle).
test-rust: web
	scripts/test_rust.py

test-web: web
	scripts/web.sh test

test-inari: setup
	scripts/inari.sh

# The Python package (python/) in the project's venv: pip install, pytest.
test-python: setup
	scripts/python.sh

# The OpenAPI document validated, and the live service fuzzed from it for
# 60 s (schemathesis in the project's venv; scripts/fuzz/ has the rules).
test-fuzz: setup
	scripts/fuzz.sh 60

# After the Rust step, its four other steps two at a time (GNU make's -j2,
# each step's output kept together): the fuzzer waits on a live service
# for 60 s and the browser and Python steps mostly wait on processes, so
# one core sat idle while they ran one after the other. Each step has its
# own target directory or only reads the Rust step's build.
test: setup lint test-rust
	$(MAKE) --no-print-directory -j2 --output-sync=target test-web test-inari test-python test-fuzz
