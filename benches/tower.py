"""Many touching bodies at one island: a tower of 10 cubes on the floor, 10 s simulated, sinew's
wall time (both friction models, dt 0.002 and 0.01) beside MuJoCo's on the same MJCF, with how
the solves went and how far the top cube moved (a tower at rest should not move). The two are
timed in turn over rounds, and the medians reported: this machine's speed drifts.

    python benches/tower.py [--rounds 9] [--out results/tower.md]
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
    parser.add_argument("--rounds", type=int, default=9, help="timings of each, alternated (median reported)")
    args = parser.parse_args()
    lines = [
        "<!-- python benches/tower.py --out results/tower.md -->",
        f"A tower of {CUBES} cubes (0.2 m, 1 kg) on the floor, 10 s simulated, one thread; wall times are the medians "
        f"of {args.rounds} rounds, MuJoCo and sinew timed in turn.",
        "",
        "| dt | friction | sinew wall time | Lemke pivots / PGS fallbacks / inexact solves | top cube moved | MuJoCo wall time | MuJoCo's top cube moved | sinew / MuJoCo |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for dt in (0.002, 0.01):
        mj, runs = [], {"pyramid": [], "one_tangent": []}
        for _ in range(args.rounds):
            mj.append(mujoco_run(dt))
            for friction in runs:
                runs[friction].append(sinew_run(dt, friction))
        mj_wall, mj_drift = float(np.median([w for w, _ in mj])), mj[0][1]
        for friction, rs in runs.items():
            wall = float(np.median([w for w, _, _ in rs]))
            _, st, drift = rs[0]
            lines.append(f"| {dt} | {friction} | {wall:.2f} s | {st['pivots']} / {st['fallback_pgs']} / {st['inexact']} | "
                         f"{drift:.1e} m | {mj_wall:.2f} s | {mj_drift:.1e} m | {wall / mj_wall:.1f}× |")
    emit("\n".join(lines) + "\n", args.out)


if __name__ == "__main__":
    main()
