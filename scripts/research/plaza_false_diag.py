#!/usr/bin/env python3
# Usage: scripts/research/plaza_false_diag.py NVECTOR PLAZA_DIR [SEEDS]
# (the Plaza-with-false-ranges diagnosis of docs/outliers.md).
# Diagnosis of CMU Plaza 1 with 71 planted false ranges (ids hidden), no solver change:
#  1. the clean ids-hidden run (`run --contractor best`): its boxes are an optimistic
#     oracle (what a robust run could at best reach);
#  2. per planted false range (seeds 1,2,3 unless SEEDS = "1,2,..."): its truth margin (how
#     far its interval misses every beacon's true distance from the true position), and
#     whether the clean run's boxes refute it one by one (its interval meets no distance from
#     the position box of its step to any box of any landmark region);
#     per group of the clean run, how many false ranges could join it (their annulus from the
#     clean position box meets its landmark region);
#     the same for the tight bands' outside ranges (--outlier-share 0.01, 0.02);
#  3. the density the ordinary propagation needs: the clean mission with every B-th range
#     kept (B = 2, 3, 4, 8, 72; 72 = q + 1 interleaved blocks), q = 0, max/mean diameter;
#  4. what the clean run's first proofs need: the ranges before step T only (T = 600, 1200),
#     then the same without the first 71 ranges of one beacon (a reading may drop them): the
#     groups proved, and the widest position box before T;
#  5. the covering of the annuli (a landmark-region rule for range-only data, prototyped here):
#     the n beacons must lie, between them, in the annuli (from the clean run's position
#     boxes) of all but q of the ranges before step 1200; 4 m cells; for 15 cells sampled more
#     than 30 m from every beacon, the ranges covered by that cell and 3 greedy companions (a
#     configuration the covering cannot exclude when it reaches |W| - q);
#  6. the smallest family of subsets that every reading keeps one of, for sets of a share
#     rho of the ranges: C(k, q) / C(k - rho k, q) (each set is avoided by that many drops).
import json, math, os, subprocess, sys, statistics
N, DIR = sys.argv[1], sys.argv[2]
seeds = [int(s) for s in sys.argv[3].split(',')] if len(sys.argv) > 3 else [1, 2, 3]
tmp = os.environ.get('TMPDIR', '/tmp') + f'/plazadiag{os.getpid()}'; os.makedirs(tmp, exist_ok=True)
def imp(out, *extra):
    subprocess.run([N, 'import', '--cmu-plaza', DIR, *extra, '--out', out], check=True, capture_output=True)
def run(p):
    r = p + '.r.json'; subprocess.run([N, 'run', p, '--contractor', 'best', '--out', r], check=True, capture_output=True)
    return json.load(open(r))
def dist_box(px, py, b):  # [min, max] distance from the box px x py to the box b
    def axis(a, c):
        return max(0.0, c[0] - a[1], a[0] - c[1]), max(abs(c[1] - a[0]), abs(a[1] - c[0]))
    (xl, xh), (yl, yh) = axis(px, b[0]), axis(py, b[1])
    return math.hypot(xl, yl), math.hypot(xh, yh)
clean = f'{tmp}/clean.json'; imp(clean); rc = run(clean)
print(f"clean: {rc['status']} recall {rc['score']['matching_recall']:.2f} max/mean diameter "
      f"{rc['metrics']['max_trajectory_diameter']:.1f}/{rc['metrics']['mean_trajectory_diameter']:.1f} m", flush=True)
traj, regions = rc['trajectory'], rc['landmark_regions']
for s in seeds:
    p = f'{tmp}/p{s}.json'; imp(p, '--false-detections', '71', '--seed', str(s)); m = json.load(open(p))
    T = m['truth']; margins, refuted, widths = [], 0, []
    for j, d in enumerate(m['detections']):
        if T['matching'][j] is not None:
            continue
        t, (lo, hi) = d['step'], d['range']; x, y = T['positions'][t]
        margins.append(min(max(lo - math.hypot(a - x, b - y), math.hypot(a - x, b - y) - hi) for a, b in T['landmarks']))
        pb = traj[t]; widths.append(max(pb[0][1] - pb[0][0], pb[1][1] - pb[1][0]))
        refuted += not any(dl <= hi and dh >= lo for reg in regions for bx in reg for dl, dh in [dist_box(pb[0], pb[1], bx)])
    per = [sum(1 for j, d in enumerate(m['detections']) if T['matching'][j] is None and any(
        (lambda dl, dh: dl <= d['range'][1] and dh >= d['range'][0])(*dist_box(traj[d['step']][0], traj[d['step']][1], bx))
        for bx in reg)) for reg in regions]
    big = sorted(c for c, g in zip(per, rc['matching']) if len(g) >= 100)
    print(f'seed {s}: per group of the clean run, the false ranges whose annulus meets its landmark region: '
          f'min {min(per)}, median {statistics.median(per)}, max {max(per)}; groups of 100 or more: {big}', flush=True)
    margins.sort()
    over = ' '.join(f'>{e}:{sum(1 for g in margins if g > e)}' for e in (0.5, 1, 2, 5, 10))
    print(f'seed {s}: {len(margins)} false ranges; truth margin min {margins[0]:.2f} median {statistics.median(margins):.2f} m; '
          f'counts {over}; clean position box at their steps median {statistics.median(widths):.1f} m; '
          f'refuted one by one with the clean boxes: {refuted}', flush=True)
