"""nvector.contract against `nvector contract`, bit for bit."""

from __future__ import annotations

import json
import random

import numpy as np
import pytest
from conftest import Cli, canonical

import nvector

CLOCK = ("stats", "elapsed_us")


def request(boxes: object, n: int, contractor: str) -> dict[str, object]:
    return {"format": "nvector-contract/1", "n": n, "boxes": boxes, "contractor": contractor}


def random_boxes(
    rng: random.Random, k: int, d: int, spread: float, m: int, margin: float | None = None
) -> list[list[list[float]]]:
    """k boxes around m planted points (so at most m distinct vectors fit):
    each box holds one of the points, with random margins."""
    points = [[rng.uniform(-spread, spread) for _ in range(d)] for _ in range(m)]
    w = spread / 4 if margin is None else margin
    out = []
    for _ in range(k):
        p = rng.choice(points)
        out.append([[x - rng.uniform(0, w), x + rng.uniform(0, w)] for x in p])
    return out


def check_same(cli: Cli, boxes: list, n: int, contractor: str) -> nvector.ContractResult:
    result = nvector.contract(boxes, n, contractor)
    text = cli.json("contract", stdin=json.dumps(request(boxes, n, contractor)))
    assert canonical(result.json, CLOCK) == canonical(json.loads(text), CLOCK)
    # The numpy boxes are the response's boxes, bound for bound.
    if result.status != "infeasible":
        np.testing.assert_array_equal(result.boxes, nvector.boxes(json.loads(text)["boxes"]))
    else:
        assert np.isnan(result.boxes).all()
    assert result.boxes.shape == (len(boxes), len(boxes[0]), 2)
    assert result.status == json.loads(text)["status"]
    assert result.groups == json.loads(text)["groups"]
    return result


def test_spec_example() -> None:
    r = nvector.contract([[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]], 2, "projection")
    assert r.status == "contracted"
    np.testing.assert_array_equal(r.boxes, [[[1, 2], [1, 2]], [[1, 2], [1, 2]], [[5, 6], [5, 6]]])
    assert r.groups == [[0, 1], [2]]
    assert r.min_distinct == (2, 2)
    assert r.min_distinct.lower == 2 and r.min_distinct.upper == 2
    assert r.reason is None and r.feasible
    assert r.json["format"] == "nvector-contract-result/1"


@pytest.mark.parametrize("contractor", ["nvalue", "projection", "independent", "exact", "best"])
@pytest.mark.parametrize("dim", [1, 2, 3])
def test_random_instances_agree_with_the_cli(cli: Cli, contractor: str, dim: int) -> None:
    rng = random.Random(1000 * dim + len(contractor))
    k = 12 if contractor == "exact" else 60
    statuses = []
    for n, planted in [(2, 2), (3, 3), (5, 4), (3, 5)]:
        boxes = random_boxes(rng, k, dim, spread=10.0, m=planted)
        r = check_same(cli, boxes, n, contractor)
        statuses.append(r.status)
        if planted <= n:
            assert r.status != "infeasible"  # the planted points are a solution
    assert "contracted" in statuses


def test_infeasible_boxes_are_nan(cli: Cli) -> None:
    r = check_same(cli, [[[0, 1]], [[2, 3]], [[4, 5]]], 2, "best")
    assert r.status == "infeasible" and not r.feasible
    assert r.reason and "n = 2" in r.reason
    assert np.isnan(r.boxes).all()


def test_unbounded_and_degenerate_bounds(cli: Cli) -> None:
    boxes = [[["-inf", 1], [0, "inf"]], [[0.5, 0.5], 2], [[0, 3], [1, 4]]]
    r = check_same(cli, boxes, 1, "best")
    assert r.status == "contracted"
    # Python infinities are the spec's "inf" bounds.
    same = nvector.contract([[[-np.inf, 1], [0, np.inf]], [[0.5, 0.5], 2], [[0, 3], [1, 4]]], 1, "best")
    assert canonical(same.json, CLOCK) == canonical(r.json, CLOCK)


def test_numpy_input_equals_list_input() -> None:
    rng = np.random.default_rng(7)
    lo = rng.uniform(-5, 5, size=(40, 2))
    arr = np.stack([lo, lo + rng.uniform(0, 2, size=(40, 2))], axis=-1)
    assert arr.shape == (40, 2, 2)
    a = nvector.contract(arr, np.int64(4), "independent")
    b = nvector.contract(arr.tolist(), 4, "independent")
    assert canonical(a.json, CLOCK) == canonical(b.json, CLOCK)
    np.testing.assert_array_equal(a.boxes, b.boxes)
    # Soundness as seen from Python: the result is inside the input.
    if a.status != "infeasible":
        assert (a.boxes[..., 0] >= arr[..., 0]).all() and (a.boxes[..., 1] <= arr[..., 1]).all()


def test_large_instance_agrees(cli: Cli) -> None:
    rng = random.Random(99)
    boxes = random_boxes(rng, 5000, 2, spread=1000.0, m=40, margin=5.0)
    assert check_same(cli, boxes, 40, "best").status == "contracted"
