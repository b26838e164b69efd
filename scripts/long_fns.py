#!/usr/bin/env python3
"""Lists the functions of the workspace's crates (core/src, server/src,
web/src, python/src; outside `#[cfg(test)]` modules) of more
than LIMIT lines, with whether a reason is written above them: a comment
line starting with `// Long:` among the attributes and comments right
above the `fn`. Exit status 1 when one has no reason (`--check`).

    scripts/long_fns.py [--check] [DIR...]     (default: the four crates' src)
"""
import os
import re
import sys

LIMIT = 80
FN = re.compile(r'^\s*(pub(\([a-z]+\))?\s+)?(const\s+)?(unsafe\s+)?fn\s+([A-Za-z_0-9]+)')


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
            out.append((m.group(5), i + 1, end - i + 1, reason))
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
    roots = args or [r for r in ('core/src', 'server/src', 'web/src', 'python/src') if os.path.isdir(r)]
    rows = []
    for root in roots:
        for d, _, files in os.walk(root):
            for f in sorted(files):
                if f.endswith('.rs'):
                    p = os.path.join(d, f)
                    for name, line, n, reason in functions(p):
                        if n > LIMIT:
                            rows.append((n, f'{p}:{line}', name, reason))
    rows.sort(reverse=True)
    for n, where, name, reason in rows:
        print(f'{n:5} {name:32} {where}{"  (reason given)" if reason else ""}')
    missing = [r for r in rows if not r[3]]
    print(f'{len(rows)} functions over {LIMIT} lines, {len(missing)} without a reason')
    if check and missing:
        sys.exit(1)


if __name__ == '__main__':
    main()
