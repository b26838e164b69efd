"""Figures of SLAM results with matplotlib (imported only when drawing).

The same picture as ``nvector plot`` and the service's SVG (the paper's
Figure 9): trajectory boxes in blue, detection boxes coloured by proved
group (grey when in none), landmark boxes in red, and the truth (path and
landmarks) in black, on the first two axes, y up.
"""

from __future__ import annotations

import json
import os
from typing import Any, Union

PathLike = Union[str, "os.PathLike[str]"]

#: Colours of matching groups, as the CLI's figures.
PALETTE = ("#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#9a6324")
TRAJECTORY = "#4a90d9"
UNGROUPED = "#888888"
LANDMARK_EDGE = "#b00000"
LANDMARK_FILL = (200 / 255, 0.0, 0.0, 0.25)


def _read(obj: Any) -> Any:
    if isinstance(obj, (str, os.PathLike)):
        with open(os.fspath(obj), encoding="utf-8") as f:
            return json.load(f)
    return obj


def _rect(box: Any) -> tuple[float, float, float, float] | None:
    """(x0, y0, x1, y1) of a box's first two axes, when bounded."""
    if not isinstance(box, (list, tuple)) or len(box) < 2:
        return None
    try:
        x0, x1 = float(box[0][0]), float(box[0][1])
        y0, y1 = float(box[1][0]), float(box[1][1])
    except (TypeError, ValueError, IndexError):
        return None
    bounds = (x0, x1, y0, y1)
    if any(b != b or b in (float("inf"), float("-inf")) for b in bounds):
        return None
    return x0, y0, x1, y1


def plot(
    result: dict[str, Any] | PathLike,
    mission: dict[str, Any] | PathLike | None = None,
    ax: Any = None,
    max_boxes: int = 1500,
) -> Any:
    """Draws a result (``nvector-result/1`` dict or file) on ``ax`` (a new
    figure's axes when None) and returns the axes.

    ``mission`` (dict or file), when given, adds the truth it holds. At most
    ``max_boxes`` trajectory boxes are drawn (every k-th and the last), as
    the CLI does. Needs matplotlib (``pip install matplotlib``).
    """
    try:
        import matplotlib.pyplot as plt
        from matplotlib.collections import PatchCollection
        from matplotlib.patches import Rectangle
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("nvector.plot needs matplotlib: pip install matplotlib") from e

    res: dict[str, Any] = _read(result)
    mis: dict[str, Any] = _read(mission) if mission is not None else {}
    if ax is None:
        _, ax = plt.subplots(figsize=(9, 6))

    def patches(rects: list[tuple[float, float, float, float]], **style: Any) -> None:
        if rects:
            shapes = [Rectangle((x0, y0), x1 - x0, y1 - y0) for x0, y0, x1, y1 in rects]
            ax.add_collection(PatchCollection(shapes, **style))

    trajectory = list(res.get("trajectory") or [])
    stride = max(1, -(-len(trajectory) // max(1, max_boxes)))
    drawn = trajectory[::stride] + trajectory[-1:]
    patches([r for r in map(_rect, drawn) if r], facecolor="none", edgecolor=TRAJECTORY, linewidth=0.6, label="trajectory")

    detections = list(res.get("detections") or [])
    group_of = [-1] * len(detections)
    for g, members in enumerate(res.get("matching") or []):
        for m in members:
            if isinstance(m, int) and 0 <= m < len(group_of):
                group_of[m] = g
    by_colour: dict[str, list[tuple[float, float, float, float]]] = {}
    for box, g in zip(detections, group_of):
        r = _rect(box)
        if r:
            by_colour.setdefault(UNGROUPED if g < 0 else PALETTE[g % len(PALETTE)], []).append(r)
    for colour, rects in by_colour.items():
        patches(rects, facecolor="none", edgecolor=colour, linewidth=0.8)

    landmarks = [r for r in map(_rect, res.get("landmarks") or []) if r]
    patches(landmarks, facecolor=LANDMARK_FILL, edgecolor=LANDMARK_EDGE, linewidth=0.8)

    truth = mis.get("truth") or {}
    path = [p for p in truth.get("positions") or [] if len(p) >= 2]
    if path:
        step = max(1, len(path) // 5000)
        xs = [float(p[0]) for p in path[::step]]
        ys = [float(p[1]) for p in path[::step]]
        ax.plot(xs, ys, color="black", linewidth=0.8, label="truth")
    marks = [p for p in truth.get("landmarks") or [] if len(p) >= 2]
    if marks:
        ax.scatter([float(p[0]) for p in marks], [float(p[1]) for p in marks], s=12, color="black", zorder=3)

    ax.autoscale_view()
    ax.set_aspect("equal", adjustable="datalim")
    diameter = (res.get("metrics") or {}).get("max_trajectory_diameter")
    shown = f"{diameter:.4g}" if isinstance(diameter, (int, float)) else str(diameter)
    contractor = (res.get("options") or {}).get("contractor", "")
    ax.set_title(f"{res.get('mission', '')} — {contractor} — max trajectory diameter {shown}")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    return ax
