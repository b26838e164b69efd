#!/usr/bin/env python3
"""Adversarial end-to-end soundness campaign for `nvector run` / `nvector tdoa`.

Simulates missions (paper, auv, woods, radar) with varied options, mutates
each one while keeping its truth inside its bounds (wider or infinite or
degenerate bounds, a shifted or scaled world, headings and bearings moved by
multiples of 2 pi, more landmarks than true, the exact minimum separation,
null truth entries, shuffled or duplicated detections, scans, ...), solves
it with every contractor and checks the result independently of its
`score`: status not infeasible, every true position, heading and landmark
inside its box, every proved group within one true landmark, no crash, no
timeout. Stdlib only.

    python3 scripts/soundness_campaign.py --bin target/release/nvector \
        --out /tmp/campaign --seeds 1-20 [--only woods] [--jobs 2]

A failure is written to OUT/fail-*.json (the mutated mission) with a line
in OUT/failures.jsonl; every case is a line of OUT/cases.jsonl.
"""

import argparse
import copy
import json
import math
import os
import random
import subprocess
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction

INF = float("inf")
TWO_PI = 2.0 * math.pi
CONTRACTORS = ["none", "nvalue", "projection", "independent", "shapes", "best"]


# ---------------------------------------------------------------- intervals


def num(x):
    if x == "inf":
        return INF
    if x == "-inf":
        return -INF
    if x is None:
        return None
    return float(x)


def ival(x):
    """An input or output interval as (lo, hi); None for "empty"."""
    if x == "empty" or x is None:
        return None
    if isinstance(x, (int, float)):
        return (float(x), float(x))
    return (num(x[0]), num(x[1]))


def out_lo(v):
    return "-inf" if v == -INF else v


def out_hi(v):
    return "inf" if v == INF else v


def mk(lo, hi):
    return [out_lo(lo), out_hi(hi)]


def down(x, k=1):
    for _ in range(k):
        x = math.nextafter(x, -INF)
    return x


def up(x, k=1):
    for _ in range(k):
        x = math.nextafter(x, INF)
    return x


def contains(iv, x):
    return iv is not None and iv[0] <= x <= iv[1]


def box_contains(box, p):
    if box == "empty" or box is None:
        return False
    return all(contains(ival(b), x) for b, x in zip(box, p))


# ---------------------------------------------------------------- simulate


def simulate(binary, scenario, args, timeout=60):
    cmd = [binary, "simulate", "--scenario", scenario] + [str(a) for a in args]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError("simulate failed: %s: %s" % (cmd, p.stderr[-500:]))
    return json.loads(p.stdout)


def base_missions(binary, seed, only):
    """(label, mission) pairs for one seed."""
    rng = random.Random(seed * 7919)
    out = []
    if only in (None, "paper"):
        for layout in ["line", "ring", "random"]:
            steps = rng.choice([1500, 3000, 5000])
            lms = rng.choice([2, 3, 4, 6, 9])
            args = ["--seed", seed, "--steps", steps, "--landmarks", lms, "--layout", layout]
            if rng.random() < 0.4:
                args.append("--range-only")
            if rng.random() < 0.4:
                args += ["--false-detections", rng.choice([1, 2, 5])]
            if rng.random() < 0.4:
                args.append("--operator")
            if rng.random() < 0.3:
                args += ["--noise", rng.choice([0.5, 2, 4])]
            out.append(("paper " + " ".join(map(str, args)), simulate(binary, "paper", args)))
    if only in (None, "auv"):
        steps = rng.choice([3000, 6000, 12000])
        args = ["--seed", seed, "--steps", steps]
        if rng.random() < 0.5:
            args.append("--operator")
        out.append(("auv " + " ".join(map(str, args)), simulate(binary, "auv", args)))
    if only in (None, "woods"):
        steps = rng.choice([60, 120, 200, 300])
        args = ["--seed", seed, "--steps", steps]
        if rng.random() < 0.3:
            args.append("--operator")
        out.append(("woods " + " ".join(map(str, args)), simulate(binary, "woods", args)))
    return out


# ---------------------------------------------------------------- mission walks


def dim(m):
    return 3 if m["model"] == "auv3d" else 2


