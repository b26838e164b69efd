#!/usr/bin/env python3
"""Measures the facts that data/*/README.md state about the three real data
sets, from their files alone (standard library only).
    python3 scripts/research/data_facts.py [plaza|woods|locards ...]
Each line printed is one fact; the READMEs quote them."""
import bisect
import csv
import json
import math
import os
import statistics
import sys

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data")


def rows(path, sep=None):
    """The numeric rows of a whitespace- or comma-separated file."""
    with open(path) as f:
        out = []
        for line in f:
            cells = line.replace(",", " ").split() if sep is None else line.split(sep)
            if cells:
                out.append([float(c) for c in cells])
        return out


def quantile(xs, q):
    """The q-quantile of xs (nearest rank)."""
    s = sorted(xs)
    return s[min(len(s) - 1, max(0, math.ceil(q * len(s)) - 1))]


def wrap(a):
    """a brought into [-pi, pi)."""
    return (a + math.pi) % (2 * math.pi) - math.pi


def plaza():
    d = os.path.join(DATA, "cmu-plaza1")
    dr = rows(os.path.join(d, "Plaza1_DR.txt"))
    gt = rows(os.path.join(d, "Plaza1_GT.csv"))
    td = rows(os.path.join(d, "Plaza1_TD.txt"))
    tl = {int(r[0]): (r[1], r[2]) for r in rows(os.path.join(d, "Plaza1_TL.csv"))}
    print(f"plaza: {len(dr)} odometry rows, {len(gt)} truth rows, {len(td)} ranges, {len(tl)} beacons {sorted(tl)}")
    print(f"plaza: duration {gt[-1][0] - gt[0][0]:.0f} s")
    dts = [b[0] - a[0] for a, b in zip(dr, dr[1:])]
    print(f"plaza: odometry interval {min(dts):.3f} to {max(dts):.3f} s, median {statistics.median(dts):.3f} s")
    # Row k of GT is the pose before odometry row k: GT[k+1].t == DR[k].t.
    same_t = sum(1 for k in range(len(dr)) if abs(gt[k + 1][0] - dr[k][0]) < 1e-9)
    print(f"plaza: truth row k+1 has the time of odometry row k for {same_t} of {len(dr)} rows")
    # Heading: the truth's heading against the integrated odometry heading.
    th = gt[0][3]
    worst = 0.0
    for k, r in enumerate(dr):
        th += r[2]
        worst = max(worst, abs(wrap(gt[k + 1][3] - th)))
    print(f"plaza: |truth heading - integrated odometry heading| <= {worst:.1e} rad")
    # Step length against delta_distance; backward steps.
    res, backs = [], []
    for k, r in enumerate(dr):
        dx, dy = gt[k + 1][1] - gt[k][1], gt[k + 1][2] - gt[k][2]
        res.append((abs(math.hypot(dx, dy) - r[1]), k))
        along = dx * math.cos(gt[k + 1][3]) + dy * math.sin(gt[k + 1][3])
        if along < -1e-3:
            backs.append((-along, k))
    for tol in (1e-4, 1e-3, 2e-2):
        print(f"plaza: |true step length - delta_distance| < {tol:g} m on {sum(e < tol for e, _ in res)} of {len(res)} steps")
    backs.sort()
    print(f"plaza: {len(backs)} steps of the truth move backwards; the largest two {backs[-1][0]:.3f} m (row {backs[-1][1]}) "
          f"and {backs[-2][0]:.3f} m (row {backs[-2][1]}), the next {backs[-3][0]:.3f} m")
    # Ranges against the true distance (truth interpolated at the range time).
    ts = [r[0] for r in gt]
    errs = []
    for t, _, beacon, rng in td:
        i = min(max(bisect.bisect(ts, t), 1), len(ts) - 1)
        a, b = gt[i - 1], gt[i]
        w = (t - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
        x, y = a[1] + w * (b[1] - a[1]), a[2] + w * (b[2] - a[2])
        bx, by = tl[int(beacon)]
        errs.append(rng - math.hypot(x - bx, y - by))
    print(f"plaza: range - true distance: mean {statistics.mean(errs):+.2f} m, min {min(errs):+.2f} m, max {max(errs):+.2f} m")
    pts = list(tl.values())
    sep = min(math.dist(p, q) for i, p in enumerate(pts) for q in pts[i + 1:])
    print(f"plaza: beacons at least {sep:.1f} m apart")


def table(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def woods():
    d = os.path.join(DATA, "utias-lost-in-the-woods")
    odo, meas = table(os.path.join(d, "odometry.csv")), table(os.path.join(d, "measurements.csv"))
    truth, lm = table(os.path.join(d, "truth.csv")), table(os.path.join(d, "landmarks.csv"))
    print(f"woods: {len(odo)} odometry rows over {float(odo[-1]['t']):.1f} s, {len(meas)} detections, {len(lm)} landmarks")
    invalid = sum(1 for r in truth if r["valid"] != "1")
    print(f"woods: {invalid} truth rows invalid")
    per_t = {}
    for m in meas:
        per_t.setdefault(m["t"], []).append(m["landmark"])
    print(f"woods: at most {max(len(v) for v in per_t.values())} detections at once; "
          f"{len(odo) - len(per_t)} steps without detection; "
          f"a landmark twice in one scan: {sum(len(v) != len(set(v)) for v in per_t.values())} times")
    rs = [float(m["range"]) for m in meas]
    print(f"woods: ranges {min(rs):.2f} to {max(rs):.2f} m")
    pts = [(float(r["x"]), float(r["y"])) for r in lm]
    sep = min(math.dist(p, q) for i, p in enumerate(pts) for q in pts[i + 1:])
    print(f"woods: landmarks at least {sep:.3f} m apart")
    # Residuals against the truth: the laser sits d ahead of the centre.
    dlaser = 0.219016
    tr = {r["t"]: r for r in truth}
    er, eb = [], []
    for m in meas:
        r = tr[m["t"]]
        if r["valid"] != "1":
            continue
        x, y, th = float(r["x"]), float(r["y"]), float(r["theta"])
        sx, sy = x + dlaser * math.cos(th), y + dlaser * math.sin(th)
        lx, ly = pts[int(m["landmark"])]
        er.append(float(m["range"]) - math.hypot(lx - sx, ly - sy))
        eb.append(wrap(float(m["bearing"]) - (math.atan2(ly - sy, lx - sx) - th)))
    print(f"woods: range residual {min(er):+.3f} to {max(er):+.3f} m; bearing residual {min(eb):+.2f} to {max(eb):+.2f} rad")
    hs = []
    for k in range(len(odo) - 1):
        a, b = truth[k], truth[k + 1]
        if a["valid"] == "1" and b["valid"] == "1":
            dt = float(odo[k + 1]["t"]) - float(odo[k]["t"])
            hs.append(wrap(float(b["theta"]) - float(a["theta"]) - dt * float(odo[k]["om"])))
    print(f"woods: heading step residual 1%..99% {quantile(hs, 0.01):+.3f}..{quantile(hs, 0.99):+.3f} rad, "
          f"extremes {min(hs):+.3f} and {max(hs):+.3f} rad")


def ecef(lat, lon, h):
    """WGS84 geodetic (degrees, metres) to earth-centred coordinates (m)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    la, lo = math.radians(lat), math.radians(lon)
    n = a / math.sqrt(1 - e2 * math.sin(la) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo), (n * (1 - e2) + h) * math.sin(la))


def locards():
    d = os.path.join(DATA, "locards-mlat")
    sensors = {r["serial"]: ecef(float(r["latitude"]), float(r["longitude"]), float(r["height"]))
               for r in table(os.path.join(d, "sensors.csv"))}
    c = 299792458.0
    msgs, aircraft, seps, dists, res, alt = 0, set(), [], [], [], []
    for n in range(1, 5):
        for r in table(os.path.join(d, f"set_{n}.csv")):
            msgs += 1
            aircraft.add(r["aircraft"])
            meas = json.loads(r["measurements"])
            p = ecef(float(r["latitude"]), float(r["longitude"]), float(r["geoAltitude"]))
            rx = [sensors[str(m[0])] for m in meas]
            seps += [math.dist(a, b) for i, a in enumerate(rx) for b in rx[i + 1:]]
            ds = [math.dist(p, s) for s in rx]
            dists += ds
            # Arrival minus time of flight, less one offset per message (their mean).
            e = [m[1] - dd / c * 1e9 for m, dd in zip(meas, ds)]
            off = statistics.mean(e)
            res += [abs(x - off) for x in e]
            alt.append(float(r["baroAltitude"]) - float(r["geoAltitude"]))
    print(f"locards: {msgs} messages of {len(aircraft)} aircraft, {len(sensors)} sensors listed")
    print(f"locards: receivers of a message {min(seps) / 1e3:.0f} to {max(seps) / 1e3:.0f} km apart "
          f"(median {statistics.median(seps) / 1e3:.0f} km); aircraft {min(dists) / 1e3:.0f} to {max(dists) / 1e3:.0f} km from a receiver")
    print(f"locards: |arrival - distance/c - per-message mean|: median {statistics.median(res):.0f} ns, "
          f"90% {quantile(res, 0.9):.0f} ns, 99% {quantile(res, 0.99):.0f} ns, max {max(res):.0f} ns")
    print(f"locards: barometric minus geometric altitude {min(alt):+.0f} to {max(alt):+.0f} m, "
          f"median {statistics.median(alt):+.0f} m")


if __name__ == "__main__":
    which = sys.argv[1:] or ["plaza", "woods", "locards"]
    for name in which:
        {"plaza": plaza, "woods": woods, "locards": locards}[name]()
