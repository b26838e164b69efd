"""Type stubs of the compiled part of the nvector package (nvector._nvector)."""

from typing import Any, Callable

MAX_STEPS: int

def contract(request: dict[str, Any]) -> tuple[dict[str, Any], bytes, int]:
    """One nvector-contract/1 request -> (response, boxes as little-endian
    f64 bytes k x dim x 2 with NaN for empty boxes, dim)."""

def simulate(
    scenario: str,
    seed: int,
    steps: int | None,
    landmarks: int | None,
    operator: bool,
    noise: float,
    layout: str,
    range_only: bool,
    false_detections: int,
) -> dict[str, Any]:
    """A simulated nvector-mission/1 mission with truth."""

def run(
    mission: str | dict[str, Any],
    contractor: str | None,
    max_rounds: int,
    tolerance: float,
    progress: Callable[[int, float, float], Any] | None,
) -> dict[str, Any]:
    """One SLAM job: mission JSON text or objects -> nvector-result/1."""

def tdoa(
    problem: str | dict[str, Any],
    contractor: str | None,
    budget: int,
    max_rounds: int,
) -> dict[str, Any]:
    """One TDOA problem: nvector-tdoa/1 text or objects -> nvector-tdoa-result/1."""

def check(mission: str | dict[str, Any]) -> dict[str, Any]:
    """The constraints a mission's truth breaks: mission JSON text or
    objects -> {"violations": [...], "unchecked": int,
    "broken_detections": int, "max_outliers": int}."""

def import_dataset(
    name: str,
    directory: str,
    operator: bool,
    outlier_share: float,
    false_detections: int,
    seed: int,
    set: int,
) -> dict[str, Any]:
    """A data set's directory as `nvector import` converts it."""

def import_csv(
    model: str,
    log: str,
    detections: str,
    errors: list[tuple[str, float]],
    dt: float | None,
    motion_error: float,
    initial: list[tuple[float, float]] | None,
    initial_heading: tuple[float, ...] | None,
    heading_error: float | None,
    sensor_offset: tuple[float, ...] | None,
    landmark_count: int | None,
    landmark_min_separation: float | None,
    max_outliers: int | None,
    name: str | None,
) -> tuple[dict[str, Any], list[str]]:
    """A log CSV and a detections CSV as `nvector import --model` reads them: (mission, notes)."""

def dumps(obj: Any) -> str:
    """Python objects as compact JSON text, as the nvector binary writes it."""

def read_result(result: Any) -> dict[str, Any]:
    """A nvector-result/1 result (JSON text or objects) read through core's
    types, as written; InputError names the path of its first fault."""

def figure(result: Any, mission: Any = None) -> str:
    """The picture of a nvector-result/1 result (with the truth of the
    mission, when given), as JSON text: title, subtitle, axis labels, view
    [x0, x1, y0, y1] and layers (name, label, kind, colour, fill_alpha,
    line_width, rects, points, polygons), bottom first; what the CLI's
    figures draw (odometry2d headings as polygons)."""
