#!/usr/bin/env python3
"""The Rust step of `make test`: every test executable of the workspace, two at a time.

`cargo test --workspace` runs the test executables one after another, and
most of the long ones spend most of their time in one test, so one of the
two cores sat idle for most of that step (BENCHMARKS.md, "CI time"). This
script builds exactly what `cargo test --workspace` builds (the same
package selection and profile: `cargo build --workspace --bins --tests
--profile test`, which is also what the end-to-end harness asks for, so
nothing is compiled twice), then runs the executables JOBS at a time
(default: the number of CPUs; NVECTOR_TEST_JOBS=N to change it), the longest
known ones first, each in its package's directory as cargo runs them. Each
executable's output is printed whole when it ends, under cargo's own
`Running` line, and the step fails if any executable fails (their names are
listed at the end). The doc tests run last through cargo.

Usage: scripts/test_rust.py [ARGS...]   (ARGS go to every test executable,
e.g. a name filter or `--nocapture`)
"""

import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

# Measured in the cold CI runs of 2026-11-24 and 2026-11-25 (seconds,
# wall, per executable; `integration`, core's integration tests in one
# executable on libtest's two threads, took 142-144 s): the order in which
# to start the executables, so that a long one does not start last. A name
# missing here only starts later.
KNOWN_SECONDS = {
    "integration": 143,
    "browser": 54,
    "huge_fields": 16,
    "cli_slam": 14,
    "http_durability": 14,
    "cli_figures": 10,
    "interval_props": 10,
    "nvector_core": 5,
}


def build(root):
    """Builds the test executables; returns (name, kind, executable, package dir)."""
    cmd = [
        "cargo", "build", "--workspace", "--bins", "--tests", "--profile", "test",
        "--message-format=json-render-diagnostics",
    ]
    print(" ".join(cmd), flush=True)
    proc = subprocess.run(cmd, cwd=root, stdout=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit(proc.returncode)
    found = []
    for line in proc.stdout.splitlines():
        try:
            msg = json.loads(line)
        except json.JSONDecodeError:
            continue
        if msg.get("reason") != "compiler-artifact" or not msg.get("executable"):
            continue
        if not msg["profile"]["test"]:
            continue
        target = msg["target"]
        found.append((
            target["name"],
            target["kind"][0],
            target["src_path"],
            msg["executable"],
            os.path.dirname(msg["manifest_path"]),
        ))
    return found


def run_one(exe_info, args):
    name, _kind, src, exe, pkg_dir = exe_info
    env = dict(os.environ)
    env["CARGO_MANIFEST_DIR"] = pkg_dir
    start = time.monotonic()
    proc = subprocess.run(
        [exe, *args], cwd=pkg_dir, env=env,
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
    )
    seconds = time.monotonic() - start
    rel = os.path.relpath(src, pkg_dir)
    header = f"     Running {rel} ({os.path.relpath(exe, os.getcwd())})"
    out = proc.stdout.decode("utf-8", errors="replace")
    sys.stdout.write(f"{header}\n{out}     [{name}: {seconds:.1f} s]\n\n")
    sys.stdout.flush()
    return name, proc.returncode, seconds


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.chdir(root)
    args = sys.argv[1:]
    jobs = int(os.environ.get("NVECTOR_TEST_JOBS") or os.cpu_count() or 2)
    exes = build(root)
    if not exes:
        print("test_rust: cargo built no test executable", file=sys.stderr)
        sys.exit(1)
    exes.sort(key=lambda e: (-KNOWN_SECONDS.get(e[0], 0), e[0]))
    start = time.monotonic()
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        results = list(pool.map(lambda e: run_one(e, args), exes))
    wall = time.monotonic() - start
    failed = [name for name, code, _ in results if code != 0]
    slowest = sorted(results, key=lambda r: -r[2])[:8]
    print(f"test_rust: {len(results)} test executables, {jobs} at a time, {wall:.1f} s;"
          " the longest: " + ", ".join(f"{n} {s:.1f} s" for n, _, s in slowest))
    if failed:
        print("test_rust: FAILED: " + ", ".join(failed), file=sys.stderr)
        sys.exit(1)
    doc = subprocess.run(["cargo", "test", "--workspace", "--doc", "--", *args], cwd=root)
    sys.exit(doc.returncode)


if __name__ == "__main__":
    main()
