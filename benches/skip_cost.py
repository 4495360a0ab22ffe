"""What a scene does not use should cost nothing: step cost of each gymnasium model with its floor
moved 100 m below (collision runs, no contact), with contacts switched off, and with contacts and
limits off (the bare ABA step), single thread, semi-implicit Euler, gravity off so nothing falls.

    python benches/skip_cost.py [--out results/skip_cost.md]
"""

import argparse
import os
import re
import time
import warnings

import sinew
from sinew.tasks import ASSETS


def rate(model, steps=20000):
    sim = sinew.Sim(model)
    sim.step(1000)
    best = 0.0
    for _ in range(3):
        sim.reset()
        t = time.perf_counter()
        sim.step(steps)
        best = max(best, steps / (time.perf_counter() - t))
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["| model | far floor (steps/s) | contacts off | contacts and limits off (bare ABA) | far floor / bare |", "|---|---|---|---|---|"]
    for name in ("hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"):
        xml = open(os.path.join(ASSETS, name + ".xml")).read()
        # the floor 100 m down: the broadphase still checks every pair each step
        xml = re.sub(r'(<geom[^>]*name="floor"[^>]*?)pos="0 0 0"', r'\1pos="0 0 -100"', xml)
        if 'pos="0 0 -100"' not in xml:
            xml = re.sub(r'(<geom[^>]*name="floor")', r'\1 pos="0 0 -100"', xml)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = sinew.Model.from_mjcf_string(xml).with_options(integrator="Euler", gravity=[0, 0, 0])
        far = rate(m)
        off = rate(m.with_options(contact=False))
        bare = rate(m.with_options(contact=False, limit=False))
        lines.append(f"| {name} | {far:,.0f} | {off:,.0f} | {bare:,.0f} | {far / bare:.2f} |")
        print(lines[-1], flush=True)
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/skip_cost.py --out {args.out} -->\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
