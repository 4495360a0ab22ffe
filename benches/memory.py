"""Bytes per world of a batch: the growth of the process's resident memory from 1 to N worlds
(one thread, after 300 steps under random controls, which grow the buffers sized to a step's
contacts and rows), split into the state and output arrays Python sees (their sizes
from their shapes) and the rest (what each world keeps between steps: history, caches, the forces its rows applied; the threads hold the scratch), and the extra a
world pays once it holds model values of its own (`set_params`: its own copy of the model).

    python benches/memory.py [--worlds 1024] [--out results/memory.md]

Each measurement runs in a fresh process.
"""

import argparse
import json
import subprocess
import sys

from emit import emit, invocation

TASKS = {"Hopper": "hopper", "Walker2d": "walker2d_v5", "HalfCheetah": "half_cheetah", "Ant": "ant", "Humanoid": "humanoid"}

PROBE = """
import json, sys, numpy as np, sinew
from sinew.tasks import ASSETS
name, n, own = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "1"
m = sinew.Model.from_mjcf(f"{ASSETS}/{name}.xml")
rss = lambda: int(open("/proc/self/statm").read().split()[1]) * 4096
rng = np.random.default_rng(0)
def run(b):
    for k in range(300):
        if k % 10 == 0:
            b.ctrl[:] = rng.uniform(-1, 1, b.ctrl.shape)
        b.step()
run(sinew.Batch(m, 1, num_threads=1))
before = rss()
b = sinew.Batch(m, n, num_threads=1)
if own:
    b.set_params("gravity", np.tile([0.0, 0.0, -9.81], (n, 1)) * np.linspace(0.9, 1.1, n)[:, None])
run(b)
after = rss()
arrays = sum(getattr(b, k).nbytes for k in ("qpos", "qvel", "ctrl", "act", "time", "diverged", "xpos", "xmat", "xipos",
                                            "xvel", "cfrc_ext", "qfrc_constraint", "cinert", "cvel"))
print(json.dumps({"total": (after - before) / n, "arrays": arrays / n}))
"""


def probe(xml: str, n: int, own: bool) -> dict:
    out = subprocess.run([sys.executable, "-c", PROBE, xml, str(n), "1" if own else "0"], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--worlds", type=int, default=1024)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = [f"| task | kB per world ({args.worlds} worlds) | of which state and output arrays | kept between steps (history, caches, forces) | "
             "a world with its own model values, extra |", "|---|---|---|---|---|"]
    for task, xml in TASKS.items():
        plain, own = probe(xml, args.worlds, False), probe(xml, args.worlds, True)
        kb = lambda x: f"{x / 1024:.1f}"
        lines.append(f"| {task} | {kb(plain['total'])} | {kb(plain['arrays'])} | {kb(plain['total'] - plain['arrays'])} | "
                     f"{kb(own['total'] - plain['total'])} |")
        print(lines[-1], flush=True)
    emit("\n".join([invocation(), *lines]) + "\n", args.out)


if __name__ == "__main__":
    main()
