"""Gymnasium models on their floors: 10 s of random actions (a new uniform ctrl every 5 steps),
maximum penetration, maximum hinge-limit violation, constraint statistics and wall time, for both
constraint modes (seed friction).

    python benches/contact_floor.py [--out results/contact_floor.md]
"""

import argparse
import os
import time
import warnings

import numpy as np

import sinew
from sinew.tasks import ASSETS  # gymnasium's model files: one definition



def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = [
        "| model | constraint mode | steps | max penetration (mm) | max limit violation (rad) | after 1 s (rad) | impacts | LCP pivots | warm starts | PGS fallbacks | wall (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, mode in [(n, c) for n in ["hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"] for c in ["acceleration", "velocity"]]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = sinew.Model.from_mjcf(os.path.join(ASSETS, name + ".xml")).with_options(constraint_mode=mode)
        sim = sinew.Sim(m)
        rng = np.random.default_rng(0)
        lo, hi = m.actuator_ctrlrange.T
        hinges = [j for j in range(m.njnt) if m.jnt_limited[j] and m.joint_types[j] == "hinge"]
        pen = lim = lim_late = 0.0
        steps = int(10 / m.timestep)
        t0 = time.perf_counter()
        for k in range(steps):
            if k % 5 == 0:
                sim.ctrl[:] = rng.uniform(lo, hi)
            sim.step()
            pen = max([pen] + [-c["dist"] for c in sim.contacts])
            for j in hinges:
                q = sim.qpos[m.jnt_qposadr[j]]
                lo_j, hi_j = m.jnt_range[j]
                lim = max(lim, lo_j - q, q - hi_j)
                if k * m.timestep >= 1.0:
                    lim_late = max(lim_late, lo_j - q, q - hi_j)
        wall = time.perf_counter() - t0
        s = sim.constraint_stats
        lines.append(
            f"| {name} | {mode} | {steps} | {pen * 1e3:.2f} | {lim:.4f} | {lim_late:.1e} | {s['impacts']} | {s['pivots']} | {s['warm_starts']} | {s['fallback_pgs']} | {wall:.2f} |"
        )
        print(lines[-1], flush=True)
    table = "\n".join(lines)
    print(table)
    if args.out:
        with open(args.out, "w") as f:
            f.write("<!-- python benches/contact_floor.py --out results/contact_floor.md -->\n" + table + "\n")


if __name__ == "__main__":
    main()
