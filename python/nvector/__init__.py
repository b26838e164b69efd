"""nvector: guaranteed (interval) SLAM with the nvector global constraint.

The compiled nvector core (the same Rust code as the ``nvector`` command and
the service, so the same bits), a client of an nvector service, and figures:

- :func:`contract`: one atmost_nvector contraction of boxes (numpy arrays);
- :func:`simulate`: a simulated mission with ground truth (a dict);
- :func:`run`: one SLAM job on a mission (dict or file) -> the result (a dict);
- :func:`check`: every constraint of a mission that its truth breaks;
- :func:`import_dataset`, :func:`import_csv`: a mission from a bundled data
  set's directory or from sensor log CSVs, as ``nvector import`` makes it;
- :class:`Client`: missions and jobs on a running ``nvector serve``;
- :func:`read_result`: a result (dict or file) read through the core's
  types of ``nvector-result/1``, each fault named by its JSON path;
- :func:`plot`: a result drawn with matplotlib, the picture of the CLI's
  figures (:func:`figure`: its description, shared with the CLI).

Missions and results are the JSON documents of the nvector formats
(``nvector-mission/1``, ``nvector-result/1``) as plain Python objects: a
bound is a number or the string ``"inf"`` / ``"-inf"``, an empty box the
string ``"empty"``. In input, ``float("inf")`` and numpy arrays are accepted
too. Bad input raises :class:`InputError` naming the JSON path of the bad
value.

Example::

    import nvector
    mission = nvector.simulate("paper", seed=3, steps=2000)
    result = nvector.run(mission)
    print(result["status"], result["matching"], result["score"])
    nvector.plot(result, mission)
"""

from __future__ import annotations

import os
from importlib.metadata import PackageNotFoundError, version
from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple, Sequence, Union

import numpy as np

from . import _nvector
from ._errors import InputError, JobError, ServiceError, read_with_file
from ._progress import ProgressBar
from ._client import Client
from ._plot import figure, plot, read_result

__all__ = [
    "contract",
    "simulate",
    "run",
    "check",
    "tdoa",
    "import_dataset",
    "import_csv",
    "load",
    "dumps",
    "boxes",
    "Client",
    "plot",
    "figure",
    "read_result",
    "ContractResult",
    "MinDistinct",
    "InputError",
    "ServiceError",
    "JobError",
    "MAX_STEPS",
]

try:
    __version__ = version("nvector-slam")
except PackageNotFoundError:  # imported from the source tree
    __version__ = "0+unknown"

#: Most steps of a mission.
MAX_STEPS: int = _nvector.MAX_STEPS

PathLike = Union[str, "os.PathLike[str]"]


class MinDistinct(NamedTuple):
    """Bounds on the minimum number of distinct vectors (hitting set size)."""

    lower: int
    """A proved lower bound."""
    upper: int
    """The size of a hitting set that was found."""


@dataclass(frozen=True)
class ContractResult:
    """The outcome of :func:`contract` (``nvector-contract-result/1``)."""

    status: str
    """``"contracted"``, ``"unchanged"`` or ``"infeasible"``."""
    boxes: np.ndarray
    """The contracted boxes, float64 of shape (k, d, 2): ``boxes[i, axis] =
    [lo, hi]``; every bound NaN for an empty box (status infeasible)."""
    groups: list[list[int]]
    """A partition of the box indices into groups proved to take one vector."""
    min_distinct: MinDistinct
    """Bounds on the minimum number of distinct vectors."""
    reason: str | None
    """Why the constraint is infeasible (status infeasible only)."""
    rounds: int
    """Rounds of the contractor's fixpoint."""
    json: dict[str, Any] = field(repr=False)
    """The response as ``nvector contract`` prints it (``stats.elapsed_us``
    measured here)."""

    @property
    def feasible(self) -> bool:
        """False when the constraint was proved infeasible."""
        return self.status != "infeasible"


