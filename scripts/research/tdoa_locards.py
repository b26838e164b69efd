#!/usr/bin/env python3
"""LocaRDS figures of BENCHMARKS.md (docs/tdoa.md): for each imported set
(`nvector import --locards-mlat`) and its result (`nvector tdoa`), the share
of messages whose box holds the truth, the median and 90th percentile box
diameter, and beside them a plain least-squares multilateration of the same
messages (Levenberg-Marquardt on x, y, z, tau with the time stamps' centres,
c = the nominal speed in meta; standard library only) and its error against
the truth. Usage: tdoa_locards.py PROBLEM.json RESULT.json [...pairs]."""
import json
import math
import sys


def solve4(a, b):
    """Solves the 4x4 system a x = b (Gaussian elimination, pivoting)."""
    n = 4
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        if abs(m[p][c]) < 1e-300:
            return None
        m[c], m[p] = m[p], m[c]
        for r in range(n):
            if r != c:
                f = m[r][c] / m[c][c]
                for k in range(c, n + 1):
                    m[r][k] -= f * m[c][k]
    return [m[i][n] / m[i][i] for i in range(n)]


def least_squares(rx, t, c, start):
    """LM on r_i = |x - rx_i| / c + tau - t_i (tau scaled by c: metres)."""
    x = list(start)
    lam = 1e-3

    def cost(x):
        return sum((math.dist(x[:3], r) + x[3] - c * ti) ** 2 for r, ti in zip(rx, t))

    f = cost(x)
    for _ in range(200):
        jtj = [[0.0] * 4 for _ in range(4)]
        jtr = [0.0] * 4
        for r, ti in zip(rx, t):
            d = math.dist(x[:3], r) or 1e-9
            res = d + x[3] - c * ti
            j = [(x[0] - r[0]) / d, (x[1] - r[1]) / d, (x[2] - r[2]) / d, 1.0]
            for a in range(4):
                jtr[a] += j[a] * res
                for b in range(4):
                    jtj[a][b] += j[a] * j[b]
        for a in range(4):
            jtj[a][a] *= 1 + lam
        step = solve4(jtj, [-v for v in jtr])
        if step is None:
            break
        y = [x[i] + step[i] for i in range(4)]
        g = cost(y)
        if g < f:
            x, f, lam = y, g, lam / 3
            if max(abs(s) for s in step[:3]) < 1e-4:
                break
        else:
            lam *= 5
    return x


def quantile(v, q):
    v = sorted(v)
    return v[min(len(v) - 1, int(q * (len(v) - 1) + 0.5))] if v else float("nan")


def main(args):
    for pf, rf in zip(args[::2], args[1::2]):
        p, r = json.load(open(pf)), json.load(open(rf))
        c = p["meta"]["nominal_speed"]
        rx = [[(a + b) / 2 for a, b in q["position"]] for q in p["receivers"]]
        inside, diam, ls_err = 0, [], []
        for k, pulse in enumerate(p["pulses"]):
            truth = p["truth"]["positions"][k]
            box = r["pulses"][k]
            if box != "empty" and all(lo <= v <= hi for (lo, hi), v in zip(box, truth)):
                inside += 1
            diam.append(math.sqrt(sum((hi - lo) ** 2 for lo, hi in box)) if box != "empty" else 0.0)
            rs = [rx[a["receiver"]] for a in pulse["arrivals"]]
            ts = [(a["time"][0] + a["time"][1]) / 2 for a in pulse["arrivals"]]
            # Start: above the receivers' mean, tau from the earliest arrival.
            m = [sum(q[i] for q in rs) / len(rs) for i in range(3)]
            start = [m[0], m[1], m[2] + 10000.0, -1e5]
            x = least_squares(rs, ts, c, start)
            ls_err.append(math.dist(x[:3], truth))
        n = len(p["pulses"])
        print(json.dumps({
            "set": p["name"], "messages": n, "truth_inside": inside / n,
            "median_diameter_m": quantile(diam, 0.5), "p90_diameter_m": quantile(diam, 0.9),
            "ls_median_error_m": quantile(ls_err, 0.5), "ls_p90_error_m": quantile(ls_err, 0.9),
            "ms_per_message": r["metrics"]["elapsed_ms"] / n,
        }))


if __name__ == "__main__":
    main(sys.argv[1:])
