#!/usr/bin/env python3
"""The repository lint of `make lint`: fails (exit status 1), naming file and
line, when a git-tracked file

  1. names the folder that once sat beside the repository (the parent
     directory's `shared`): the repository stands alone, its data sets are
     under data/;
  2. is source (.rs .py .js .sh .toml .html .css, Makefile) and cites a
     numbered issue (the word issue or issues, any case, then a number,
     with or without #) in a comment, docstring or string: the reader of the code cannot open the
     tracker, so the text must give the reason itself. A citation right
     after a third party's `owner/repo` ("rust-lang/rust issue 1234") is
     another project's, and allowed;
  3. is Markdown and has a relative link (`[text](path)`, `![alt](path)`,
     `[label]: path`) to no existing file or directory.

    scripts/lint_repo.py [--paths PATH ...]   check the tracked files under PATHs (default: all)
    scripts/lint_repo.py --self-test          show each rule failing on a planted case
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# Spelled in two pieces so that this file does not name it itself.
OUTSIDE = ".." + "/" + "shared"

SOURCE_EXTS = (".rs", ".py", ".js", ".sh", ".toml", ".html", ".css")
ISSUE_WORD = "iss" + "ue"  # spelled in two pieces, as OUTSIDE
ISSUE = re.compile(r"\bissues?\s+#?\d+", re.IGNORECASE)
THIRD_PARTY = re.compile(r"\b[\w.-]+/[\w.-]+\s*$")

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
REF_LINK = re.compile(r"^\s*\[[^\]]+\]:\s*(\S+)")
INLINE_CODE = re.compile(r"`[^`]*`")


def is_source(path):
    name = os.path.basename(path)
    return name == "Makefile" or name.endswith(SOURCE_EXTS)


def outside_refs(path, text):
    """Rule 1: the lines of `text` that name the folder beside the repository."""
    return [(n, "names " + OUTSIDE + " (the repository must stand alone: use data/ or docs/)")
            for n, line in enumerate(text.splitlines(), 1) if OUTSIDE in line]


def issue_citations(path, text):
    """Rule 2: the lines of a source file that cite a numbered issue."""
    if not is_source(path):
        return []
    out = []
    for n, line in enumerate(text.splitlines(), 1):
        for m in ISSUE.finditer(line):
            if THIRD_PARTY.search(line[:m.start()]):
                continue
            out.append((n, f"cites \"{m.group(0)}\": say the reason instead of the issue number"))
            break
    return out


def is_relative(target):
    return not re.match(r"^([a-z][a-z0-9+.-]*:|#|/)", target, re.IGNORECASE)


def broken_links(path, text, root=ROOT):
    """Rule 3: the relative links of a Markdown file that point at nothing."""
    if not path.endswith(".md"):
        return []
    out, fenced = [], False
    base = os.path.dirname(os.path.join(root, path))
    for n, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith(("```", "~~~")):
            fenced = not fenced
            continue
        if fenced or line.startswith("    "):
            continue
        bare = INLINE_CODE.sub("", line)
        targets = [m.group(1) for m in LINK.finditer(bare)]
        ref = REF_LINK.match(bare)
        if ref:
            targets.append(ref.group(1))
        for t in targets:
            t = t.strip("<>")
            if not is_relative(t):
                continue
            file = t.split("#", 1)[0].split("?", 1)[0]
            if file and not os.path.exists(os.path.normpath(os.path.join(base, file))):
                out.append((n, f"links to {t}, which does not exist"))
    return out


RULES = (outside_refs, issue_citations, broken_links)


def tracked(paths):
    """The git-tracked files under `paths` (relative to the repository)."""
    cmd = ["git", "-C", ROOT, "ls-files", "-z", "--"] + list(paths)
    names = subprocess.run(cmd, check=True, capture_output=True).stdout.decode().split("\0")
    return [n for n in names if n and os.path.isfile(os.path.join(ROOT, n))]


def read_text(path):
    """The file's text, or None for a binary file."""
    with open(os.path.join(ROOT, path), "rb") as f:
        data = f.read()
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", errors="replace")


def lint(files, read=read_text, root=ROOT):
    """Every fault of `files`, as "path:line: message" strings."""
    faults = []
    for path in files:
        text = read(path)
        if text is None:
            continue
        for rule in RULES:
            found = rule(path, text, root) if rule is broken_links else rule(path, text)
            faults += [f"{path}:{n}: {msg}" for n, msg in found]
    return faults


def self_test():
    """Each rule must fail on a planted case and pass on its clean twin."""
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "docs"))
        for name in ("docs/here.md", "README.md"):
            open(os.path.join(root, name), "w").close()
        planted = {
            "a.rs": f"// the bound of {ISSUE_WORD} 18\nfn f() {{}}\n",
            "b.py": f'"""{ISSUE_WORD.title()}s 17-19: the lint."""\n',
            "c.sh": "# " + OUTSIDE + "/data is not in a clone\n",
            "Makefile": f"lint:  # {ISSUE_WORD.title()} 12: speed\n",
            "docs/d.md": "See [the page](missing.md) and ![fig](img/none.svg).\n",
            "e.toml": "# see ../" + OUTSIDE + "/x\n",
            "docs/f.md": "[label]: ../nowhere.md\n",
        }
        clean = {
            "a.rs": "#[cfg(test)]\n// a bound from the data (see docs/design.md)\n",
            "b.py": f"# upstream: rust-lang/rust {ISSUE_WORD} 1234 (another project's)\nx = {{'{ISSUE_WORD}': 3}}\n",
            "c.sh": "# the data sets are in data/\n",
            "Makefile": "lint:  # fast enough for every commit\n",
            "docs/d.md": "See [here](here.md#top), [the README](../README.md), "
                         "[site](https://example.org/x.md), `[x](nope.md)`.\n\n    [y](nope.md)\n",
            "e.toml": "# the issues of the tracker are not cited\n",
            "docs/f.md": "```\n[z](nope.md)\n```\n[label]: here.md\n",
        }
        ok = True
        for name in planted:
            bad = lint([name], read=lambda p: planted[p], root=root)
            good = lint([name], read=lambda p: clean[p], root=root)
            if not bad or good:
                ok = False
            print(f"self-test {name}: planted -> {bad or 'NOT CAUGHT'}; clean -> {good or 'passes'}")
        print("self-test:", "every rule caught its planted case" if ok else "FAILED")
        return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--paths", nargs="+", default=[], help="files or folders to check (default: every tracked file)")
    ap.add_argument("--self-test", action="store_true", help="show each rule failing on a planted case")
    args = ap.parse_args()
    if args.self_test:
        return 0 if self_test() else 1
    files = tracked(args.paths)
    faults = lint(files)
    for f in faults:
        print(f, file=sys.stderr)
    if faults:
        print(f"lint_repo: {len(faults)} fault(s) in {len(files)} files", file=sys.stderr)
        return 1
    print(f"lint_repo: {len(files)} files, no fault")
    return 0


if __name__ == "__main__":
    sys.exit(main())
