#!/usr/bin/env python3
"""The headings a scan's tight landmarks leave possible at one step
(a diagnosis of the hidden-ids woods runs).

    python3 scripts/research/woods_pose_span.py MISSION.json RESULT.json STEP [STEP ...]

For each STEP: the detections of that step whose group (in the result's
`matching`) has a landmark box narrower than 0.6 m are the anchors. A
heading th of the result's heading interval is kept when some position p
of the result's position box has every anchor's landmark box reachable:
some point of the box lies at a range and a bearing (seen from the sensor
point p + R(th) o) within the detection's intervals. The grid: 61
headings, 31 x 31 positions, 5 x 5 points per landmark box.

The span printed is that of the kept headings: an inner estimate (a grid
point kept is a true pose for these boxes; the boxes themselves are the
result's, which enclose the landmarks). It says how narrow any reasoning
that reads only this scan and these boxes can make the heading; compared
with the result's heading width, it says what the scan-pose contractor
leaves on the table. Floats, not outward-rounded: a diagnosis, not a
proof. Reads only the JSON files; pure Python (about 10 s per step).
"""
import json
import math
import sys

TIGHT = 0.6
HEADINGS = 61
GRID = 31
BOX_POINTS = 5


def lin(lo, hi, n):
    if n == 1:
        return [0.5 * (lo + hi)]
    return [lo + (hi - lo) * k / (n - 1) for k in range(n)]


def group_boxes(result):
    boxes = {}
    det = result["detections"]
    for members in result.get("matching", []):
        x0 = max(det[j][0][0] for j in members)
        x1 = min(det[j][0][1] for j in members)
        y0 = max(det[j][1][0] for j in members)
        y1 = min(det[j][1][1] for j in members)
        for j in members:
            boxes[j] = (x0, x1, y0, y1)
    return boxes


def reachable(px, py, th, offset, det, box):
    """Whether some point of `box` is seen within det's range and bearing."""
    sx = px + offset[0] * math.cos(th) - offset[1] * math.sin(th)
    sy = py + offset[0] * math.sin(th) + offset[1] * math.cos(th)
    r_lo, r_hi = det["range"]
    b_lo, b_hi = det["bearing"]
    for lx in lin(box[0], box[1], BOX_POINTS):
        for ly in lin(box[2], box[3], BOX_POINTS):
            vx, vy = lx - sx, ly - sy
            r = math.hypot(vx, vy)
            if r < r_lo or r > r_hi:
                continue
            ang = (math.atan2(vy, vx) - th - b_lo) % (2 * math.pi)
            if ang <= b_hi - b_lo:
                return True
    return False


def span(mission, result, step):
    dets = mission["detections"]
    offset = mission.get("sensor_offset") or [0.0, 0.0]
    boxes = group_boxes(result)
    anchors = [
        j
        for j, d in enumerate(dets)
        if d["step"] == step
        and d.get("bearing") is not None
        and j in boxes
        and max(boxes[j][1] - boxes[j][0], boxes[j][3] - boxes[j][2]) < TIGHT
    ]
    pos = result["trajectory"][step]
    head = result["headings"][step]
    kept = []
    poses = []
    for th in lin(head[0], head[1], HEADINGS):
        for px in lin(pos[0][0], pos[0][1], GRID):
            for py in lin(pos[1][0], pos[1][1], GRID):
                if all(reachable(px, py, th, offset, dets[j], boxes[j]) for j in anchors):
                    poses.append((px, py, th))
        if poses and poses[-1][2] == th:
            kept.append(th)
    return anchors, head, kept, poses


def landmark_points(det, offset, poses):
    """Points where det's landmark may be from the kept poses (the range
    and bearing intervals' ends and middles)."""
    pts = []
    for px, py, th in poses:
        for r in lin(det["range"][0], det["range"][1], 3):
            for b in lin(det["bearing"][0], det["bearing"][1], 3):
                x = offset[0] + r * math.cos(b)
                y = offset[1] + r * math.sin(b)
                pts.append((px + x * math.cos(th) - y * math.sin(th), py + x * math.sin(th) + y * math.cos(th)))
    return pts


def box_far(box, pt):
    """The distance from pt to the farthest point of box."""
    dx = max(abs(pt[0] - box[0]), abs(pt[0] - box[1]))
    dy = max(abs(pt[1] - box[2]), abs(pt[1] - box[3]))
    return math.hypot(dx, dy)


def box_near(box, pt):
    """The distance from pt to the nearest point of box."""
    dx = max(box[0] - pt[0], 0.0, pt[0] - box[1])
    dy = max(box[2] - pt[1], 0.0, pt[1] - box[3])
    return math.hypot(dx, dy)


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    mission = json.load(open(sys.argv[1]))
    result = json.load(open(sys.argv[2]))
    truth = mission.get("truth", {})
    for step in map(int, sys.argv[3:]):
        anchors, head, kept, poses = span(mission, result, step)
        ranges = ", ".join(f"{mission['detections'][j]['range'][0]:.2f}" for j in anchors)
        line = f"step {step}: {len(anchors)} anchors (ranges {ranges} m); heading box {head[1] - head[0]:.3f} rad"
        if kept:
            line += f", headings kept span {max(kept) - min(kept):.3f} rad"
        else:
            line += ", no heading kept (the grid is too coarse)"
        if truth.get("headings") and truth["headings"][step] is not None:
            line += f" (truth {truth['headings'][step]:.4f})"
        print(line)
        labels = truth.get("matching")
        offset = mission.get("sensor_offset") or [0.0, 0.0]
        tight = group_boxes(result)
        sep = mission.get("landmark_min_separation", 0.0)
        for j, d in enumerate(mission["detections"]):
            if d["step"] != step or j in anchors or d.get("bearing") is None or not poses:
                continue
            pts = landmark_points(d, offset, poses)
            diam = max(math.hypot(a[0] - b[0], a[1] - b[1]) for a in pts[:: max(1, len(pts) // 400)] for b in pts[:: max(1, len(pts) // 400)])
            out = f"  detection {j} at {d['range'][0]:.2f} m: landmark points span {diam:.2f} m"
            if labels and labels[j] is not None:
                # The tightest earlier group of the same true landmark.
                olds = [
                    k for k in tight
                    if labels[k] == labels[j] and mission["detections"][k]["step"] < step
                    and max(tight[k][1] - tight[k][0], tight[k][3] - tight[k][2]) < TIGHT
                ]
                if olds:
                    box = tight[olds[0]]
                    near = max(box_near(box, p) for p in pts)
                    far = max(box_far(box, p) for p in pts)
                    out += (
                        f"; from its landmark's earlier box (label {labels[j]}): every point within {near:.2f} m"
                        f" of some point of it, within {far:.2f} m of all of it (s = {sep:.2f})"
                    )
            print(out)


if __name__ == "__main__":
    main()