def contract(boxes: Any, n: int, contractor: str = "best") -> ContractResult:
    """One atmost_nvector contraction: "the boxes hold at most n distinct vectors".

    ``boxes`` is k boxes of one dimension d: a float array of shape (k, d, 2)
    (numpy or nested lists; a bound may also be ``"inf"``/``"-inf"``, and a
    bare number x the interval [x, x]). ``contractor``: ``"nvalue"`` (the
    paper's naive contractor), ``"projection"`` (the paper's improved one),
    ``"independent"`` (pairwise disjoint boxes as witnesses), ``"exact"``
    (bound consistency, k <= 40) or ``"best"``, as in ``nvector contract``. Every vector tuple that satisfies the constraint
    stays inside the returned boxes (soundness); the answer is the one of
    ``nvector contract`` bit for bit.

    Raises :class:`InputError` (naming the JSON path, e.g. ``boxes[3][1]``)
    for invalid input, such as a lower bound above an upper bound, NaN or
    boxes of different dimensions.
    """
    request = {
        "format": "nvector-contract/1",
        "n": n,
        "boxes": boxes,
        "contractor": contractor,
    }
    response, raw, dim = _nvector.contract(request)
    k = len(response["boxes"])
    array = np.frombuffer(raw, dtype="<f8").reshape(k, dim, 2).astype(np.float64)
    return ContractResult(
        status=response["status"],
        boxes=array,
        groups=response["groups"],
        min_distinct=MinDistinct(
            response["min_distinct"]["lower"], response["min_distinct"]["upper"]
        ),
        reason=response.get("reason"),
        rounds=response["stats"]["rounds"],
        json=response,
    )


def simulate(
    scenario: str,
    seed: int = 1,
    steps: int | None = None,
    landmarks: int | None = None,
    operator: bool = False,
    noise: float = 1.0,
    layout: str = "line",
    range_only: bool = False,
    false_detections: int = 0,
) -> dict[str, Any]:
    """A simulated mission with ground truth (``nvector-mission/1``), as a dict.

    ``scenario``: ``"paper"`` (the paper's section 6 experiment: a robot
    looping around its start, side-scan sonar detections of ``landmarks``
    landmarks, default 4, at most 64), ``"auv"`` (a Redermor-scale 3-D
    survey) or ``"woods"`` (an ``odometry2d`` robot, its heading integrated
    from a turn rate, among ``landmarks`` identical landmarks, default 17,
    seen by range-and-bearing scans: ``scan`` on the detections,
    ``sensor_offset``, ``landmark_min_separation``, ``truth["headings"]``;
    default 3000 steps; ``layout``, ``range_only`` and ``noise`` must keep
    their defaults). ``steps`` defaults to 10,000 (paper) or 60,000 (auv), at most
    2,000,000 (below 2 reads as 2; ``landmarks`` 0 reads as 1); ``noise``,
    in [0, 100], scales
    the sensor error bounds; ``operator`` writes the true matching as
    operator ``landmark`` fields. Paper only: ``layout`` puts the landmarks
    on a ``"line"`` (10 m apart along x, the paper's Figure 9), a ``"ring"``
    around the start (the axis projections interleave) or at ``"random"``;
    ``range_only`` drops the bearings for a rough region per detection (the
    paper's P''). Paper and woods: ``false_detections`` adds false
    detections (``None`` in ``truth["matching"]``, ``max_outliers`` set; at
    most 100,000): ranges to no landmark (paper), or range-and-bearing
    detections in the robot's scans of phantom points at least
    ``landmark_min_separation`` + 0.5 m from every landmark, seen once, two
    or three times from nearby scans, or with ``operator`` under a real
    landmark's label (woods; the points in ``meta["false_points"]``).

    Deterministic for a seed: equal to ``nvector simulate --scenario S
    --seed N ...`` with the same options. Bad options raise
    :class:`InputError` naming the option.
    """
    return _nvector.simulate(
        scenario, seed, steps, landmarks, operator, noise, layout, range_only, false_detections
    )


def dumps(obj: Any) -> str:
    """Python objects as compact JSON text, written as the ``nvector`` binary
    writes JSON (shortest round-trip floats; ``float("inf")`` as ``"inf"``).
    NaN raises :class:`InputError` naming its path."""
    return _nvector.dumps(obj)


def load(path: PathLike) -> Any:
    """Reads a JSON file (a mission or a result) into Python objects."""
    import json

    with open(os.fspath(path), encoding="utf-8") as f:
        return json.load(f)


