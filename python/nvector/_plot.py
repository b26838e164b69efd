"""Figures of SLAM results with matplotlib (imported only when drawing).

The same picture as ``nvector plot`` and ``nvector run --plot``: both draw
the one description of the picture that the compiled core computes
(``nvector._nvector.figure``, Rust ``nvector_core::figure``): the
trajectory's boxes translucent (their envelope past 400 boxes), the
tightest proved groups outlined with their landmark regions, the
headings of an ``odometry2d`` result as wedges (every k-th step; a circle
where the heading is 2 pi wide or more), the truth (path, heading ticks
and landmarks) on top; axes in metres at one scale, the diameters in
metres in the title, and a legend beside the axes, with the figure laid
out (matplotlib's constrained layout when it has no layout engine) so that
the legend, the labels and the title lie inside it. Each call fits the
axes to its own result, so panels side by side each show their result at
its own scale.
"""

from __future__ import annotations

import json
import os
import textwrap
from typing import Any, Union

from . import _nvector
from ._errors import InputError, read_with_file

PathLike = Union[str, "os.PathLike[str]"]

#: Largest magnitude of a drawn bound (as the CLI's figures).
LIMIT = 1e300


def _read(obj: Any) -> Any:
    if isinstance(obj, (str, os.PathLike)):
        with open(os.fspath(obj), encoding="utf-8") as f:
            return json.load(f)
    return obj


def read_result(result: dict[str, Any] | PathLike) -> dict[str, Any]:
    """A result (``nvector-result/1``: a dict, or the path of a file) read
    through the compiled core's types, as ``nvector plot`` reads it: the
    result as a dict, as written (bounds ``"inf"`` / ``"-inf"``, empty
    boxes ``"empty"``). Raises :class:`InputError` naming the JSON path of
    the first fault (unknown or missing field, bad interval, a box of
    another dimension, a group naming no detection, ...) and the file, for
    a path."""
    out: dict[str, Any] = read_with_file(_nvector.read_result, result)
    return out


def figure(result: dict[str, Any] | PathLike, mission: dict[str, Any] | PathLike | None = None) -> dict[str, Any]:
    """The description of a result's picture (a dict), as the CLI draws it:
    ``title``, ``subtitle``, ``x_label``, ``y_label``, ``view`` ([x0, x1,
    y0, y1] in metres) and ``layers``, bottom first, each with ``name``,
    ``label`` (the legend's text), ``kind`` (``rects``, ``path``,
    ``points`` or ``polygons``), ``colour``, ``fill_alpha``, ``line_width``
    (pixels), ``rects`` ([x0, x1, y0, y1]), ``points`` ([x, y]) and
    ``polygons`` (lists of [x, y]; closed; two points make a segment)."""
    res = read_result(result)
    mis = _read(mission) if mission is not None else None
    out: dict[str, Any] = json.loads(_nvector.figure(res, mis))
    return out


