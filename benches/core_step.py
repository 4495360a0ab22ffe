"""Single-thread steps/s of the constraint-free step: sinew beside MuJoCo on the same MJCF file and
integrator, both stepping inside native code (sinew ``Sim.step(n)``, MuJoCo ``mj_step(nstep=n)``).

Both run with contacts and joint limits switched off (sinew ``with_options(contact=False,
limit=False)``, MuJoCo mjDSBL_CONSTRAINT): the like-for-like constraint-free step. MuJoCo's default
pipeline (with its constraints) is shown for reference.

    python benches/core_step.py [--steps 20000] [--out results/core_step.md]
"""

import argparse
import os
import time
import warnings

import gymnasium
import mujoco
import numpy as np

import sinew

ASSETS = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets")
MODELS = ["inverted_pendulum", "inverted_double_pendulum", "reacher", "swimmer", "hopper", "half_cheetah", "ant", "humanoid"]


def best_rate(fn, steps, repeats=5):
    fn(1000)  # warm-up
    best = 0.0
    for _ in range(repeats):
        t = time.perf_counter()
        fn(steps)
        best = max(best, steps / (time.perf_counter() - t))
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for name in MODELS:
        path = os.path.join(ASSETS, name + ".xml")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sm = sinew.Model.from_mjcf(path)
            mj = mujoco.MjModel.from_xml_path(path)
        mj.opt.density = mj.opt.viscosity = 0.0
        for integrator in ("Euler", "RK4"):
            mj.opt.integrator = getattr(mujoco.mjtIntegrator, "mjINT_EULER" if integrator == "Euler" else "mjINT_RK4")
            sim = sinew.Sim(sm.with_options(integrator=integrator, contact=False, limit=False))
            rng = np.random.default_rng(0)
            ctrl = rng.uniform(-0.1, 0.1, size=sm.nu)
            sim.ctrl[:] = ctrl

            # rollouts of 1000 steps from the reset state: without limits a motor at constant
            # torque spins a joint up without bound
            def run_sinew(n):
                for _ in range(n // 1000):
                    sim.reset()
                    sim.ctrl[:] = ctrl
                    sim.step(1000)

            d = mujoco.MjData(mj)

            def run_mj(n):
                for _ in range(n // 1000):
                    mujoco.mj_resetData(mj, d)
                    d.ctrl[:] = ctrl
                    mujoco.mj_step(mj, d, nstep=1000)

            s_rate = best_rate(run_sinew, args.steps)
            mj.opt.disableflags = 0
            m_rate = best_rate(run_mj, args.steps)
            mj.opt.disableflags = int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
            m_free = best_rate(run_mj, args.steps)
            mj.opt.disableflags = 0
            rows.append((name, integrator, sm.nv, s_rate, m_rate, m_free))
            print(f"{name:26s} {integrator:5s} sinew {s_rate/1e3:9.1f}k  mujoco {m_rate/1e3:9.1f}k  "
                  f"mujoco(no constraints) {m_free/1e3:9.1f}k  ratio {s_rate/m_free:5.2f}", flush=True)
    lines = [
        "| model | integrator | nv | sinew steps/s, constraints off | MuJoCo steps/s, default | MuJoCo, constraints off | sinew / MuJoCo (off) |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, integ, nv, s, m, f in rows:
        lines.append(f"| {name} | {integ} | {nv} | {s:,.0f} | {m:,.0f} | {f:,.0f} | {s/f:.2f}× |")
    table = "\n".join(lines)
    print(table)
    if args.out:
        os.makedirs(os.path.dirname(args.out), exist_ok=True)
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/core_step.py --steps {args.steps} --out {args.out}; mujoco {mujoco.__version__} -->\n")
            f.write(table + "\n")


if __name__ == "__main__":
    main()
