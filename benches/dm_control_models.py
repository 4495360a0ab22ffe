"""dm_control's suite models (the dm-control package's files, includes and all) beside MuJoCo:
whether sinew loads each, its sizes, the largest relative error of the constraint-free
acceleration at 5 random states and controls (MuJoCo's fluid forces off: sinew does not model
them), whether 2 s of random controls stay finite, and single-world steps/s of sinew's `Sim.step`
and MuJoCo's `mj_step` over those 2 s, one Python call a step (one thread, the file's own
timestep and integrator; MuJoCo computes fish's and swimmer's fluid forces, sinew does not).

    python benches/dm_control_models.py [--out results/dm_control_models.md]
"""

import argparse
import glob
import importlib.util
import os
import time
import warnings

import mujoco
import numpy as np

import sinew

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")


def qacc_error(m, mj):
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    mj.opt.density = mj.opt.viscosity = 0.0
    d = mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    worst = 0.0
    for _ in range(5):
        q = mj.qpos0.copy()
        mujoco.mj_integratePos(mj, q, rng.normal(0.0, 0.3, mj.nv), 1.0)
        v, u = rng.normal(0.0, 1.0, mj.nv), rng.uniform(-1.0, 1.0, mj.nu)
        d.qpos[:], d.qvel[:], d.ctrl[:] = q, v, u
        mujoco.mj_forward(mj, d)
        s = sinew.Sim(m)
        s.qpos[:], s.qvel[:], s.ctrl[:] = q, v, u
        s.forward()
        if m.nv:
            worst = max(worst, float(np.max(np.abs(s.qacc - d.qacc) / (1.0 + np.abs(d.qacc)))))
    return worst


def controls(nu, lo, hi, steps):
    rng = np.random.default_rng(0)
    return rng.uniform(lo, hi, size=(steps, nu)) if nu else np.zeros((steps, 0))


def rollout(m, path):
    steps = int(round(2.0 / m.timestep))
    lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
    u = controls(m.nu, lo, hi, steps)
    s = sinew.Sim(m)
    t = time.perf_counter()
    finite = True
    try:
        for k in range(steps):
            s.ctrl[:] = u[k]
            s.step()
    except sinew.SimulationError:
        finite = False
    ours = steps / (time.perf_counter() - t)
    mj = mujoco.MjModel.from_xml_path(path)
    d = mujoco.MjData(mj)
    t = time.perf_counter()
    for k in range(steps):
        d.ctrl[:] = u[k]
        mujoco.mj_step(mj, d)
    theirs = steps / (time.perf_counter() - t)
    return finite, ours, theirs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = ["| model | loads | nq / nv / nu | qacc error vs MuJoCo | 2 s finite | sinew steps/s | MuJoCo steps/s |",
            "|---|---|---|---|---|---|---|"]
    for path in sorted(glob.glob(os.path.join(SUITE, "*.xml"))):
        name = os.path.basename(path)[:-4]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m = sinew.Model.from_mjcf(path)
            except sinew.ModelError as e:
                reason = str(e).split(": ", 1)[1]
                rows.append(f"| {name} | no: {reason} | | | | | |")
                continue
        err = qacc_error(m, mujoco.MjModel.from_xml_path(path))
        finite, ours, theirs = rollout(m, path)
        rows.append(f"| {name} | yes | {m.nq} / {m.nv} / {m.nu} | {err:.1e} | {'yes' if finite else 'no'} | {ours:,.0f} | {theirs:,.0f} |")
    loaded = sum(" | yes | " in r for r in rows)
    text = "\n".join([f"dm_control's suite: {loaded} of {len(rows) - 2} files load.", "", *rows, ""])
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write("# dm_control's suite models beside MuJoCo\n\n`python benches/dm_control_models.py --out results/dm_control_models.md`\n\n" + text)


if __name__ == "__main__":
    main()
