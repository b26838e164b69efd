#!/usr/bin/env python3
"""Lists the functions of the workspace's sources (core, server, web,
python; outside `#[cfg(test)]` modules, `tests.rs` files and the tests'
directories) of more
than LIMIT lines, with whether a reason is written above them: a comment
line starting with `// Long:` among the attributes and comments right
above the `fn`. With `--check` (run by `make test`, target `lint`): exit
status 1 when one has no reason and is not in scripts/long_fns.todo (the
functions being split elsewhere at the time of writing).

    scripts/long_fns.py [--check] [DIR...]
        (default: core/src server/src web/src python/src)
"""
import os
import re
import sys

LIMIT = 80
ROOTS = ['core/src', 'server/src', 'web/src', 'python/src']
TODO = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'long_fns.todo')


def todo():
    """The (path, function) pairs of scripts/long_fns.todo."""
    out = set()
    for line in open(TODO, encoding='utf-8'):
        line = line.strip()
        if line and not line.startswith('#'):
            path, name = line.split()
            out.add((path, name))
    return out
FN = re.compile(r'^\s*(pub(\([a-z]+\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?fn\s+([A-Za-z_0-9]+)')


def functions(path):
    lines = open(path, encoding='utf-8').read().split('\n')
    out = []
    skip_to = -1
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.strip() == '#[cfg(test)]' and i + 1 < len(lines) and re.match(r'\s*(pub(\([a-z]+\))?\s+)?mod\s+\w+\s*\{', lines[i + 1]):
            skip_to = block_end(lines, i + 1)
        if i <= skip_to:
            i += 1
            continue
        m = FN.match(line)
        if m and not line.rstrip().endswith(';'):
            end = block_end(lines, i)
            reason = False
            j = i - 1
            while j >= 0 and (lines[j].strip().startswith(('///', '//', '#['))):
                if lines[j].strip().startswith('// Long:'):
                    reason = True
                j -= 1
            out.append((m.group(6), i + 1, end - i + 1, reason))
        i += 1
    return out


def block_end(lines, start):
    depth = 0
    opened = False
    for k in range(start, len(lines)):
        code = lines[k].split('//')[0]
        for c in code:
            if c == '{':
                depth += 1
                opened = True
            elif c == '}':
                depth -= 1
        if opened and depth == 0:
            return k
    return len(lines) - 1


def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    check = '--check' in sys.argv
    roots = args or ROOTS
    rows = []
    for root in roots:
        for d, _, files in os.walk(root):
            for f in sorted(files):
                # `tests.rs`: a module's tests in a file of their own
                # (`#[cfg(test)] mod tests;`), test code as the inline ones.
                if f.endswith('.rs') and f != 'tests.rs':
                    p = os.path.join(d, f)
                    for name, line, n, reason in functions(p):
                        if n > LIMIT:
                            rows.append((n, f'{p}:{line}', name, reason))
    rows.sort(reverse=True)
    pending = todo()
    for n, where, name, reason in rows:
        path = where.rsplit(':', 1)[0]
        note = '  (reason given)' if reason else '  (being split: long_fns.todo)' if (path, name) in pending else ''
        print(f'{n:5} {name:32} {where}{note}')
    missing = [r for r in rows if not r[3] and (r[1].rsplit(':', 1)[0], r[2]) not in pending]
    long_now = {(r[1].rsplit(':', 1)[0], r[2]) for r in rows}
    for path, name in sorted(pending - long_now):
        if any(path.startswith(root) for root in roots):
            print(f'note: {path} {name} is no longer over {LIMIT} lines: remove it from scripts/long_fns.todo')
    print(f'{len(rows)} functions over {LIMIT} lines, {len(missing)} without a reason or a todo entry')
    for n, where, name, _ in missing:
        print(f'error: {where}: `{name}` is {n} lines: split it, or write the reason above it (`// Long: ...`)')
    if check and missing:
        sys.exit(1)


if __name__ == '__main__':
    main()
