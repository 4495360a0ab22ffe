"""Cost of the two friction models: single-world steps/s on the gymnasium models under random
controls (reset every 1000 steps), the one-tangent ("one_tangent") model beside the pyramid.

    python benches/friction_models.py [--out results/friction_models.md]
"""

import argparse
import os
import time

import numpy as np

import sinew
from emit import emit
from sinew.tasks import ASSETS

MODELS = ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"]


def steps_per_second(name, friction, steps=20_000):
    model = sinew.Model.from_mjcf(os.path.join(ASSETS, name + ".xml")).with_options(friction=friction)
    sim, rng = sinew.Sim(model), np.random.default_rng(0)
    start = time.perf_counter()
    for k in range(steps):
        if k % 10 == 0:
            sim.ctrl[:] = rng.uniform(-1, 1, model.nu)
        sim.step()
        if k % 1000 == 999:
            sim.reset()
    return steps / (time.perf_counter() - start)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the table here (Markdown)")
    args = parser.parse_args()
    lines = [
        "<!-- python benches/friction_models.py --out results/friction_models.md -->",
        "| model | one tangent (seed), steps/s | pyramid, steps/s | pyramid's extra time |",
        "|---|---|---|---|",
    ]
    for name in MODELS:
        seed, pyramid = steps_per_second(name, "one_tangent"), steps_per_second(name, "pyramid")
        lines.append(f"| {name} | {seed:,.0f} | {pyramid:,.0f} | {seed / pyramid - 1:+.0%} |")
    emit("\n".join(lines) + "\n", args.out)


if __name__ == "__main__":
    main()
