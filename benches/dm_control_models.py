"""dm_control's suite models (the dm-control package's files, includes and all) beside MuJoCo:
whether sinew loads each, its sizes, the largest relative error of the constraint-free
acceleration at 5 random states and controls (fluid forces, tendons and actuators included),
whether 2 s of random controls stay finite, the largest overshoot of a tendon's length limit
over those 2 s in each simulator (ball_in_cup's string), the largest residual of an equality
constraint over those 2 s in each (the tendon couplings of manipulator, quadruped and stacker:
sinew holds them as exact rows, MuJoCo's soft ones give), and single-world steps/s of sinew's
`Sim.step` and MuJoCo's `mj_step` over those 2 s, one Python call a step (one thread, the file's
own timestep and integrator).

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


def overshoot(length, ranges):
    """The largest distance by which a length lies outside its [low, high] (NaN: unlimited)."""
    lo, hi = ranges.T
    out = np.maximum(lo - length, length - hi)
    return float(np.max(out[np.isfinite(out)], initial=0.0))


def equality_residual(mj, qpos, ten_length, qpos0, length0):
    """The largest |x₁ − x₁⁰ − Σ cᵢ (x₂ − x₂⁰)ⁱ| over the file's joint and tendon equalities
    (x: a joint's position or a tendon's length, ⁰ at qpos0, c the polycoef); None without any."""
    worst = None
    for e in range(mj.neq):
        if mj.eq_type[e] == mujoco.mjtEq.mjEQ_JOINT:
            x, x0 = qpos[mj.jnt_qposadr], qpos0[mj.jnt_qposadr]
        elif mj.eq_type[e] == mujoco.mjtEq.mjEQ_TENDON:
            x, x0 = ten_length, length0
        else:
            continue
        a, b = mj.eq_obj1id[e], mj.eq_obj2id[e]
        c = mj.eq_data[e, :5]
        d = 0.0 if b < 0 else x[b] - x0[b]
        r = abs(x[a] - x0[a] - sum(c[i] * d ** i for i in range(5)))
        worst = r if worst is None else max(worst, r)
    return worst


def rollout(m, path):
    steps = int(round(2.0 / m.timestep))
    lo, hi = m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0))
    u = controls(m.nu, lo, hi, steps)
    s = sinew.Sim(m)
    limited = not np.isnan(m.tendon_range).all()
    finite, ours_over, elapsed = True, 0.0, 0.0
    mj = mujoco.MjModel.from_xml_path(path)
    s.forward()
    length0 = np.array(s.ten_length)
    ours_eq = theirs_eq = equality_residual(mj, s.qpos, s.ten_length, mj.qpos0, length0)
    try:
        for k in range(steps):
            s.ctrl[:] = u[k]
            t = time.perf_counter()
            s.step()
            elapsed += time.perf_counter() - t
            if limited:
                ours_over = max(ours_over, overshoot(s.ten_length, m.tendon_range))
            if ours_eq is not None:
                ours_eq = max(ours_eq, equality_residual(mj, s.qpos, s.ten_length, mj.qpos0, length0))
    except sinew.SimulationError:
        finite = False
    ours = steps / elapsed
    d = mujoco.MjData(mj)
    ranges = np.where(mj.tendon_limited[:, None] == 1, mj.tendon_range, np.nan)
    theirs_over, elapsed = 0.0, 0.0
    for k in range(steps):
        d.ctrl[:] = u[k]
        t = time.perf_counter()
        mujoco.mj_step(mj, d)
        elapsed += time.perf_counter() - t
        if limited:
            theirs_over = max(theirs_over, overshoot(d.ten_length, ranges))
        if theirs_eq is not None:
            theirs_eq = max(theirs_eq, equality_residual(mj, d.qpos, d.ten_length, mj.qpos0, mj.tendon_length0))
    theirs = steps / elapsed
    over = f"{ours_over:.1e} / {theirs_over:.1e}" if limited else ""
    eq = "" if ours_eq is None else f"{ours_eq:.1e} / {theirs_eq:.1e}"
    return finite, over, eq, ours, theirs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = ["| model | loads | nq / nv / nu | qacc error vs MuJoCo | 2 s finite | tendon limit overshoot (m), sinew / MuJoCo | equality residual, sinew / MuJoCo | sinew steps/s | MuJoCo steps/s |",
            "|---|---|---|---|---|---|---|---|---|"]
    for path in sorted(glob.glob(os.path.join(SUITE, "*.xml"))):
        name = os.path.basename(path)[:-4]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                m = sinew.Model.from_mjcf(path)
            except sinew.ModelError as e:
                reason = str(e).split(": ", 1)[1]
                rows.append(f"| {name} | no: {reason} | | | | | | | |")
                continue
        err = qacc_error(m, mujoco.MjModel.from_xml_path(path))
        finite, over, eq, ours, theirs = rollout(m, path)
        rows.append(f"| {name} | yes | {m.nq} / {m.nv} / {m.nu} | {err:.1e} | {'yes' if finite else 'no'} | {over} | {eq} | {ours:,.0f} | {theirs:,.0f} |")
    loaded = sum(" | yes | " in r for r in rows)
    note = ("The dog's inertias come from its meshes; MuJoCo diagonalises them to about 1e-8 (its eigen-solver's "
            "tolerance on near-equal moments), which is its qacc error here; with sinew's inertias given to MuJoCo the "
            "accelerations agree to 1e-11 (tests/python/test_dm_control_models.py).")
    text = "\n".join([f"dm_control's suite: {loaded} of {len(rows) - 2} files load.", "", *rows, "", note, ""])
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write("# dm_control's suite models beside MuJoCo\n\n`python benches/dm_control_models.py --out results/dm_control_models.md`\n\n" + text)


if __name__ == "__main__":
    main()