def positions_boxes(m):
    """Every position-valued box of a mission (to shift or scale)."""
    boxes = [m["initial_position"]]
    if m.get("final_position") is not None:
        boxes.append(m["final_position"])
    if m.get("landmark_region") is not None:
        boxes.append(m["landmark_region"])
    for d in m["detections"]:
        if d.get("region") is not None:
            boxes.append(d["region"])
    return boxes


def add_error(m, key, w):
    e = m.get(key, 0)
    m[key] = [up(x + w, 2) for x in e] if isinstance(e, list) else up(e + w, 2)


def widen_ranges(m, w):
    for d in m["detections"]:
        lo, hi = ival(d["range"])
        d["range"] = mk(max(0.0, down(lo - w, 2)), up(hi + w, 2))
        if "bearing" in d:
            blo, bhi = ival(d["bearing"])
            a = min(math.pi, 4 * w / max(lo - w, 1e-300))
            d["bearing"] = mk(down(blo - a, 2), up(bhi + a, 2))


# ---------------------------------------------------------------- mutations
# Each takes (mission, rng) and returns a label, or None when it does not apply.


def m_identity(m, rng):
    return "identity"


def m_widen(m, rng):
    f = rng.choice([0.5, 2.0, 10.0])
    for box in positions_boxes(m):
        for iv in box:
            lo, hi = ival(iv)
            w = (hi - lo) * f + 1e-3
            iv[:] = mk(down(lo - w), up(hi + w))
    for d in m["detections"]:
        lo, hi = ival(d["range"])
        w = (hi - lo) * f * rng.random()
        d["range"] = mk(max(0.0, down(lo - w)), up(hi + w))
    return "widen x%s" % f


def m_inf(m, rng):
    d = dim(m)
    m["landmark_region"] = [["-inf", "inf"]] * d
    m["final_position"] = None
    if rng.random() < 0.5:
        m["initial_position"][rng.randrange(d)] = ["-inf", "inf"]
    for det in m["detections"]:
        if "region" in det and rng.random() < 0.5:
            det["region"] = [["-inf", "inf"]] * d
    return "inf bounds"


def m_huge(m, rng):
    d = dim(m)
    big = rng.choice([1e300, 1.7e308, 1e154])
    m["landmark_region"] = [[-big, big]] * d
    if rng.random() < 0.5:
        m["initial_position"] = [[-big, big]] * d
    if rng.random() < 0.5:
        m["final_position"] = [[-big, big]] * d
    for det in m["detections"]:
        if rng.random() < 0.2:
            det["range"] = [ival(det["range"])[0], big]
    return "huge bounds %g" % big


def m_zero(m, rng):
    t = m["truth"]
    if t["positions"][0] is not None:
        # A null truth at step 0 (an earlier mutation) leaves the box as it is.
        m["initial_position"] = [[x, x] for x in t["positions"][0]]
    if t["positions"][-1] is not None:
        m["final_position"] = [[x, x] for x in t["positions"][-1]]
    if m["model"] == "odometry2d" and t.get("headings"):
        h = t["headings"][0]
        if h is not None:
            m["initial_heading"] = [h, h]
        if t["headings"][-1] is not None and rng.random() < 0.5:
            m["final_heading"] = [t["headings"][-1]] * 2
    for i, det in enumerate(m["detections"]):
        j = t["matching"][i]
        if j is None or rng.random() < 0.6:
            continue
        lm = t["landmarks"][j]
        det["region"] = [[x, x] for x in lm]
        if m["model"] == "auv3d":
            det["depth"] = [lm[2], lm[2]]
    return "zero-width at truth"


def _shift_value(m, delta, w):
    d = dim(m)
    for box in positions_boxes(m):
        for a in range(d):
            lo, hi = ival(box[a])
            box[a] = mk(down(lo + delta[a], 2), up(hi + delta[a], 2))
    t = m["truth"]
    t["positions"] = [None if p is None else [x + dx for x, dx in zip(p, delta)] for p in t["positions"]]
    t["landmarks"] = [[x + dx for x, dx in zip(p, delta)] for p in t["landmarks"]]
    for det in m["detections"]:
        if "depth" in det:
            lo, hi = ival(det["depth"])
            det["depth"] = mk(down(lo + delta[2], 2), up(hi + delta[2], 2))
    add_error(m, "motion_error", w)
    for win in m.get("motion_drift", []):
        win["error"] = up(win["error"] + 4 * w, 2)
    widen_ranges(m, w)


