#!/usr/bin/env python3
# Usage: scripts/research/false_detections_bench.py NVECTOR K line,ring,random [SEEDS]
#        scripts/research/false_detections_bench.py NVECTOR K --scenario woods [--steps N] [--seeds A-B] [--timeout S] [--operator]
# (the false-detection figures of BENCHMARKS.md).
# Paper scenario with K false detections: per layout, median recall, errors,
# truth inside, median max diameter, phantoms proved false; with
# NVBENCH_PER_RUN=1 also one line per run as it ends (with the CPU time of
# `nvector run`).
# Woods scenario (the odometry2d robot) with K false detections: one
# line per seed (status, truth inside, matching errors, recall, max
# trajectory diameter, max heading width, elapsed), each `nvector run
# --contractor best` killed after --timeout seconds (default 300), then a
# summary line.
import json, sys, subprocess, statistics, os, resource, time
N = sys.argv[1]; K = int(sys.argv[2]); rest = sys.argv[3:]
tmp = os.environ.get('TMPDIR', '/tmp') + f'/nvbench{os.getpid()}'; os.makedirs(tmp, exist_ok=True)


def flag(name, default):
    if name in rest:
        i = rest.index(name); v = rest[i + 1]; del rest[i:i + 2]; return v
    return default


def seed_range(text):
    a, _, b = text.partition('-')
    return range(int(a), int(b or a) + 1)


def width(iv):
    lo, hi = (float(x) for x in iv)  # "-inf"/"inf" read as floats
    return hi - lo


def woods():
    steps = flag('--steps', '300'); seeds = seed_range(flag('--seeds', '1-5')); limit = float(flag('--timeout', '300'))
    operator = '--operator' in rest
    rows = []
    for s in seeds:
        p, r = f'{tmp}/w.json', f'{tmp}/wr.json'
        args = [N, 'simulate', '--scenario', 'woods', '--seed', str(s), '--steps', steps, '--out', p]
        if K: args += ['--false-detections', str(K)]
        if operator: args += ['--operator']
        subprocess.run(args, check=True, capture_output=True)
        t0 = time.monotonic()
        try:
            subprocess.run([N, 'run', p, '--contractor', 'best', '--out', r], check=True, capture_output=True, timeout=limit)
        except subprocess.TimeoutExpired:
            print(f'K={K} woods seed {s}: timeout after {limit:.0f} s', flush=True); rows.append(None); continue
        wall = time.monotonic() - t0
        res = json.load(open(r)); sc = res['score']
        diam = res['metrics']['max_trajectory_diameter']
        hw = max(width(h) for h in res['headings'])
        row = (res['status'], sc['truth_inside'], sc['matching_errors'], sc['matching_recall'], diam, hw, res['metrics']['elapsed_ms'], wall, len(res['matching']))
        rows.append(row)
        print(f'K={K} woods seed {s}: {row[0]} truth inside {row[1]} errors {row[2]} recall {row[3]:.2f} max diam {row[4]:.3f} max heading width {row[5]:.4f} groups {row[8]} elapsed {row[6]:.0f} ms (wall {row[7]:.1f} s)', flush=True)
    done = [x for x in rows if x]
    if done:
        print(f'K={K} woods {steps} steps: solved {len(done)}/{len(rows)} truth inside {sum(x[1] for x in done)} errors {sum(x[2] for x in done)} median recall {statistics.median(x[3] for x in done):.2f} median max diam {statistics.median(x[4] for x in done):.3f} median ms {statistics.median(x[6] for x in done):.0f}', flush=True)


if flag('--scenario', 'paper') == 'woods':
    woods(); sys.exit(0)
layouts = rest[0].split(','); seeds = range(1, int(rest[1]) + 1) if len(rest) > 1 else range(1, 11)
for lay in layouts:
    rec, errs, inside, diam, pf, tf, times, groups = [], 0, 0, [], [], 0, [], []
    for s in seeds:
        p, r = f'{tmp}/p.json', f'{tmp}/r.json'
        args = [N, 'simulate', '--scenario', 'paper', '--seed', str(s), '--layout', lay, '--out', p]
        if K: args += ['--false-detections', str(K)]
        subprocess.run(args, check=True, capture_output=True)
        cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([N, 'run', p, '--contractor', 'best', '--out', r], check=True, capture_output=True)
        cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = cpu1.ru_utime - cpu0.ru_utime + cpu1.ru_stime - cpu0.ru_stime
        m = json.load(open(p)); res = json.load(open(r))
        sc = res['score']; rec.append(sc['matching_recall']); errs += sc['matching_errors']; inside += sc['truth_inside'] and res['status'] == 'consistent'
        diam.append(res['metrics']['max_trajectory_diameter']); times.append(res['metrics']['elapsed_ms'])
        tm = m['truth']['matching']
        pf.append(sum(1 for j, t in enumerate(tm) if t is None and res['detections'][j] == 'empty'))
        tf += sum(1 for j, t in enumerate(tm) if t is not None and res['detections'][j] == 'empty')
        groups.append(len(res['matching']))
        if os.environ.get('NVBENCH_PER_RUN'):
            print(f'  K={K} {lay} seed {s}: {res["status"]} recall {rec[-1]:.2f} errors {sc["matching_errors"]} truth inside {sc["truth_inside"]} max diam {diam[-1]:.2f} phantoms proved false {pf[-1]} of {sum(1 for t in tm if t is None)} groups {groups[-1]} cpu {cpu:.2f} s elapsed {times[-1]:.0f} ms', flush=True)
    print(f'K={K} {lay}: median recall {statistics.median(rec):.2f} (min {min(rec):.2f}) errors {errs} truth-inside+consistent {inside}/{len(rec)} median max diam {statistics.median(diam):.2f} ({min(diam):.2f}-{max(diam):.2f}) phantoms proved false {pf} true proved false {tf} groups {groups} median ms {statistics.median(times):.0f}', flush=True)
