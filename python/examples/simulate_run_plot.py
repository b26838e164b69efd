"""Simulate the paper's experiment, run it with and without the nvector
constraint, and draw both results side by side (like the paper's Figure 9).

    python examples/simulate_run_plot.py [--steps N] [--seed S] [--out FIG.png]
"""

from __future__ import annotations

import argparse

import matplotlib

matplotlib.use("Agg")  # files only; drop this line in a notebook
import matplotlib.pyplot as plt

import nvector


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--steps", type=int, default=4000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default="slam.png")
    args = parser.parse_args()

    mission = nvector.simulate("paper", seed=args.seed, steps=args.steps)
    # Each panel fitted to its own result (axes in metres, a legend each).
    fig, axes = plt.subplots(1, 2, figsize=(16, 6), layout="constrained")
    for ax, contractor in zip(axes, ["none", "best"]):
        result = nvector.run(mission, contractor=contractor, progress=True)
        metrics = result["metrics"]
        print(
            f"{contractor:>5}: {result['status']}, max trajectory diameter "
            f"{metrics['max_trajectory_diameter']:.3f} m, {metrics['matched_detections']} "
            f"detections matched, truth inside: {result['score']['truth_inside']}"
        )
        nvector.plot(result, mission, ax=ax)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
