#!/usr/bin/env python3
# Usage: scripts/research/compare_runs.py OLD_NVECTOR NEW_NVECTOR
# Simulates robust missions (paper K = 10 on every layout and range only,
# woods K = 5 and 10, 300 steps) and runs each with both binaries;
# prints per mission whether status, recall, max diameter, truth inside
# and errors are the same, with both wall times (BENCHMARKS.md,
# "Conflict packing: each conflict within its share").
import json, subprocess, sys, time, os
old, new = sys.argv[1], sys.argv[2]
cases = []
for lay in ('line','ring','random'):
    for s in range(1, 11):
        cases.append(('paper', s, ['--layout', lay, '--false-detections', '10'], f'paper-{lay}'))
for s in range(1, 6):
    cases.append(('paper', s, ['--range-only', '--false-detections', '10'], 'paper-range'))
for K in (5, 10):
    for s in (1, 2, 3):
        cases.append(('woods', s, ['--steps', '300', '--false-detections', str(K)], f'woods-K{K}'))
diffs = 0
for sc, s, extra, name in cases:
    m = f'/tmp/cmp-{name}-{s}.json'
    subprocess.run([new, 'simulate', '--scenario', sc, '--seed', str(s), *extra, '--out', m], check=True, capture_output=True)
    row = []
    for b in (old, new):
        r = m + '.r.json'
        t = time.time()
        p = subprocess.run([b, 'run', m, '--out', r], capture_output=True, timeout=600)
        el = time.time() - t
        if p.returncode != 0:
            row.append(('ERR', p.stderr[-200:])); continue
        x = json.load(open(r))
        row.append((x['status'], x['score']['matching_recall'], round(x['metrics']['max_trajectory_diameter'], 6), x['score']['truth_inside'], x['score']['matching_errors'], round(el, 1)))
    same = row[0][:5] == row[1][:5]
    diffs += not same
    print(name, s, 'SAME' if same else 'DIFF', row, flush=True)
print('diffs', diffs)
