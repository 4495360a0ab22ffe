"""Numerical-stability stress suite: each case must end finite and bounded, or report exactly what
broke (a SimulationError naming the array, index and time, or a flagged world).

    python benches/stress.py [--quick] [--out results/stress.md]
"""

import argparse
import os
import re
import time
import warnings

import numpy as np

import sinew
from sinew.tasks import ASSETS


def chain(n, dt=1e-3, ratio=1.0):
    """n hinges about alternating axes perpendicular to the links; adjacent links' masses differ by
    `ratio`."""
    body = ""
    for i in range(n):
        axis = "0 1 0" if i % 2 == 0 else "0 0 1"
        mass = ratio ** (i % 2)
        body += f'<body pos="{0 if i == 0 else 0.2} 0 0"><joint type="hinge" axis="{axis}"/>'
        body += f'<geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" mass="{mass}"/>'
    return (f'<mujoco><option timestep="{dt}"><flag contact="disable"/></option>'
            f'<worldbody>{body}{"</body>" * n}</worldbody></mujoco>')


def run(sim, steps):
    """Steps; returns (ok, detail)."""
    try:
        sim.step(steps)
    except sinew.SimulationError as e:
        return False, str(e)
    return bool(np.isfinite(sim.get_state()).all()), f"max |qvel| {np.abs(sim.qvel).max():.3g}"


def chains(quick):
    rows = []
    for n in (2, 10, 50, 200) if not quick else (2, 50):
        sim = sinew.Sim(sinew.Model.from_mjcf_string(chain(n)))
        sim.qvel[:] = 0.5
        ok, d = run(sim, 10_000 if not quick else 2000)
        rows.append((f"chain of {n} links, 10⁴ steps at dt = 1e-3", ok, d))
    for ratio in (10.0, 100.0, 1000.0):
        sim = sinew.Sim(sinew.Model.from_mjcf_string(chain(20, ratio=ratio)))
        sim.qvel[:] = 0.5
        ok, d = run(sim, 10_000 if not quick else 2000)
        rows.append((f"20-link chain, adjacent mass ratio 1:{ratio:g}", ok, d))
    return rows


