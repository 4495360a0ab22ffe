"""Throughput on a machine shared with other work: sinew's native vector env (64 worlds, random
actions, default thread count) quiet, beside one busy process (a Python loop spinning on one
core), and as two such processes running together; EnvPool (2 threads) under the same busy
process for comparison.

    python benches/shared_machine.py [--tasks Hopper Humanoid] [--steps 400] [--rounds 3] [--out results/shared_machine.md]

Quiet and busy runs alternate, ``--rounds`` times; each keeps its median. "kept" is busy / quiet.
"two processes" is the sum of two processes' env-steps/s, each timed while the other runs, over
one process alone (1.00: nothing lost to oversubscription).
"""

import argparse
import subprocess
import sys
import time

import numpy as np

from emit import emit, invocation

SPIN = "while True: pass"


def rate(task, steps, envpool=False):
    """Env-steps/s of one 64-world vector env over `steps` seeded random actions."""
    import gymnasium as gym

    n = 64
    if envpool:
        import envpool as ep

        env = ep.make_gymnasium(f"{task}-v4", num_envs=n, num_threads=2, seed=0)
    else:
        import sinew  # noqa: F401

        env = gym.make_vec(f"sinew/{task}-v0", num_envs=n, vectorization_mode="vector_entry_point")
    space = env.single_action_space
    a = np.random.default_rng(0).uniform(space.low, space.high, size=(steps, n) + space.shape).astype(space.dtype)
    env.reset(seed=0)
    env.step(a[0])
    t = time.perf_counter()
    for x in a:
        env.step(x)
    return steps * n / (time.perf_counter() - t)


def measure(task, steps, envpool=False, copies=1):
    """Env-steps/s of `copies` processes each running `rate`, started together, summed."""
    code = f"import sys; sys.path.insert(0, {sys.path[0]!r}); from shared_machine import rate; print(rate({task!r}, {steps}, {envpool}))"
    procs = [subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True) for _ in range(copies)]
    return sum(float(p.communicate()[0]) for p in procs)


def busy(run):
    """`run()` while one other process spins."""
    hog = subprocess.Popen([sys.executable, "-c", SPIN])
    time.sleep(0.2)
    try:
        return run()
    finally:
        hog.kill()
        hog.wait()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tasks", nargs="+", default=["Hopper", "Walker2d", "HalfCheetah", "Ant", "Humanoid"])
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--envpool", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for task in args.tasks:
        runs = {
            "quiet": lambda: measure(task, args.steps),
            "busy": lambda: busy(lambda: measure(task, args.steps)),
            "two": lambda: measure(task, args.steps, copies=2),
        }
        if args.envpool:
            runs["ep quiet"] = lambda: measure(task, args.steps, envpool=True)
            runs["ep busy"] = lambda: busy(lambda: measure(task, args.steps, envpool=True))
        got = {k: [] for k in runs}
        for _ in range(args.rounds):
            for k, run in runs.items():
                got[k].append(run())
        med = {k: float(np.median(v)) for k, v in got.items()}
        row = [task, med["quiet"], med["busy"], med["busy"] / med["quiet"], med["two"] / med["quiet"]]
        if args.envpool:
            row += [med["ep busy"] / med["ep quiet"]]
        rows.append(row)
        print(" ".join(f"{x:,.2f}" if isinstance(x, float) else x for x in row), flush=True)
    head = "| task | sinew quiet (env-steps/s) | beside a busy process | kept | two processes / one |"
    rule = "|---|---|---|---|---|"
    if args.envpool:
        head, rule = head + " EnvPool kept |", rule + "---|"
    lines = [head, rule]
    for r in rows:
        cells = [r[0], f"{r[1]:,.0f}", f"{r[2]:,.0f}", f"{r[3]:.0%}", f"{r[4]:.2f}"] + ([f"{r[5]:.0%}"] if args.envpool else [])
        lines.append("| " + " | ".join(cells) + " |")
    emit("\n".join([invocation(), *lines]) + "\n", args.out)


if __name__ == "__main__":
    main()
