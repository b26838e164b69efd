#!/usr/bin/env python3
"""A planted false range that some solution keeps: why a strict
matching on CMU Plaza 1 with planted false ranges is empty.

Usage: scripts/research/plaza_witness.py MISSION.json [--all]

MISSION.json: `nvector import --cmu-plaza DIR --false-detections K --seed S`
(unicycle2d, planted ranges have `truth.matching` null).

For the planted range closest to a beacon's true distance (each with
--all), it builds a *witness*: the ground truth with the positions moved
by a triangular bump around the range's step, radially from that beacon,
so that the range holds that beacon's distance. It then checks, number by
number, every constraint of the mission without the other planted ranges:
the initial (and final) position boxes, every step's motion
(p(i+1) = p(i) + dt speed (cos heading, sin heading) + e, |e| <= motion
error per axis: a speed and a heading within their bounds are found and
printed with the slack left), every true range against its true beacon,
and the planted range against the beacon chosen. Floating point, not
outward-rounded: every slack printed is far above the rounding.

Why it matters (docs/outliers.md, "What blocks a strict matching on CMU Plaza 1"):
a reading may drop the K - 1 other planted ranges and any one true range
t; the witness, which does not need t, is a solution of that reading. So
every true range is dropped by some reading, no detection is kept in every
reading, and no group can be proved: a sound solver's recall on this
mission is 0, whatever its reasoning.
"""
import json
import math
import sys


def interval_of(channel, i):
    """(lo, hi) of an input channel at step i."""
    if "lo" in channel:
        return channel["lo"][i], channel["hi"][i]
    e = channel["error"]
    e = e[i] if isinstance(e, list) else e
    v = channel["value"][i]
    return v - e, v + e


def motion_slack(d, speed, heading, dt, me):
    """A slack me - |e|_inf reached by a speed in `speed` and a heading in
    `heading` (the first heading of a grid, middle out, that leaves a slack
    of at least a tenth of `me`, else the largest; ternary search over the
    speed, the residual being convex in it); returns (slack, speed,
    heading)."""
    best = (-math.inf, None, None)
    lo, hi = heading
    for g in sorted(range(201), key=lambda g: abs(g - 100)):
        h = lo + (hi - lo) * g / 200
        c, s = math.cos(h) * dt, math.sin(h) * dt

        def res(v):
            return max(abs(d[0] - v * c), abs(d[1] - v * s))

        a, b = speed
        for _ in range(80):
            m1, m2 = a + (b - a) / 3, b - (b - a) / 3
            if res(m1) <= res(m2):
                b = m2
            else:
                a = m1
        v = (a + b) / 2
        slack = me - res(v)
        if slack > best[0]:
            best = (slack, v, h)
        if slack >= 0.1 * me:
            break
    return best


def in_box(p, box):
    return all(lo <= x <= hi for x, (lo, hi) in zip(p, box))


def witness(m, j, beacon, verbose=True):
    t = m["truth"]
    pos = [list(p) for p in t["positions"]]
    lms = t["landmarks"]
    det = m["detections"][j]
    i = det["step"]
    lo, hi = det["range"]
    b = lms[beacon]
    d = math.dist(pos[i], b)
    # Aim a tenth of the way into the range's interval.
    target = lo + 0.1 * (hi - lo) if d < lo else hi - 0.1 * (hi - lo)
    u = [(pos[i][0] - b[0]) / d, (pos[i][1] - b[1]) / d]
    delta = target - d
    steps, dt = m["steps"], m.get("dt", 1.0)
    me_all = m.get("motion_error", 0.0)
    for w in (5, 10, 20, 50, 100, 200, 500):
        moved = [p[:] for p in pos]
        for k in range(max(0, i - w), min(steps, i + w) + 1):
            f = max(0.0, 1.0 - abs(k - i) / w)
            moved[k] = [pos[k][0] + delta * f * u[0], pos[k][1] + delta * f * u[1]]
        if moved[0] != pos[0] and not in_box(moved[0], m["initial_position"]):
            continue
        fp = m.get("final_position")
        if fp and not in_box(moved[steps], fp):
            continue
        worst = math.inf
        for k in range(max(0, i - w - 1), min(steps, i + w + 1)):
            disp = [moved[k + 1][0] - moved[k][0], moved[k + 1][1] - moved[k][1]]
            me = me_all[k] if isinstance(me_all, list) else me_all
            slack, _, _ = motion_slack(
                disp,
                interval_of(m["inputs"]["speed"], k),
                interval_of(m["inputs"]["heading"], k),
                dt,
                me,
            )
            worst = min(worst, slack)
        if worst < 0:
            continue
        # Every true range, and the planted one against `beacon`.
        range_slack = math.inf
        for jj, (dd, lab) in enumerate(zip(m["detections"], t["matching"])):
            if jj == j:
                lab = beacon
            elif lab is None:
                continue
            r = math.dist(moved[dd["step"]], lms[lab])
            range_slack = min(range_slack, r - dd["range"][0], dd["range"][1] - r)
        if range_slack < 0:
            return None
        if verbose:
            print(
                f"planted range {j} (step {i}, [{lo:.4f}, {hi:.4f}]) misses beacon {beacon} "
                f"by {lo - d if d < lo else d - hi:.4f} m at the true position; witness: the truth "
                f"moved by at most {abs(delta):.4f} m over steps {max(0, i - w)}..{min(steps, i + w)}; "
                f"motion slack >= {worst:.3e} m, range slack >= {range_slack:.3e} m: "
                f"consistent with every true range"
            )
        return w
    return None


def main():
    m = json.load(open(sys.argv[1]))
    every = "--all" in sys.argv
    t = m["truth"]
    cands = []
    for j, (det, lab) in enumerate(zip(m["detections"], t["matching"])):
        if lab is not None:
            continue
        p = t["positions"][det["step"]]
        if p is None:
            continue
        lo, hi = det["range"]
        for b, lm in enumerate(t["landmarks"]):
            d = math.dist(p, lm)
            cands.append((lo - d if d < lo else d - hi, j, b))
    cands.sort()
    if every:
        # Each planted range against its closest beacon only.
        seen = set()
        cands = [c for c in cands if not (c[1] in seen or seen.add(c[1]))]
    found = 0
    for margin, j, b in cands if every else cands[:8]:
        if witness(m, j, b):
            found += 1
            if not every:
                break
    planted = sum(1 for lab in t["matching"] if lab is None)
    print(f"{found} planted range(s) of {planted} shown consistent with every true range")
    sys.exit(0 if found else 1)


if __name__ == "__main__":
    main()
