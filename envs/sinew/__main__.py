"""``python -m sinew [model]``: load a model, simulate it, print what happened and how fast.

With no argument it runs gymnasium's humanoid.xml for 10 simulated seconds under random controls.
"""

import argparse
import os
import time

import numpy as np

import sinew


def default_model() -> str:
    import gymnasium

    return os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "humanoid.xml")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("model", nargs="?", default=None, help="MJCF file (default: gymnasium's humanoid.xml)")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    path = args.model or default_model()
    model = sinew.Model.from_mjcf(path)
    print(f"loaded {path}\n  {model}")
    sim = sinew.Sim(model)
    rng = np.random.default_rng(args.seed)
    lo, hi = model.actuator_ctrlrange.T if model.nu else (np.zeros(0), np.zeros(0))
    steps_per_ctrl = max(1, int(round(0.02 / model.timestep)))
    n_ctrl = int(round(args.seconds / model.timestep)) // steps_per_ctrl
    start = sim.xpos.copy()
    t0 = time.perf_counter()
    for _ in range(n_ctrl):
        sim.ctrl[:] = rng.uniform(lo, hi) if model.nu else sim.ctrl
        sim.step(steps_per_ctrl)
    wall = time.perf_counter() - t0
    steps = n_ctrl * steps_per_ctrl
    end = sim.xpos
    moved = np.linalg.norm(end - start, axis=1)
    far = int(np.argmax(moved))
    print(f"simulated {sim.time:.2f} s ({steps} steps, {model.integrator}, dt={model.timestep})")
    print(f"  body '{model.body_names[far]}' moved farthest: {moved[far]:.3f} m, now at {np.round(end[far], 3)}")
    print(f"  max |qvel| = {np.abs(sim.qvel).max():.3f}, all finite: {bool(np.isfinite(sim.get_state()).all())}")
    print(f"  wall time {wall:.3f} s: {steps / wall:,.0f} steps/s, {sim.time / wall:,.0f}x real time (one thread)")


if __name__ == "__main__":
    main()
