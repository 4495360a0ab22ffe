"""Prints the results table of training/README.md from runs/*/*/result.json."""

import glob
import json
import os
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "runs")
rows = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(root, "*", "*", "result.json")))]
print("| environment | algorithm | steps | seed | evaluated return (10 episodes) | training wall time (s) |")
print("|---|---|---|---|---|---|")
for r in sorted(rows, key=lambda r: (r["env"].split("/")[-1], r["algo"], r["env"])):
    print(f"| {r['env']} | {r['algo'].upper()} | {r['steps']:,} | {r['seed']} | {r['return_mean']:.1f} ± {r['return_std']:.1f} | {r['train_wall_s']:.0f} |")
