"""A/B of the batched gym step against a given commit: builds that commit's wheel once (cached
under ~/.cache/sinew-ab/<sha>, beside its worktree), then times the native vector env's step loop (64 worlds,
seeded random actions) with the installed sinew and with the commit's, in alternating runs, on an
Euler model and the RK4 ones, with 1 and 2 threads. Run it before a change to the step lands.

    python benches/ab_step.py BASE_COMMIT [--rounds 5] [--tasks Hopper HalfCheetah Ant Humanoid] [--out FILE]

A task is a gymnasium or dm_control env (`Hopper`, `dmc-quadruped-walk`), or a model file (a robot
scene: `path/to/scene.xml`), whose 64 worlds a `sinew.Batch` steps under random controls in their
ranges, held for 10 steps.

Each run is a fresh process timing only the step loop; the ratio is new time / base time per
round (below 1: the installed build is faster), reported as the median and range over rounds.
The two runs of a round go in turns (new first, then base first), so that whatever favours the
first or the second run of a pair cancels.
"""

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path

from ab_base import base_tree
from emit import invocation

STEPS = {"Hopper": 1500, "Walker2d": 1000, "HalfCheetah": 1000, "Ant": 600, "Humanoid": 500}

LOOP = """
import sys, time, numpy as np, gymnasium as gym, sinew
task, threads, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
env = gym.make_vec(f"sinew/{task}-v0", num_envs=64, vectorization_mode="vector_entry_point", num_threads=threads)
space = env.single_action_space
a = np.random.default_rng(0).uniform(space.low, space.high, (steps, 64) + space.shape)
env.reset(seed=0)
t = time.perf_counter()
for x in a:
    env.step(x)
print(time.perf_counter() - t)
"""

BATCH_LOOP = """
import sys, time, warnings, numpy as np, sinew
warnings.simplefilter("ignore")
path, threads, steps = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
m = sinew.Model.from_mjcf(path)
b = sinew.Batch(m, 64, num_threads=threads)
lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
c = np.random.default_rng(0).uniform(lo, hi, (steps // 10 + 1, 64, m.nu))
t = time.perf_counter()
for k in range(steps // 10):
    b.ctrl[:] = c[k]
    b.step(10)
print(time.perf_counter() - t)
"""


def build(commit: str) -> Path:
    """The package of `commit`, unpacked from its wheel (built once, from its worktree)."""
    tree = base_tree(commit)
    pkg, wheels = tree.parent / "pkg", tree.parent / "wheel"
    if (pkg / "sinew").is_dir():
        return pkg
    subprocess.run([sys.executable, "-m", "pip", "wheel", ".", "--no-deps", "-q", "-w", str(wheels)], cwd=tree, check=True)
    wheel = next(wheels.glob("*.whl"))
    subprocess.run([sys.executable, "-m", "zipfile", "-e", str(wheel), str(pkg)], check=True)
    return pkg


def run(task: str, threads: int, base: Path | None) -> float:
    env = dict(os.environ)
    if base is not None:
        env["PYTHONPATH"] = str(base)
    loop = BATCH_LOOP if task.endswith(".xml") else LOOP
    out = subprocess.run([sys.executable, "-c", loop, task, str(threads), str(STEPS.get(task, 300))], env=env, capture_output=True, text=True, check=True)
    return float(out.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--tasks", nargs="+", default=["Hopper", "HalfCheetah", "Ant", "Humanoid"])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    base = build(args.base)
    lines = [f"| task | threads | new / base step time (median) | range over {args.rounds} rounds | new (s) | base (s) |", "|---|---|---|---|---|---|"]
    for task in args.tasks:
        for threads in (1, 2):
            new, old = [], []
            for k in range(args.rounds):
                # the order turns each round, so that a bias of a pair's first or second run cancels
                for side in ((None, base) if k % 2 == 0 else (base, None)):
                    (new if side is None else old).append(run(task, threads, side))
            ratios = sorted(a / b for a, b in zip(new, old))
            row = f"| {Path(task).name if task.endswith('.xml') else task} | {threads} | {statistics.median(ratios):.3f} | {ratios[0]:.3f}–{ratios[-1]:.3f} | {statistics.median(new):.3f} | {statistics.median(old):.3f} |"
            print(row, flush=True)
            lines.append(row)
    if args.out:
        Path(args.out).write_text("\n".join([invocation(), *lines]) + "\n")


if __name__ == "__main__":
    main()