def m_shift(m, rng):
    big = rng.choice([1e6, -1e6, 1e12, 3.3e9])
    d = dim(m)
    delta = [big * rng.choice([1, -1, 0.5]) for _ in range(d)]
    extent = max(abs(x) for p in m["truth"]["positions"] + m["truth"]["landmarks"] if p for x in p)
    w = 8 * math.ulp(abs(big) + extent + 1e3)
    _shift_value(m, delta, w)
    return "shift %g" % big


def _scale_interval_key(obj, key, s):
    if key in obj and obj[key] is not None:
        lo, hi = ival(obj[key])
        obj[key] = mk(lo * s, hi * s)


def m_scale(m, rng):
    k = rng.choice([-30, -10, 10, 40, 200, 500])
    s = math.ldexp(1.0, k)
    for box in positions_boxes(m):
        for iv in box:
            lo, hi = ival(iv)
            iv[:] = mk(lo * s, hi * s)
    lin = {"speed", "vx", "vy", "vz"}
    for name, ch in m["inputs"].items():
        if name in lin:
            if "value" in ch:
                ch["value"] = [v * s for v in ch["value"]]
                e = ch.get("error", 0)
                ch["error"] = [x * s for x in e] if isinstance(e, list) else e * s
            else:
                ch["lo"] = [v * s for v in ch["lo"]]
                ch["hi"] = [v * s for v in ch["hi"]]
    e = m.get("motion_error", 0)
    m["motion_error"] = [x * s for x in e] if isinstance(e, list) else e * s
    for win in m.get("motion_drift", []):
        win["error"] = win["error"] * s
        if "exempt_above" in win:
            win["exempt_above"] = win["exempt_above"] * s
    for det in m["detections"]:
        for key in ("range", "depth"):
            _scale_interval_key(det, key, s)
    for key in ("landmark_min_separation",):
        if key in m:
            m[key] = m[key] * s
    if "sensor_offset" in m:
        m["sensor_offset"] = [x * s for x in m["sensor_offset"]]
    t = m["truth"]
    t["positions"] = [None if p is None else [x * s for x in p] for p in t["positions"]]
    t["landmarks"] = [[x * s for x in p] for p in t["landmarks"]]
    return "scale 2^%d" % k


def _angle_channel(m):
    return {"unicycle2d": "heading", "auv3d": "yaw"}.get(m["model"])


def m_heading_wrap(m, rng):
    k = rng.choice([-3, 1, 7, 1000, -100000])
    c = TWO_PI * k
    w = 4 * math.ulp(abs(c) + 10)
    name = _angle_channel(m)
    if name:
        ch = m["inputs"][name]
        if "value" in ch:
            ch["value"] = [v + c for v in ch["value"]]
            e = ch.get("error", 0)
            ch["error"] = [x + w for x in e] if isinstance(e, list) else e + w
        else:
            ch["lo"] = [down(v + c, 2) for v in ch["lo"]]
            ch["hi"] = [up(v + c, 2) for v in ch["hi"]]
    else:
        lo, hi = ival(m["initial_heading"])
        m["initial_heading"] = mk(down(lo + c, 2), up(hi + c, 2))
        if m.get("final_heading") is not None:
            lo, hi = ival(m["final_heading"])
            m["final_heading"] = mk(down(lo + c, 2), up(hi + c, 2))
        t = m["truth"]
        if t.get("headings"):
            t["headings"] = [None if h is None else h + c for h in t["headings"]]
        add_error(m, "heading_error", w)
    return "heading +2pi*%d" % k


def m_bearing_wrap(m, rng):
    if not any("bearing" in d for d in m["detections"]):
        return None
    for d in m["detections"]:
        if "bearing" in d:
            k = rng.choice([-2, -1, 1, 3, 50])
            lo, hi = ival(d["bearing"])
            d["bearing"] = mk(down(lo + TWO_PI * k, 2), up(hi + TWO_PI * k, 2))
    return "bearing +2pi*k"


def m_more_landmarks(m, rng):
    if "landmark_count" not in m:
        return None
    k = rng.choice([1, 2, 10])
    m["landmark_count"] += k
    return "landmark_count +%d" % k


