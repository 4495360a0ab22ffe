"""Single-thread steps/s of one step: sinew beside MuJoCo on the same MJCF file and integrator,
both stepping inside native code (sinew ``Sim.step(n)``, MuJoCo ``mj_step(nstep=n)``).

First with contacts and joint limits switched off (sinew ``with_options(contact=False,
limit=False)``, MuJoCo mjDSBL_CONSTRAINT): the like-for-like constraint-free step. Then each
simulator's default pipeline, with its constraints: sinew's exact contacts and limits, MuJoCo's soft
ones. Under RK4 sinew's steps with constraint rows are semi-implicit Euler steps (the seed's scheme,
one dynamics evaluation), MuJoCo's are RK4 steps (four, each with its constraint solve).

    python benches/core_step.py [--steps 20000] [--out results/core_step.md]
"""

import argparse
import os
import time
import warnings

import mujoco
import numpy as np

import sinew
from sinew.tasks import ASSETS  # gymnasium's model files: one definition

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
            rng = np.random.default_rng(0)
            ctrl = rng.uniform(-0.1, 0.1, size=sm.nu)

            # rollouts of 1000 steps from the reset state: without limits a motor at constant
            # torque spins a joint up without bound
            def sinew_runner(model):
                sim = sinew.Sim(model)

                def run(n):
                    for _ in range(n // 1000):
                        sim.reset()
                        sim.ctrl[:] = ctrl
                        sim.step(1000)
                return run

            d = mujoco.MjData(mj)

            def run_mj(n):
                for _ in range(n // 1000):
                    mujoco.mj_resetData(mj, d)
                    d.ctrl[:] = ctrl
                    mujoco.mj_step(mj, d, nstep=1000)

            s_free = best_rate(sinew_runner(sm.with_options(integrator=integrator, contact=False, limit=False)), args.steps)
            s_rate = best_rate(sinew_runner(sm.with_options(integrator=integrator)), args.steps)
            mj.opt.disableflags = int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
            m_free = best_rate(run_mj, args.steps)
            mj.opt.disableflags = 0
            m_rate = best_rate(run_mj, args.steps)
            rows.append((name, integrator, sm.nv, s_free, m_free, s_rate, m_rate))
            print(f"{name:26s} {integrator:5s} off: sinew {s_free/1e3:9.1f}k  mujoco {m_free/1e3:9.1f}k  ratio {s_free/m_free:5.2f}  "
                  f"default: sinew {s_rate/1e3:9.1f}k  mujoco {m_rate/1e3:9.1f}k  ratio {s_rate/m_rate:5.2f}", flush=True)
    lines = [
        "| model | integrator | nv | sinew, constraints off | MuJoCo, constraints off | sinew / MuJoCo (off) | sinew, default | MuJoCo, default | sinew / MuJoCo (default) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, integ, nv, sf, mf, s, m in rows:
        lines.append(f"| {name} | {integ} | {nv} | {sf:,.0f} | {mf:,.0f} | {sf/mf:.2f}× | {s:,.0f} | {m:,.0f} | {s/m:.2f}× |")
    table = "\n".join(lines)
    print(table)
    if args.out:
        os.makedirs(os.path.dirname(args.out), exist_ok=True)
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/core_step.py --steps {args.steps} --out {args.out}; mujoco {mujoco.__version__} -->\n")
            f.write(table + "\n")


if __name__ == "__main__":
    main()