for P in ('0.01', '0.02'):  # the tight bands: the ranges left outside (meta.outlier_share.outside)
    p = f'{tmp}/share{P}.json'; imp(p, '--outlier-share', P); m = json.load(open(p)); T = m['truth']
    out = m['meta']['outlier_share']['outside']; margins, refuted = [], 0
    for j in out:
        d = m['detections'][j]; t, (lo, hi) = d['step'], d['range']; x, y = T['positions'][t]
        margins.append(min(max(lo - math.hypot(a - x, b - y), math.hypot(a - x, b - y) - hi) for a, b in T['landmarks']))
        pb = traj[t]
        refuted += not any(dl <= hi and dh >= lo for reg in regions for bx in reg for dl, dh in [dist_box(pb[0], pb[1], bx)])
    print(f"share {P}: q {m['max_outliers']}, {len(out)} outside; margin to every beacon <= 0 (fits another): "
          f"{sum(1 for g in margins if g <= 0)}, largest {max(margins):.2f} m; refuted one by one with the clean boxes: {refuted}", flush=True)
mc = json.load(open(clean)); dets = mc['detections']
order = sorted(range(len(dets)), key=lambda j: (dets[j]['step'], j))
for B in (2, 3, 4, 8, 72):
    keep = sorted(j for r, j in enumerate(order) if r % B == 0); sub = dict(mc)
    sub['detections'] = [dets[j] for j in keep]; sub['truth'] = dict(mc['truth'])
    sub['truth']['matching'] = [mc['truth']['matching'][j] for j in keep]; sub.pop('meta', None)
    p = f'{tmp}/every{B}.json'; json.dump(sub, open(p, 'w')); r = run(p)
    print(f"every {B}th range ({len(keep)}): recall {r['score']['matching_recall']:.2f} max/mean diameter "
          f"{r['metrics']['max_trajectory_diameter']:.1f}/{r['metrics']['mean_trajectory_diameter']:.1f} m", flush=True)
tm = mc['truth']['matching']
for T in (600, 1200):
    pre = [j for j, d in enumerate(dets) if d['step'] < T]
    for b in (None, 0, 1, 2, 3):
        drop = set([j for j in pre if tm[j] == b][:71]) if b is not None else set()
        keep = [j for j in pre if j not in drop]; sub = dict(mc)
        sub['detections'] = [dets[j] for j in keep]; sub['truth'] = dict(mc['truth'])
        sub['truth']['matching'] = [tm[j] for j in keep]; sub.pop('meta', None)
        p = f'{tmp}/pre{T}_{b}.json'; json.dump(sub, open(p, 'w')); r = run(p)
        w = max(max(x[0][1] - x[0][0], x[1][1] - x[1][0]) for x in r['trajectory'][:T])
        what = 'all' if b is None else f'without the first 71 of beacon {b}'
        print(f"ranges before step {T}, {what} ({len(keep)}): {len(r['matching'])} groups, "
              f"{r['metrics']['matched_detections']} matched, {r['score']['matching_errors']} errors; "
              f"widest position box before {T}: {w:.1f} m", flush=True)
import random
pk = json.load(open(f'{tmp}/p{seeds[0]}.json')); Wr = [(d['step'], d['range']) for d in pk['detections'] if d['step'] < 1200]
h, R = 4.0, 100; cells = [(x, y) for x in range(-R, R, 4) for y in range(-R, R, 4)]
def covered(x, y):
    cb, st = ((x, x + h), (y, y + h)), set()
    for j, (t, (lo, hi)) in enumerate(Wr):
        dl, dh = dist_box(traj[t][0], traj[t][1], cb)
        if dl <= hi and dh >= lo:
            st.add(j)
    return st
sets = [covered(x, y) for x, y in cells]
def greedy(first):
    got = set(sets[first])
    for _ in range(3):
        got |= max(sets, key=lambda st: len(st - got))
    return len(got)
Lk = pk['truth']['landmarks']
far = [i for i, (x, y) in enumerate(cells) if min(math.hypot(x + h / 2 - a, y + h / 2 - b) for a, b in Lk) > 30]
random.seed(1); cov = sorted(greedy(i) for i in random.sample(far, 15))
print(f'covering, seed {seeds[0]}, {len(Wr)} ranges before step 1200, q 71: cells > 30 m from every beacon reach '
      f'{sum(1 for c in cov if c >= len(Wr) - 71)} of 15 (need {len(Wr) - 71}; covered {cov[0]}-{cov[-1]})', flush=True)
for k, q in ((3600, 71), (3529, 25), (3529, 54)):
    for rho in (0.5, 1 / 3):
        lg = math.log10(math.comb(k, q)) - math.log10(math.comb(k - int(rho * k), q))
        print(f'k {k} q {q}: a family of sets of {rho:.2f} k that every set of q drops keeps one of has >= 10^{lg:.1f} sets')