def timesteps(quick):
    rows = []
    for dt in (1e-4, 1e-3, 1e-2, 5e-2):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = sinew.Model.from_mjcf(os.path.join(ASSETS, "humanoid.xml")).with_options(timestep=dt)
        sim = sinew.Sim(m)
        rng = np.random.default_rng(0)
        ok, d = True, ""
        t0 = time.perf_counter()
        for _ in range(int(min(2.0, 2000 * dt) / dt) // 10):
            sim.ctrl[:] = rng.uniform(-0.4, 0.4, m.nu)
            ok, d = run(sim, 10)
            if not ok:
                break
        rows.append((f"humanoid with floor, random controls, dt = {dt:g}", ok, d + f", {time.perf_counter() - t0:.1f} s wall"))
    return rows


def free_flight(quick):
    """The humanoid in zero gravity with contacts off, a random control every 10 steps: with its
    joints held at their limits, semi-implicit Euler's momentum error grows (see docs/physics.md, known
    gaps); without limits it stays small."""
    rows = []
    seconds = 60.0 if not quick else 3.0
    for limit in (True, False):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = sinew.Model.from_mjcf(os.path.join(ASSETS, "humanoid.xml")).with_options(
                gravity=[0, 0, 0], contact=False, limit=limit)
        sim = sinew.Sim(m)
        rng = np.random.default_rng(7)
        ok, d = True, ""
        for _ in range(int(seconds / m.timestep) // 10):
            sim.ctrl[:] = rng.uniform(-1, 1, m.nu)
            ok, d = run(sim, 10)
            if not ok:
                break
        rows.append((f"humanoid in free flight (zero gravity, contacts off), random controls, {seconds:g} s, "
                     f"limits {'on' if limit else 'off'}", ok, d))
    return rows


def pd_sweep():
    """PD servo on a free hinge of inertia I: semi-implicit Euler is stable for h²K/I + 2hD/I < 4."""
    rows = []
    h, inertia = 0.01, 0.1
    xml = f"""<mujoco><option timestep="{h}" gravity="0 0 0"/><worldbody><body><joint name="j" axis="0 0 1" armature="{inertia}"/>
    <geom type="sphere" size="0.001" mass="1e-9"/></body></worldbody>
    <actuator><motor joint="j" gear="1" ctrllimited="false"/></actuator></mujoco>"""
    for factor in (0.5, 0.9, 1.1, 2.0, 10.0):
        k = factor * 4 * inertia / h**2 * 0.8  # 80% of the budget on stiffness,
        d = factor * 4 * inertia / (2 * h) * 0.2  # 20% on damping
        m = sinew.Model.from_mjcf_string(xml).with_options(pd_gains=(k, d))
        sim = sinew.Sim(m)
        sim.qpos[:] = 0.1  # target 0 (ctrl)
        ok, detail = run(sim, 1000)
        bounded = ok and abs(sim.qpos[0]) <= 0.1 + 1e-12
        expect = "bounded" if factor < 1 else "flagged"
        got = "bounded" if bounded else "flagged"
        rows.append((f"PD at {factor:g}× the stability bound (expect {expect})", got == expect,
                     f"{got}: {detail[:90]}"))
    return rows


def ragdolls(n, seconds):
    """n humanoids (no actuators) dropped in a pile on the floor."""
    src = open(os.path.join(ASSETS, "humanoid.xml")).read()
    torso = src[src.index('<body name="torso"'):src.index("</worldbody>")]
    floor = re.search(r'<geom condim="3"[^>]*name="floor"[^>]*/>', src).group(0)
    head = src[:src.index("<worldbody>")]
    bodies = []
    for i in range(n):
        b = re.sub(r'name="([^"]+)"', lambda mt: f'name="{mt.group(1)}_{i}"', torso)
        # 3 × 3 per layer, 1.2 m apart (no initial overlap), layers 1.6 m apart, dropped together
        x, y, z = (i % 3) * 1.2 - 1.2, ((i // 3) % 3) * 1.2 - 1.2, 1.4 + 1.6 * (i // 9)
        b = b.replace('<body name="torso_%d" pos="0 0 1.4">' % i, f'<body name="torso_{i}" pos="{x} {y} {z}">', 1)
        bodies.append(b)
    xml = head + "<worldbody>" + floor + "".join(bodies) + "</worldbody></mujoco>"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = sinew.Model.from_mjcf_string(xml).with_options(integrator="Euler")
    sim = sinew.Sim(m)
    t0 = time.perf_counter()
    ok, detail = True, ""
    pen = 0.0
    for _ in range(int(seconds / m.timestep) // 10):
        ok, detail = run(sim, 10)
        pen = max([pen] + [-c["dist"] for c in sim.contacts])
        if not ok:
            break
    st = sim.constraint_stats
    return [(f"{n} humanoid ragdolls dropped in a pile, {seconds:g} s", ok,
             f"{detail}; max penetration {pen * 1e3:.1f} mm; PGS fallbacks {st['fallback_pgs']}, inexact {st['inexact']}; "
             f"{time.perf_counter() - t0:.0f} s wall")]


def million_steps(quick):
    import gymnasium as gym

    rows = []
    total = 10**6 if not quick else 10**4
    for name in ("Hopper", "Walker2d", "HalfCheetah", "Ant", "Humanoid"):
        env = gym.make_vec(f"sinew/{name}-v0", num_envs=64, vectorization_mode="vector_entry_point", num_threads=2)
        env.reset(seed=0)
        low, high = env.single_action_space.low, env.single_action_space.high
        rng = np.random.default_rng(0)
        diverged, bad = 0, 0
        t0 = time.perf_counter()
        for _ in range(total // 64):
            # random maximum-torque actions: each motor at one end of its range
            a = np.where(rng.random((64, len(low))) < 0.5, low, high)
            obs, r, term, trunc, info = env.step(a)
            # an entry no env reports (every env reset at once) is left out, as SyncVectorEnv does
            if "sim_diverged" in info:
                diverged += int(info["sim_diverged"][info["_sim_diverged"]].sum())
            bad += int((~np.isfinite(obs)).any(axis=1).sum() + (~np.isfinite(r)).sum())
        rows.append((f"{name}: {total:,} env steps of random maximum-torque actions", bad == 0,
                     f"non-finite obs/rewards {bad}, worlds diverged and reset {diverged}, {time.perf_counter() - t0:.0f} s wall"))
    return rows


def painleve():
    import math

    rows = []
    for mode in ("acceleration", "velocity"):
        th, half = math.atan(2.0), 0.5
        xml = f"""<mujoco><option timestep="0.01"/><worldbody><geom type="plane" size="10 10 .1" friction="1.5"/>
        <body><freejoint/><geom type="capsule" size="0.01 {half}" friction="1.5" mass="1"/></body></worldbody></mujoco>"""
        sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(constraint_mode=mode, friction="one_tangent"))
        a = math.pi / 2 - th
        sim.qpos[3:7] = [math.cos(a / 2), 0, math.sin(a / 2), 0]
        sim.qpos[2] = 0.01 + half * math.sin(th)
        sim.qvel[0] = -3.0
        ok, d = run(sim, 300)
        rows.append((f"Painlevé rod (tan θ = 2, μ = 1.5), {mode} mode", ok, d))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="smaller cases, for a smoke run")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    parts = (lambda: chains(args.quick), lambda: timesteps(args.quick), lambda: free_flight(args.quick), pd_sweep, painleve,
             lambda: ragdolls(20 if not args.quick else 2, 3.0 if not args.quick else 0.5), lambda: million_steps(args.quick))
    for make in parts:
        part = make()
        for r in part:
            print(f"{'ok ' if r[1] else 'BROKE'} {r[0]}: {r[2]}", flush=True)
        rows += part
    lines = ["| case | result | detail |", "|---|---|---|"] + [f"| {c} | {'ok' if ok else 'broke'} | {d} |" for c, ok, d in rows]
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/stress.py --out {args.out} -->\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
