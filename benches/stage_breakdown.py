"""Per-stage cost of a step (kinematics, ABA, collision, rows, K assembly, LCP, impact update,
integration, post-stabilisation) for each gymnasium model on its floor: 10 s of random controls at
the model's own dt and integrator, pyramid friction, one thread. Builds and runs the Rust example
`stage_breakdown` with the `stage-timing` feature (timers around each stage: the rates printed
are slower than untimed stepping).

    python benches/stage_breakdown.py [--out results/stage_breakdown.md]
"""

import argparse
import os
import subprocess

from sinew.tasks import ASSETS

MODELS = ("inverted_pendulum", "reacher", "hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    root = os.path.join(os.path.dirname(__file__), "..")
    cmd = ["cargo", "run", "--quiet", "--profile", "wheel", "--features", "stage-timing", "--example", "stage_breakdown", "--"]
    table = subprocess.run(cmd + [os.path.join(ASSETS, m + ".xml") for m in MODELS], cwd=root, check=True, capture_output=True, text=True).stdout
    print(table, end="")
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/stage_breakdown.py --out {args.out} -->\n" + table)


if __name__ == "__main__":
    main()