def run(
    mission: dict[str, Any] | PathLike,
    contractor: str | None = None,
    max_rounds: int = 10_000,
    tolerance: float = 1e-9,
    progress: bool | Callable[[int, float, float], Any] = False,
) -> dict[str, Any]:
    """One SLAM job: the guaranteed boxes of a mission (``nvector-result/1``).

    ``mission`` is a mission dict or the path of a mission file.
    ``contractor``: ``"none"`` (the basic model: only operator matchings tie
    detections), ``"nvalue"``, ``"projection"``, ``"independent"`` or
    ``"best"``, as ``nvector run --contractor``; None (the default) does what ``nvector run`` does: ``"best"`` when the mission has a
    ``landmark_count``, ``"none"`` otherwise. ``max_rounds`` and
    ``tolerance`` are the CLI's ``--max-rounds`` and ``--tolerance``.
    ``progress``: True draws a progress bar on stderr (tqdm when installed);
    a callable is called as ``progress(round, max_trajectory_diameter,
    fraction)``.

    Every model of the formats runs, ``odometry2d`` included (with
    ``scan``, ``sensor_offset``, ``landmark_min_separation`` and ``None``
    truth entries): its result has ``headings`` (an interval per step) and
    ``metrics["max_heading_width"]``.

    The result equals ``nvector run``'s, ``metrics.elapsed_ms`` aside.
    The computation runs without the GIL; Ctrl-C stops it (KeyboardInterrupt).
    Raises :class:`InputError` naming the JSON path of a bad value (and the
    file, for a path).
    """
    bar: ProgressBar | None = None
    callback: Callable[[int, float, float], Any] | None
    if progress is True:
        bar = ProgressBar("nvector run")

        def callback(round_: int, diameter: float, fraction: float) -> None:
            assert bar is not None
            bar.update(fraction, f"round {round_}, max trajectory diameter {diameter:.4g}")

    elif callable(progress):
        callback = progress
    elif progress is False or progress is None:
        callback = None
    else:
        raise TypeError(f"progress must be True, False or a callable, not {type(progress).__name__}")
    try:
        result: dict[str, Any] = read_with_file(
            lambda source: _nvector.run(source, contractor, max_rounds, tolerance, callback), mission
        )
        if bar is not None:
            bar.finish()
        return result
    finally:
        if bar is not None:
            bar.close()


def check(mission: dict[str, Any] | PathLike) -> list[dict[str, Any]]:
    """Every constraint of a mission that its truth breaks, and by how
    much, as ``nvector check --json`` lists them (docs/cli.md, "check";
    docs/formats.md, "Check"): one dict per violation with ``path`` (the
    constraint's JSON path in the mission, e.g. ``"detections[5].range"``,
    ``"motion_error[12]"``), ``kind``, ``unit``, ``value`` (the truth's),
    ``bound`` (an interval ``[lo, hi]`` or a number), ``relation``
    (``"within"``, ``"at_most"``, ``"at_least"``), ``excess`` (how far
    beyond the bound, rounded down), ``outlier`` (a detection's violation
    that ``max_outliers`` covers) and, when they apply, ``step``,
    ``detection``, ``landmark``. An empty list: the truth satisfies every
    constraint checked.

    ``mission`` is a mission dict or the path of a mission file; it must
    have a ``truth``. Raises :class:`InputError` naming the JSON path of a
    bad value (and the file, for a path).
    """
    report: dict[str, Any] = read_with_file(_nvector.check, mission)
    violations: list[dict[str, Any]] = report["violations"]
    return violations


def tdoa(
    problem: dict[str, Any] | PathLike,
    contractor: str | None = None,
    budget: int = 96,
    max_rounds: int = 8,
) -> dict[str, Any]:
    """TDOA passive location (docs/tdoa.md): the guaranteed boxes of an
    ``nvector-tdoa/1`` problem (a dict or the path of a file), as
    ``nvector tdoa`` computes them (``nvector-tdoa-result/1``).

    ``contractor``: ``"none"`` (the operator's ``emitter`` ids only) or an
    atmost_nvector contractor (default ``"best"``); ``budget`` and
    ``max_rounds`` are the CLI's ``--budget`` and ``--max-rounds``.
    Raises :class:`InputError` naming the JSON path of a bad value.
    """
    result: dict[str, Any] = read_with_file(
        lambda source: _nvector.tdoa(source, contractor, budget, max_rounds), problem
    )
    return result


