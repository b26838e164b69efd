#!/usr/bin/env python3
"""How far the closed world's clique rule could go on a hidden-ids woods
result, granted an oracle for distinct pairs (a diagnosis of the hidden-ids
woods runs).

    python3 scripts/research/woods_closure_ceiling.py MISSION.json RESULT.json WINDOW [LAST_STEP]

The groups are the result's `matching` (cut to the detections at steps
<= LAST_STEP; groups of one detection left out). Two groups of different
true landmarks (the mission's `truth.matching`) count as proved distinct
when they share a scan, when their landmark boxes (the intersection of
their members' boxes) are disjoint, or, the oracle, when a member of one
is at most WINDOW steps from a member of the other: a stand-in for any
relative evidence, however strong, over that many steps (what the
odometry proves is far less: docs/journal/benchmarks-2026-11.md, "groups compared in a local
frame"). Groups of one true landmark are never distinct.

Then the rule of `Distinct::infer` (core/src/shapes/distinct.rs) runs to
its fixpoint with n = `landmark_count`: for every (n-1)-clique of the
graph of groups, its common neighbours are one landmark and merge (the
maximal cliques are listed by Bron-Kerbosch with pivoting, at most
200,000 per pass). Prints the merges per pass and, at the end, the
detections in the largest group of each true landmark (all of them: the
world closed everywhere). Every merge is checked against the truth.
Reads only the JSON files; pure Python.
"""
import bisect
import json
import sys
from itertools import combinations

MAX_CLIQUES = 200_000


def groups_of(mission, result, last):
    dets = mission["detections"]
    labels = mission["truth"]["matching"]
    boxes = result["detections"]
    out = []
    for members in result.get("matching", []):
        members = [j for j in members if dets[j]["step"] <= last]
        if len(members) < 2:
            continue
        out.append(
            {
                "label": labels[members[0]],
                "steps": sorted({dets[j]["step"] for j in members}),
                "scans": {dets[j].get("scan") for j in members} - {None},
                "box": (
                    max(boxes[j][0][0] for j in members),
                    min(boxes[j][0][1] for j in members),
                    max(boxes[j][1][0] for j in members),
                    min(boxes[j][1][1] for j in members),
                ),
                "size": len(members),
            }
        )
    return out


def near(a, b, window):
    steps = b["steps"]
    for s in a["steps"]:
        i = bisect.bisect_left(steps, s - window)
        if i < len(steps) and steps[i] <= s + window:
            return True
    return False


def disjoint(a, b):
    p, q = a["box"], b["box"]
    return p[1] < q[0] or q[1] < p[0] or p[3] < q[2] or q[3] < p[2]


def maximal_cliques(adj, budget):
    """Bron-Kerbosch with pivoting; stops after `budget` cliques."""
    found = []

    def expand(r, p, x):
        if len(found) >= budget:
            return
        if not p and not x:
            found.append(r)
            return
        pivot = max(p | x, key=lambda u: len(adj[u] & p))
        for v in list(p - adj[pivot]):
            expand(r + [v], p & adj[v], x & adj[v])
            p = p - {v}
            x = x | {v}

    expand([], set(adj), set())
    return found


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    mission = json.load(open(sys.argv[1]))
    result = json.load(open(sys.argv[2]))
    window = int(sys.argv[3])
    last = int(sys.argv[4]) if len(sys.argv) > 4 else 10**12
    n = mission["landmark_count"]
    groups = groups_of(mission, result, last)
    count = len(groups)
    pair = [set() for _ in range(count)]
    for i in range(count):
        for j in range(i + 1, count):
            a, b = groups[i], groups[j]
            if a["label"] == b["label"]:
                continue
            if a["scans"] & b["scans"] or disjoint(a, b) or near(a, b, window):
                pair[i].add(j)
                pair[j].add(i)
    parent = list(range(count))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    print(f"{count} groups, {sum(len(p) for p in pair) // 2} distinct pairs (window {window} steps)")
    for rnd in range(64):
        adj = {}
        for i in range(count):
            adj.setdefault(find(i), set()).update(find(j) for j in pair[i])
        for r in adj:
            adj[r].discard(r)
        merged = 0
        for clique in maximal_cliques(adj, MAX_CLIQUES):
            if len(clique) < n - 1:
                continue
            for sub in combinations(clique, n - 1):
                common = set.intersection(*(adj[x] for x in sub))
                common = sorted({find(x) for x in common})
                if len(common) < 2:
                    continue
                assert len({groups[x]["label"] for x in common}) == 1, "a merge across landmarks"
                for x in common[1:]:
                    if find(x) != find(common[0]):
                        parent[find(x)] = find(common[0])
                        merged += 1
        roots = len({find(i) for i in range(count)})
        print(f"pass {rnd}: {merged} merges, {roots} groups left")
        if merged == 0:
            break
    size = {}
    for i in range(count):
        size[find(i)] = size.get(find(i), 0) + groups[i]["size"]
    best = {}
    for root, k in size.items():
        label = groups[root]["label"]
        best[label] = max(best.get(label, 0), k)
    total = sum(g["size"] for g in groups)
    print(f"detections in the largest group of each landmark: {sum(best.values())} of {total}")


if __name__ == "__main__":
    main()