def plot(
    result: dict[str, Any] | PathLike,
    mission: dict[str, Any] | PathLike | None = None,
    ax: Any = None,
    legend: bool = True,
) -> Any:
    """Draws a result (``nvector-result/1`` dict or file) on ``ax`` (a new
    figure's axes when None) and returns the axes.

    ``mission`` (dict or file), when given, adds the truth it holds. The
    axes are fitted to this result (x and y in metres, one scale), titled
    with the diameters in metres, and get a legend (``legend=False``: none)
    to the right of the axes. A figure without a layout engine gets
    matplotlib's constrained layout, which makes room for the legend and
    the labels (without it, a legend beside the axes is cut at the figure's
    edge or drawn over the next panel). Needs matplotlib (``pip install
    matplotlib``).
    """
    try:
        import matplotlib.pyplot as plt
        from matplotlib.collections import PatchCollection
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch, Polygon, Rectangle
        from matplotlib.transforms import Bbox
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("nvector.plot needs matplotlib: pip install matplotlib") from e

    fig_desc = figure(result, mission)
    if ax is None:
        _, ax = plt.subplots(figsize=(11, 7), layout="constrained")

    # The view within +-1e300 and every coordinate within one view's span
    # beyond it, as the CLI does: values near the float limits would
    # overflow matplotlib's transforms; what lies outside is clipped anyway.
    x0, x1, y0, y1 = (min(max(float(v), -LIMIT), LIMIT) for v in fig_desc["view"])
    sx, sy = x1 - x0, y1 - y0

    def cx(x: float) -> float:
        return min(max(x, x0 - sx), x1 + sx)

    def cy(y: float) -> float:
        return min(max(y, y0 - sy), y1 + sy)

    # Pixels of the CLI's figures to points (matplotlib's line unit).
    pt = 0.75
    handles: list[Any] = []
    for z, layer in enumerate(fig_desc["layers"]):
        # Long legend labels on several lines, as the CLI's legend.
        layer = {**layer, "label": textwrap.fill(layer["label"], 38)}
        colour = layer["colour"]
        alpha = float(layer["fill_alpha"])
        width = float(layer["line_width"]) * pt
        if layer["kind"] == "rects":
            shapes = [Rectangle((cx(a), cy(c)), cx(b) - cx(a), cy(d) - cy(c)) for a, b, c, d in layer["rects"]]
            face: Any = (*_rgb(colour), alpha) if alpha > 0 else "none"
            edge: Any = colour if width > 0 else "none"
            if width > 0 and width < pt:
                edge = (*_rgb(colour), 0.5)
            ax.add_collection(
                PatchCollection(shapes, facecolor=face, edgecolor=edge, linewidth=max(width, pt) if width > 0 else 0, zorder=1 + z, label=layer["label"])
            )
            handles.append(Patch(facecolor=face, edgecolor=edge, linewidth=max(width, pt) if width > 0 else 0, label=layer["label"]))
        elif layer["kind"] == "polygons":
            polys = [Polygon([(cx(p[0]), cy(p[1])) for p in poly], closed=len(poly) > 2) for poly in layer["polygons"]]
            face = (*_rgb(colour), alpha) if alpha > 0 else "none"
            edge = colour if width > 0 else "none"
            if width > 0 and width < pt:
                edge = (*_rgb(colour), 0.5)
            lw = max(width, pt) if width > 0 else 0
            ax.add_collection(PatchCollection(polys, facecolor=face, edgecolor=edge, linewidth=lw, zorder=1 + z, label=layer["label"]))
            if alpha > 0:
                handles.append(Patch(facecolor=face, edgecolor=edge, linewidth=lw, label=layer["label"]))
            else:
                handles.append(Line2D([], [], color=edge, linewidth=lw, label=layer["label"]))
        elif layer["kind"] == "path":
            xs = [cx(p[0]) for p in layer["points"]]
            ys = [cy(p[1]) for p in layer["points"]]
            (line,) = ax.plot(xs, ys, color=colour, linewidth=width, zorder=1 + z, label=layer["label"])
            handles.append(line)
        else:
            ax.scatter(
                [cx(p[0]) for p in layer["points"]],
                [cy(p[1]) for p in layer["points"]],
                s=30,
                color=colour,
                zorder=1 + z,
                label=layer["label"],
            )
            handles.append(Line2D([], [], color=colour, marker="o", linestyle="none", label=layer["label"]))

    # One scale on x and y, unless the view is too thin or too wide for it
    # (a figure of unbounded or huge values). The axes keep the box the
    # layout gives them, and the view widens on one axis to the box's shape
    # (adjustable data limits; the data limits are the view, without
    # margins). An axes shrunk to the view's shape instead moved away from
    # where the layout had made room for its labels and legend: the y
    # label and the legend were cut at the figure's edges.
    if sx > 0 and sy > 0 and 1e-3 < sy / sx < 1e3 and sx < 1e150 and sy < 1e150:
        ax.dataLim.set(Bbox([[x0, y0], [x1, y1]]))
        ax.set_aspect("equal", adjustable="datalim")
        ax.margins(0)
        ax.autoscale(True)
    else:
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
    # The subtitle on lines of at most 40 characters, broken after its
    # commas: an axes beside its legend can be narrower than one long line,
    # which then passed the figure's edge.
    ax.set_title("\n".join([fig_desc["title"], *_lines(fig_desc["subtitle"], 40)]), fontsize="medium")
    ax.set_xlabel(fig_desc["x_label"])
    ax.set_ylabel(fig_desc["y_label"])
    ax.grid(True, color="#ebebeb", linewidth=0.6, zorder=0)
    ax.set_axisbelow(True)
    if legend and handles:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, fontsize="small", frameon=False)
    # The legend beside the axes, the labels and the title inside the
    # figure: a layout engine makes room for them.
    if ax.figure.get_layout_engine() is None:
        ax.figure.set_layout_engine("constrained")
    return ax


def _lines(text: str, width: int) -> list[str]:
    """The text's comma-separated parts joined into lines of at most
    ``width`` characters where they fit (a longer part is a line of its
    own)."""
    lines: list[str] = []
    for part in text.split(", "):
        if lines and len(lines[-1]) + 2 + len(part) <= width:
            lines[-1] += ", " + part
        else:
            lines.append(part)
    return [f"{line}," for line in lines[:-1]] + lines[-1:]


def _rgb(hex_colour: str) -> tuple[float, float, float]:
    h = hex_colour.lstrip("#")
    return (int(h[0:2], 16) / 255, int(h[2:4], 16) / 255, int(h[4:6], 16) / 255)