def exact_min_sep(landmarks):
    """The largest float <= the true minimum distance between landmarks."""
    best = None
    for i in range(len(landmarks)):
        for j in range(i + 1, len(landmarks)):
            d2 = sum((Fraction(a) - Fraction(b)) ** 2 for a, b in zip(landmarks[i], landmarks[j]))
            if best is None or d2 < best:
                best = d2
    if best is None:
        return None
    f = math.sqrt(float(best))
    while Fraction(f) ** 2 > best:
        f = down(f)
    while Fraction(up(f)) ** 2 <= best:
        f = up(f)
    return f


def m_min_sep(m, rng):
    t = m["truth"]
    used = sorted({j for j in t["matching"] if j is not None})
    lms = [t["landmarks"][j] for j in used] if rng.random() < 0.5 else t["landmarks"]
    f = exact_min_sep(lms)
    if f is None:
        return None
    m["landmark_min_separation"] = f
    return "min_sep exact %r" % f


def m_null_truth(m, rng):
    t = m["truth"]
    n = len(t["positions"])
    for i in rng.sample(range(n), max(1, n // 5)):
        t["positions"][i] = None
        if t.get("headings"):
            t["headings"][i] = None
    return "null truth"


def m_shuffle(m, rng):
    n = len(m["detections"])
    if n < 2:
        return None
    perm = list(range(n))
    rng.shuffle(perm)
    m["detections"] = [m["detections"][i] for i in perm]
    m["truth"]["matching"] = [m["truth"]["matching"][i] for i in perm]
    return "shuffle detections"


def m_duplicate(m, rng):
    # A copy of a false detection would be one false detection more than
    # max_outliers allows: only true detections are copied.
    true = [i for i, j in enumerate(m["truth"]["matching"]) if j is not None]
    if not true:
        return None
    for i in rng.sample(true, min(len(true), 5)):
        d = copy.deepcopy(m["detections"][i])
        d.pop("scan", None)
        m["detections"].append(d)
        m["truth"]["matching"].append(m["truth"]["matching"][i])
    return "duplicate detections"


def m_scans(m, rng):
    """Scan ids: same step and distinct true landmarks share a scan id."""
    t = m["truth"]
    by_step = {}
    for i, d in enumerate(m["detections"]):
        d.pop("scan", None)
        by_step.setdefault(d["step"], []).append(i)
    sid = rng.choice([0, 10**9, 2**53])
    for step, idx in sorted(by_step.items()):
        seen = set()
        for i in idx:
            j = t["matching"][i]
            if j is None or j in seen:
                continue
            seen.add(j)
            m["detections"][i]["scan"] = sid
        sid += rng.choice([1, 7])
    return "scans by step"


def m_no_scans(m, rng):
    if not any("scan" in d for d in m["detections"]):
        return None
    for d in m["detections"]:
        d.pop("scan", None)
    return "no scans"


def m_more_outliers(m, rng):
    k = rng.choice([1, 3])
    m["max_outliers"] = m.get("max_outliers", 0) + k
    return "max_outliers +%d" % k


def m_false(m, rng):
    """K planted false detections (truth.matching null, max_outliers + K),
    some sharing a true detection's scan (a false detection is exempt from
    the scan constraint)."""
    k = rng.choice([1, 2, 4])
    dets = m["detections"]
    for _ in range(k):
        step = rng.randrange(m["steps"] + 1)
        r = rng.uniform(0, 30)
        d = {"step": step, "range": [r, r + rng.choice([0.0, 0.2, 2.0])]}
        if dets and "bearing" in dets[0]:
            b = rng.uniform(-4, 4)
            d["bearing"] = [b, b + 0.1]
        if m["model"] == "auv3d" and dets and "depth" in dets[0]:
            d["depth"] = dets[0]["depth"]
        same = [x for x in dets if x["step"] == step and "scan" in x]
        if same and rng.random() < 0.7:
            d["scan"] = same[0]["scan"]
        if any("region" in x for x in dets):
            d["region"] = [["-inf", "inf"]] * dim(m)
        dets.append(d)
        m["truth"]["matching"].append(None)
    m["max_outliers"] = m.get("max_outliers", 0) + k
    return "false detections +%d" % k


def _round_up(q):
    f = float(q)
    while Fraction(f) < q:
        f = up(f)
    return f


def m_drift_exact(m, rng):
    """odometry2d with exact turn rates: heading_drift windows (and, half
    of the time, heading_error) set to the truth's exact largest residual,
    rounded up to a float: the truth on the constraint's boundary."""
    if m["model"] != "odometry2d":
        return None
    ch = m["inputs"]["turn_rate"]
    th = m["truth"].get("headings")
    if "value" not in ch or ch.get("error", 0) != 0 or not th or None in th:
        return None
    n = m["steps"]
    inc = [Fraction(m["dt"]) * Fraction(v) for v in ch["value"]]
    T = [Fraction(h) for h in th]
    prefix = [Fraction(0)]
    for x in inc:
        prefix.append(prefix[-1] + x)

    def worst(k):
        return max(abs(T[i + k] - T[i] - (prefix[i + k] - prefix[i])) for i in range(n - k + 1))

    ks = sorted({k for k in rng.sample([1, 2, 3, 5, 10, 20, 50, n], 3) if 1 <= k <= n})
    m["heading_drift"] = [{"steps": k, "error": _round_up(worst(k))} for k in ks]
    if rng.random() < 0.5 and n >= 1:
        m["heading_error"] = _round_up(worst(1))
    return "heading_drift exact %s" % ks


def m_motion_exact(m, rng):
    """odometry2d: motion_drift windows at the truth's largest k-step
    residual (a hair above, for this script's float sums), the truth near
    the constraint's boundary. The windows speak of the true speeds, which
    a simulated mission does not hold: the speed error moves into the
    per-step motion bound (|dt (v - v_measured)| per axis) and the speed
    becomes exact, so the measured speeds are the true ones of a truth
    that satisfies every constraint. Half of the time some steps get a
    three times wider motion bound and the windows exempt them."""
    if m["model"] != "odometry2d":
        return None
    t = m["truth"]
    th, pos = t.get("headings"), t["positions"]
    ch = m["inputs"]["speed"]
    if "value" not in ch or not th or None in th or None in pos:
        return None
    n, dt = m["steps"], m["dt"]
    es = ch.get("error", 0)
    es = es if isinstance(es, list) else [es] * n
    me = m.get("motion_error", 0)
    me = me if isinstance(me, list) else [me] * n
    me = [up(e + dt * x * (1 + 1e-12), 4) for e, x in zip(me, es)]
    ch["error"] = 0
    flagged = rng.random() < 0.5
    t_exempt = None
    if flagged:
        t_exempt = max(me)
        me = [up(3 * e, 2) if rng.random() < 0.1 else e for e in me]
    m["motion_error"] = me
    r = []
    for j in range(n):
        u = dt * ch["value"][j]
        r.append((pos[j + 1][0] - pos[j][0] - u * math.cos(th[j]),
                  pos[j + 1][1] - pos[j][1] - u * math.sin(th[j])))
    extent = max(abs(x) for p in pos for x in p) + 1.0

    def worst(k, exempt):
        sx, sy = [0.0], [0.0]
        for j in range(n):
            keep = not (exempt and me[j] > t_exempt)
            sx.append(sx[-1] + (r[j][0] if keep else 0.0))
            sy.append(sy[-1] + (r[j][1] if keep else 0.0))
        c = max(math.hypot(sx[i + k] - sx[i], sy[i + k] - sy[i]) for i in range(n - k + 1))
        return up(c * (1 + 1e-9) + 8 * (k + 2) * math.ulp(extent), 2)

    ks = sorted({k for k in rng.sample([1, 2, 3, 5, 10, 20, 50, n], 3) if 1 <= k <= n})
    windows = []
    for k in ks:
        exempt = flagged and rng.random() < 0.5
        w = {"steps": k, "error": worst(k, exempt)}
        if exempt:
            w["exempt_above"] = t_exempt
        windows.append(w)
    m["motion_drift"] = windows
    return "motion_drift exact %s%s" % (ks, " flagged" if flagged else "")


def m_mislabel(m, rng):
    """1-2 true detections given a wrong operator id, counted in
    max_outliers; their truth.matching set to null (a dropped detection's
    box need not hold its landmark), and every false detection labelled."""
    t = m["truth"]
    n = m.get("landmark_count") or len(t["landmarks"])
    idx = [i for i, j in enumerate(t["matching"]) if j is not None]
    if n < 2 or not idx:
        return None
    m["landmark_count"] = n
    k = min(len(idx), rng.choice([1, 2]))
    for i in rng.sample(idx, k):
        m["detections"][i]["landmark"] = (t["matching"][i] + 1 + rng.randrange(n - 1)) % n
        t["matching"][i] = None
    for i, j in enumerate(t["matching"]):
        if j is None and "landmark" not in m["detections"][i]:
            m["detections"][i]["landmark"] = rng.randrange(n)
    m["max_outliers"] = m.get("max_outliers", 0) + k
    return "mislabel %d" % k


def m_operator_partial(m, rng):
    t = m["truth"]
    for i, d in enumerate(m["detections"]):
        j = t["matching"][i]
        if j is not None and rng.random() < 0.3:
            d["landmark"] = j
        elif rng.random() < 0.5:
            d.pop("landmark", None)
    if "landmark_count" not in m:
        m["landmark_count"] = len(t["landmarks"])
    return "partial operator"


def m_motion_array(m, rng):
    n = m["steps"]
    e = m.get("motion_error", 0)
    base = e if not isinstance(e, list) else max(e)
    m["motion_error"] = [base * rng.choice([1, 2]) for _ in range(n)]
    return "motion_error array"


def m_sensor_offset(m, rng):
    """A new sensor offset (odometry2d, with true headings): ranges and
    bearings widened to hold the new truth."""
    if m["model"] != "odometry2d":
        return None
    t = m["truth"]
    off = [rng.choice([0.0, -0.3, 1.5]), rng.choice([0.0, 0.25, -2.0])]
    m["sensor_offset"] = off
    for i, d in enumerate(m["detections"]):
        j = t["matching"][i]
        p = t["positions"][d["step"]]
        th = t["headings"][d["step"]]
        if j is None or p is None or th is None:
            continue
        lm = t["landmarks"][j]
        c, s = math.cos(th), math.sin(th)
        sx = p[0] + c * off[0] - s * off[1]
        sy = p[1] + s * off[0] + c * off[1]
        r = math.hypot(lm[0] - sx, lm[1] - sy)
        lo, hi = ival(d["range"])
        d["range"] = mk(max(0.0, down(min(lo, r) - 1e-9 * (1 + r))), up(max(hi, r) + 1e-9 * (1 + r)))
        if "bearing" in d:
            b = math.atan2(lm[1] - sy, lm[0] - sx) - th
            blo, bhi = ival(d["bearing"])
            mid = (blo + bhi) / 2
            b += TWO_PI * round((mid - b) / TWO_PI)
            a = 1e-7 / max(r, 1e-9)
            d["bearing"] = mk(down(min(blo, b) - a), up(max(bhi, b) + a))
    return "sensor_offset %s" % off


MUTATIONS = [
    m_identity, m_widen, m_inf, m_huge, m_zero, m_shift, m_scale, m_heading_wrap,
    m_bearing_wrap, m_more_landmarks, m_min_sep, m_null_truth, m_shuffle, m_duplicate,
    m_scans, m_no_scans, m_more_outliers, m_operator_partial, m_motion_array, m_sensor_offset,
    m_false, m_drift_exact, m_mislabel, m_motion_exact,
]


# ---------------------------------------------------------------- checks


def check_result(m, r):
    """Independent checks of a result against the mission's truth."""
    errs = []
    t = m.get("truth") or {}
    if r.get("status") == "infeasible":
        errs.append("status infeasible: %s" % r.get("reason"))
        return errs
    sc = r.get("score") or {}
    if sc.get("truth_inside") is not True:
        errs.append("score.truth_inside %r" % sc.get("truth_inside"))
    if sc.get("matching_errors") != 0:
        errs.append("score.matching_errors %r" % sc.get("matching_errors"))
    for i, p in enumerate(t.get("positions", [])):
        if p is not None and not box_contains(r["trajectory"][i], p):
            errs.append("position %d %r outside %r" % (i, p, r["trajectory"][i]))
            break
    if "headings" in r:
        for i, h in enumerate(t.get("headings") or []):
            if h is not None and not contains(ival(r["headings"][i]), h):
                errs.append("heading %d %r outside %r" % (i, h, r["headings"][i]))
                break
    tm = t.get("matching", [])
    lms = t.get("landmarks", [])
    for i, j in enumerate(tm):
        if j is not None and not box_contains(r["detections"][i], lms[j]):
            errs.append("detection %d landmark %d %r outside %r" % (i, j, lms[j], r["detections"][i]))
            break
    for g, grp in enumerate(r.get("matching", [])):
        ids = {tm[i] for i in grp}
        if len(ids) != 1 or None in ids:
            errs.append("group %d %r spans true landmarks %r" % (g, grp, sorted(ids, key=str)))
            continue
        j = ids.pop()
        if not box_contains(r["landmarks"][g], lms[j]):
            errs.append("group %d landmark box misses landmark %d" % (g, j))
        regs = r.get("landmark_regions")
        if regs is not None and not any(box_contains(b, lms[j]) for b in regs[g]):
            errs.append("group %d landmark region misses landmark %d" % (g, j))
    return errs


def check_tdoa(m, r):
    errs = []
    t = m.get("truth") or {}
    if r.get("status") == "infeasible":
        return ["status infeasible: %s" % r.get("reason")]
    sc = r.get("score") or {}
    if sc.get("truth_inside") is not True or sc.get("matching_errors") != 0:
        errs.append("score %r" % sc)
    tm = t.get("matching", [])
    for k, p in enumerate(t.get("positions", [])):
        if p is not None and not box_contains(r["pulses"][k], p):
            errs.append("pulse %d %r outside %r" % (k, p, r["pulses"][k]))
            break
    for g, grp in enumerate(r.get("matching", [])):
        ids = {tm[i] for i in grp}
        if len(ids) != 1 or None in ids:
            errs.append("group %d spans emitters %r" % (g, ids))
    return errs


# ---------------------------------------------------------------- running


class Campaign:
    def __init__(self, binary, out, timeout):
        self.binary = binary
        self.out = out
        self.timeout = timeout
        self.lock = threading.Lock()
        self.counts = {}
        self.failures = 0
        os.makedirs(out, exist_ok=True)
        self.cases = open(os.path.join(out, "cases.jsonl"), "a")
        self.fails = open(os.path.join(out, "failures.jsonl"), "a")

    def run_one(self, label, mutation, m, contractor, sub="run"):
        tag = "%s|%s|%s" % (label, mutation, contractor)
        path = os.path.join(self.out, "m-%d-%d.json" % (os.getpid(), threading.get_ident()))
        with open(path, "w") as f:
            json.dump(m, f)
        cmd = [self.binary, sub, path, "--contractor", contractor]
        errs = []
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=self.timeout)
            if p.returncode != 0:
                errs.append("exit %d: %s" % (p.returncode, p.stderr.strip()[-400:]))
            else:
                r = json.loads(p.stdout)
                errs = (check_tdoa if sub == "tdoa" else check_result)(m, r)
        except subprocess.TimeoutExpired:
            errs.append("timeout %ss" % self.timeout)
        with self.lock:
            key = (label.split()[0], mutation.split()[0], contractor)
            self.counts[key] = self.counts.get(key, 0) + 1
            self.cases.write(json.dumps({"case": tag, "ok": not errs}) + "\n")
            self.cases.flush()
            if errs:
                self.failures += 1
                fpath = os.path.join(self.out, "fail-%d.json" % self.failures)
                with open(fpath, "w") as f:
                    json.dump(m, f)
                self.fails.write(json.dumps({"case": tag, "errors": errs, "mission": fpath}) + "\n")
                self.fails.flush()
                print("FAIL", tag, errs[:2], fpath, flush=True)
        os.unlink(path)
        return errs


def mission_jobs(binary, seed, only, mutations_per_mission, rng):
    jobs = []
    for label, base in base_missions(binary, seed, only):
        muts = [m_identity] + rng.sample(MUTATIONS[1:], mutations_per_mission)
        for mut in muts:
            m = copy.deepcopy(base)
            r2 = random.Random(rng.random())
            desc = mut(m, r2)
            if desc is None:
                continue
            # sometimes stack a second mutation
            if mut is not m_identity and r2.random() < 0.3:
                mut2 = r2.choice(MUTATIONS[1:])
                d2 = mut2(m, r2)
                if d2:
                    desc += " + " + d2
            for c in CONTRACTORS:
                jobs.append((label, desc, m, c))
    return jobs


def radar_mutations(base, rng):
    """TDOA mutations that keep the truth: pulses shuffled, every time
    shifted by T (emission times are free; widened by a few ulps), arrivals
    dropped, pulses duplicated, huge or point regions, altitude at the
    truth."""
    out = []
    t = base["truth"]
    m = copy.deepcopy(base)
    perm = list(range(len(m["pulses"])))
    rng.shuffle(perm)
    m["pulses"] = [m["pulses"][i] for i in perm]
    for key in ("positions", "matching"):
        if key in m["truth"]:
            m["truth"][key] = [t[key][i] for i in perm]
    out.append(("shuffle pulses", m))
    m = copy.deepcopy(base)
    shift = rng.choice([1.0, 1e3, -1e4])
    w = 4 * math.ulp(abs(shift) + 1)
    for pl in m["pulses"]:
        for a in pl["arrivals"]:
            lo, hi = ival(a["time"])
            a["time"] = mk(down(lo + shift - w), up(hi + shift + w))
    out.append(("time shift %g" % shift, m))
    m = copy.deepcopy(base)
    for pl in m["pulses"]:
        if len(pl["arrivals"]) > 3 and rng.random() < 0.5:
            del pl["arrivals"][rng.randrange(len(pl["arrivals"]))]
    out.append(("drop arrivals", m))
    m = copy.deepcopy(base)
    m["emitter_region"] = [[-1e300, 1e300]] * 3
    for k, pl in enumerate(m["pulses"]):
        if rng.random() < 0.3 and t["positions"][k] is not None:
            z = t["positions"][k][2]
            pl["altitude"] = [z, z]
    out.append(("huge region, point altitudes", m))
    m = copy.deepcopy(base)
    false_pulses = {fa[0] for fa in base.get("meta", {}).get("false_arrivals", [])}
    extra = [i for i in range(len(m["pulses"])) if t["matching"][i] is not None and i not in false_pulses][:5]
    for i in extra:
        m["pulses"].append(copy.deepcopy(m["pulses"][i]))
        m["truth"]["positions"].append(t["positions"][i])
        m["truth"]["matching"].append(t["matching"][i])
    out.append(("duplicate pulses", m))
    return out


def radar_jobs(binary, seed, rng):
    jobs = []
    args = ["--seed", seed, "--pulses", rng.choice([40, 80, 150]), "--emitters", rng.choice([2, 4, 6])]
    if rng.random() < 0.4:
        args += ["--false-arrivals", rng.choice([1, 3])]
    base = simulate(binary, "radar", args)
    label = "radar " + " ".join(map(str, args))
    variants = [("identity", base)]
    m = copy.deepcopy(base)
    m["emitter_region"] = [["-inf", "inf"]] * 3
    variants.append(("inf region", m))
    m = copy.deepcopy(base)
    if "emitter_count" in m:
        m["emitter_count"] += 3
        variants.append(("emitter_count +3", m))
    m = copy.deepcopy(base)
    m["max_outliers"] = m.get("max_outliers", 0) + 2
    variants.append(("max_outliers +2", m))
    variants += radar_mutations(base, rng)
    for desc, mm in variants:
        for c in CONTRACTORS:
            jobs.append((label, desc, mm, c, "tdoa"))
    return jobs


def parse_seeds(s):
    if "-" in s:
        a, b = s.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(x) for x in s.split(",")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="target/release/nvector")
    ap.add_argument("--out", default="/tmp/nvector-campaign")
    ap.add_argument("--seeds", default="1-5")
    ap.add_argument("--only", default=None)
    ap.add_argument("--mutations", type=int, default=6)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=120)
    a = ap.parse_args()
    camp = Campaign(a.bin, a.out, a.timeout)
    for seed in parse_seeds(a.seeds):
        rng = random.Random(seed)
        if a.only == "radar":
            jobs = radar_jobs(a.bin, seed, rng)
        else:
            jobs = mission_jobs(a.bin, seed, a.only, a.mutations, rng)
            if a.only is None:
                jobs += radar_jobs(a.bin, seed, rng)
        with ThreadPoolExecutor(a.jobs) as ex:
            list(ex.map(lambda j: camp.run_one(*j), jobs))
        print("seed %d done: %d runs so far, %d failures" % (seed, sum(camp.counts.values()), camp.failures), flush=True)
    with open(os.path.join(a.out, "counts.json"), "w") as f:
        json.dump({"|".join(k): v for k, v in sorted(camp.counts.items())}, f, indent=1)
    print("total runs %d, failures %d" % (sum(camp.counts.values()), camp.failures))
    return 1 if camp.failures else 0


if __name__ == "__main__":
    sys.exit(main())
