#!/usr/bin/env python3
# Usage: scripts/false_detections_bench.py NVECTOR K line,ring,random [SEEDS]
# (issue 18; figures in BENCHMARKS.md).
# Paper scenario with K false detections: per layout, median recall, errors,
# truth inside, median max diameter, phantoms proved false; with
# NVBENCH_PER_RUN=1 also one line per run as it ends (with the CPU time of
# `nvector run`).
import json, sys, subprocess, statistics, os, resource
N = sys.argv[1]; K = int(sys.argv[2]); layouts = sys.argv[3].split(','); seeds = range(1, int(sys.argv[4]) + 1) if len(sys.argv) > 4 else range(1, 11)
tmp = os.environ.get('TMPDIR', '/tmp') + f'/nvbench{os.getpid()}'; os.makedirs(tmp, exist_ok=True)
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
