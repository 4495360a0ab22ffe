"""Many touching bodies at one island: a tower of 10 cubes on the floor, 10 s simulated, sinew's
wall time (both friction models, dt 0.002 and 0.01) beside MuJoCo's on the same MJCF, with how
the solves went and how far the top cube moved (a tower at rest should not move).

    python benches/tower.py [--out results/tower.md]
"""

import argparse
import time

import mujoco
import numpy as np

import sinew
from emit import emit

CUBES = 10
SIDE = 0.1  # half size


def mjcf(dt):
    cubes = "".join(
        f'<body pos="0 0 {SIDE + 2 * SIDE * k + 1e-4 * k}"><freejoint/><geom type="box" size="{SIDE} {SIDE} {SIDE}" mass="1"/></body>'
        for k in range(CUBES)
    )
    return (f'<mujoco><option timestep="{dt}"/><worldbody><geom type="plane" size="5 5 0.1"/>{cubes}'
            "</worldbody></mujoco>")


def sinew_run(dt, friction, seconds=10.0):
    m = sinew.Model.from_mjcf_string(mjcf(dt)).with_options(friction=friction)
    sim = sinew.Sim(m)
    top0 = sim.qpos[-7:-4].copy()
    start = time.perf_counter()
    sim.step(int(round(seconds / dt)))
    wall = time.perf_counter() - start
    st = sim.constraint_stats
    drift = np.linalg.norm(sim.qpos[-7:-4] - top0)
    return wall, st, drift


def mujoco_run(dt, seconds=10.0):
    m = mujoco.MjModel.from_xml_string(mjcf(dt))
    d = mujoco.MjData(m)
    top0 = d.qpos[-7:-4].copy()
    start = time.perf_counter()
    for _ in range(int(round(seconds / dt))):
        mujoco.mj_step(m, d)
    return time.perf_counter() - start, np.linalg.norm(d.qpos[-7:-4] - top0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the table here (Markdown)")
    args = parser.parse_args()
    lines = [
        "<!-- python benches/tower.py --out results/tower.md -->",
        f"A tower of {CUBES} cubes (0.2 m, 1 kg) on the floor, 10 s simulated, one thread.",
        "",
        "| dt | friction | sinew wall time | Lemke pivots / PGS fallbacks / inexact solves | top cube moved | MuJoCo wall time | MuJoCo's top cube moved | sinew / MuJoCo |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for dt in (0.002, 0.01):
        mj_wall, mj_drift = mujoco_run(dt)
        for friction in ("pyramid", "seed"):
            wall, st, drift = sinew_run(dt, friction)
            lines.append(f"| {dt} | {friction} | {wall:.2f} s | {st['pivots']} / {st['fallback_pgs']} / {st['inexact']} | "
                         f"{drift:.1e} m | {mj_wall:.2f} s | {mj_drift:.1e} m | {wall / mj_wall:.0f}× |")
    emit("\n".join(lines) + "\n", args.out)


if __name__ == "__main__":
    main()
