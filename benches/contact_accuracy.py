"""The analytic contact scenes of [contact], measured for both friction models, both constraint
modes and both symplectic integrators (semi-implicit Euler, leapfrog) at dt = 0.002 and 0.01: creep on a 20° slope (μ = 1, 5 s), acceleration down a 30° slope
(μ = 0.3), stopping distance from 3 m/s (μ = 0.5), rebound of a ball with e = 0.5, drift of five
stacked boxes over 10 s; with the solver's fallback counts.

    python benches/contact_accuracy.py [--out results/contact_accuracy.md]
"""

import argparse
import math
import os
import sys

import numpy as np

import sinew

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "python"))
from test_contact import bounce_peak, stack_drift  # noqa: E402
from test_friction import box_on_slope  # noqa: E402

G = 9.81


def creep(dt, fr, mode, integ):
    sim, _ = box_on_slope(20, 1.0, dt, fr, mode, integ)
    sim.step(int(0.2 / dt))
    start = sim.qpos[:3].copy()
    sim.step(int(5 / dt))
    return np.linalg.norm(sim.qpos[:3] - start), sim.constraint_stats


def slide(dt, fr, mode, integ):
    sim, down = box_on_slope(30, 0.3, dt, fr, mode, integ)
    sim.step(int(0.5 / dt))
    t0, v0 = sim.time, sim.qvel[:3] @ down
    sim.step(int(0.5 / dt))
    a = (sim.qvel[:3] @ down - v0) / (sim.time - t0)
    exact = G * (math.sin(math.radians(30)) - 0.3 * math.cos(math.radians(30)))
    return (a - exact) / exact, sim.constraint_stats


def stop(dt, fr, mode, integ):
    sim, _ = box_on_slope(0, 0.5, dt, fr, mode, integ)
    sim.qvel[0] = 3.0
    sim.step(int(1.5 / dt))
    exact = 9.0 / (2 * 0.5 * G)
    return (sim.qpos[0] - exact) / exact, sim.constraint_stats


def bounce(dt, fr, mode, integ):
    peak, sim = bounce_peak(dt, mode, fr, integrator=integ)
    return (peak - 0.225) / 0.225, sim.constraint_stats


def stack(dt, fr, mode, integ):
    worst, sim = stack_drift(dt, mode, fr, integrator=integ)
    return worst, sim.constraint_stats


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    scenes = [("creep on 20° (m)", creep), ("30° slide accel (rel err)", slide), ("stop distance (rel err)", stop),
              ("bounce height (rel err)", bounce), ("5-box stack drift (m)", stack)]
    lines = ["| scene | friction | mode | dt | Euler | leapfrog | LCP solves (Euler, leapfrog) | Lemke fails: PGS / inexact (both) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, fn in scenes:
        for fr in ("one_tangent", "pyramid"):
            for mode in ("acceleration", "velocity"):
                for dt in (0.002, 0.01):
                    (ve, se), (vl, sl) = fn(dt, fr, mode, "Euler"), fn(dt, fr, mode, "leapfrog")
                    fails = f"{se['fallback_pgs'] + sl['fallback_pgs']} / {se['inexact'] + sl['inexact']}"
                    lines.append(f"| {name} | {fr} | {mode} | {dt:g} | {ve:.2e} | {vl:.2e} | {se['solves']}, {sl['solves']} | {fails} |")
                    print(lines[-1], flush=True)
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/contact_accuracy.py --out {args.out} -->\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