def import_dataset(
    name: str,
    directory: PathLike,
    operator: bool = False,
    outlier_share: float = 0.0,
    false_detections: int = 0,
    seed: int = 1,
    set: int = 1,
) -> dict[str, Any]:
    """A data set's directory converted as ``nvector import`` converts it
    (the same bits), as a dict.

    ``name``: ``"cmu-plaza"`` (CMU Plaza 1, e.g. ``data/cmu-plaza1``: a
    ``unicycle2d`` mission, docs/cmu-plaza1.md), ``"utias-woods"`` (UTIAS
    Lost in the Woods, ``data/utias-lost-in-the-woods``: an ``odometry2d``
    mission, docs/utias-woods.md) or ``"locards-mlat"`` (LocaRDS
    multilateration, ``data/locards-mlat``: an ``nvector-tdoa/1`` problem
    of the file ``set_{set}.csv``, docs/tdoa.md); the directory names
    ``"cmu-plaza1"`` and ``"utias-lost-in-the-woods"`` are accepted too.
    Every bound is derived from the data against its truth, the method in
    ``meta``. Plaza and woods: ``operator`` keeps the data set's landmark
    ids as the operator's matching; ``outlier_share`` P in [0, 0.5) lets
    the bands hold the central 1 - P of the residuals (``max_outliers``
    counts the detections outside); ``false_detections`` plants that many
    false ranges (deterministic for ``seed``, ``None`` in
    ``truth["matching"]``).

    Raises :class:`InputError` naming the setting or the file and line of
    a bad value, ``FileNotFoundError`` for a missing file.
    """
    result: dict[str, Any] = _nvector.import_dataset(
        name, os.fspath(directory), operator, outlier_share, false_detections, seed, set
    )
    return result


def import_csv(
    model: str,
    log: PathLike,
    detections: PathLike,
    errors: dict[str, float],
    dt: float | None = None,
    motion_error: float = 0.0,
    initial: Sequence[Sequence[float]] | None = None,
    initial_heading: Sequence[float] | None = None,
    heading_error: float | None = None,
    sensor_offset: Sequence[float] | None = None,
    landmark_count: int | None = None,
    landmark_min_separation: float | None = None,
    max_outliers: int | None = None,
    name: str | None = None,
) -> dict[str, Any]:
    """A mission from a sensor log CSV and a detections CSV, as ``nvector
    import --model ...`` makes it (the same bits), as a dict.

    ``model``: ``"unicycle2d"`` (log columns ``t,speed,heading``),
    ``"auv3d"`` (``t,roll,pitch,yaw,vx,vy,vz``) or ``"odometry2d"``
    (``t,speed,turn_rate``); ``detections``: ``t,range_lo,range_hi``,
    optional ``bearing_lo,bearing_hi`` (radians), ``scan``, ``landmark``.
    ``errors`` gives the bound of each channel (``{"speed": 0.1,
    "heading": 0.01}``). ``dt`` defaults to the median spacing of ``t``;
    ``initial`` is the box of the first position, one ``(lo, hi)`` per axis
    (default the origin); ``initial_heading`` ``(lo, hi)`` and
    ``heading_error`` are for ``odometry2d`` (the first required there);
    ``sensor_offset`` ``(x, y)`` for the 2-D models. Times are matched to
    steps by ``round((t - t0) / dt)``. A column the import does not read
    is named in a ``UserWarning``.

    Raises :class:`InputError` naming the setting, or the file and line of
    a bad cell (``str(error)`` is the CLI's message), ``FileNotFoundError``
    for a missing file.
    """
    import warnings

    mission, notes = _nvector.import_csv(
        model,
        os.fspath(log),
        os.fspath(detections),
        [(str(k), float(v)) for k, v in errors.items()],
        dt,
        motion_error,
        None if initial is None else [(float(a), float(b)) for a, b in initial],
        None if initial_heading is None else tuple(initial_heading),
        heading_error,
        None if sensor_offset is None else tuple(sensor_offset),
        landmark_count,
        landmark_min_separation,
        max_outliers,
        name,
    )
    for note in notes:
        warnings.warn(f"nvector.import_csv: {note}", stacklevel=2)
    result: dict[str, Any] = mission
    return result


def boxes(result_boxes: Sequence[Any]) -> np.ndarray:
    """Boxes of a result (``result["trajectory"]``, ``result["detections"]``,
    ``result["landmarks"]``) as a float array of shape (k, d, 2):
    ``"inf"``/``"-inf"`` bounds become infinities and an ``"empty"`` box NaN."""
    rows: list[list[list[float]] | None] = []
    dim = 0
    for b in result_boxes:
        if isinstance(b, str):
            rows.append(None)
            continue
        # float() reads the bounds "inf" and "-inf" too.
        axes = [[float(x[0]), float(x[1])] for x in b]
        dim = max(dim, len(axes))
        rows.append(axes)
    out = np.full((len(rows), dim, 2), np.nan)
    for i, row in enumerate(rows):
        if row is not None and len(row) == dim:
            out[i] = row
    return out
