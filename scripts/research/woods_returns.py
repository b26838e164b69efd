#!/usr/bin/env python3
"""How many returns of a landmark a result joins, by the length of the
absence (a diagnosis of the hidden-ids woods runs).

    python3 scripts/research/woods_returns.py MISSION.json RESULT.json [RESULT2.json ...]

For each pair of consecutive sightings of one true landmark (the mission's
`truth.matching`; null entries skipped), the gap in steps and whether the
result's `matching` puts both detections in one group. Prints, per gap
range, joined / all. An operator-matched run joins every one; a
hidden-ids run joins what the solver proved. Reads only the JSON files.
"""
import json
import sys

BINS = [(2, 5), (5, 10), (10, 20), (20, 50), (50, 100), (100, 300), (300, 1000), (1000, 10**9)]


def returns(mission, result):
    dets = mission["detections"]
    truth = mission["truth"]["matching"]
    group = {}
    for g, members in enumerate(result.get("matching", [])):
        for d in members:
            group[d] = g
    sightings = {}
    for i, d in enumerate(dets):
        if truth[i] is not None:
            sightings.setdefault(truth[i], []).append((d["step"], i))
    counts = {b: [0, 0] for b in BINS}
    for seen in sightings.values():
        seen.sort()
        for (s0, a), (s1, b) in zip(seen, seen[1:]):
            for lo, hi in BINS:
                if lo <= s1 - s0 < hi:
                    counts[(lo, hi)][0] += 1
                    counts[(lo, hi)][1] += a in group and group.get(a) == group.get(b)
    return counts


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        mission = json.load(f)
    print("result | " + " | ".join(f"{lo}-{hi if hi < 10**9 else 'end'} steps" for lo, hi in BINS))
    for path in sys.argv[2:]:
        with open(path) as f:
            counts = returns(mission, json.load(f))
        cells = [f"{counts[b][1]}/{counts[b][0]}" for b in BINS]
        print(f"{path} | " + " | ".join(cells))


if __name__ == "__main__":
    main()
