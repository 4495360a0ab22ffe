"""Prints the results tables of training/README.md from runs/*/*/result.json: one row per run, then
each environment and algorithm's returns over its seeds."""

import glob
import json
import os
import sys

import numpy as np

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "runs")
rows = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(root, "*", "*", "result.json")))]


def order(env, algo):
    """Sort key: the task, the algorithm, then sinew before the twin."""
    return env.split("/")[-1], algo, env


print("| environment | algorithm | steps | seed | evaluated return (10 episodes) | training wall time (s) |")
print("|---|---|---|---|---|---|")
for r in sorted(rows, key=lambda r: (*order(r["env"], r["algo"]), r["seed"])):
    print(f"| {r['env']} | {r['algo'].upper()} | {r['steps']:,} | {r['seed']} | {r['return_mean']:.1f} ± {r['return_std']:.1f} | {r['train_wall_s']:.0f} |")
groups: dict = {}
for r in rows:
    groups.setdefault((r["env"], r["algo"], r["steps"]), []).append(r)
print()
print("| environment | algorithm | steps | seeds | mean of the evaluated returns | lowest | highest |")
print("|---|---|---|---|---|---|---|")
for (env, algo, steps), rs in sorted(groups.items(), key=lambda kv: order(kv[0][0], kv[0][1])):
    ret = np.array([r["return_mean"] for r in rs])
    seeds = ", ".join(str(s) for s in sorted(r["seed"] for r in rs))
    print(f"| {env} | {algo.upper()} | {steps:,} | {seeds} | {ret.mean():.1f} | {ret.min():.1f} | {ret.max():.1f} |")
