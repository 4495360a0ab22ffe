"""Angular momentum in free flight: bodies in zero gravity with contacts off, driven by internal
motor torques only, so their angular momentum should stay where it starts (zero). It is measured
with MuJoCo's `subtree_angmom` on each engine's states.

- a two-link free body whose second link has two hinges with ±10° limits (Euler), random controls
  for 30 s, at three timesteps and in sinew's two constraint modes, beside MuJoCo;
- gymnasium's humanoid (an RK4 model), random controls, limits on and off, beside MuJoCo;
- the same humanoid switched to Euler (as sinew's constrained steps are), limits on, 10 s at three
  timesteps in both constraint modes, beside MuJoCo's Euler;
- the humanoid, RK4 and switched to Euler, limits on, 10 s: the change of angular momentum
  summed over each kind of step (free of rows, with rows, with an impact solve), which shows the
  drift coming from the first-order steps;
- along the two-link body's acceleration-level trajectory (dt = 3e-3), each constrained step
  redone from the same state by velocity-level time stepping: how much angular momentum (along
  the current momentum) the acceleration-level step adds beyond it, for steps with and without an
  impact solve.

    python benches/free_flight.py [--out results/free_flight.md]
"""

import argparse
import os
import warnings

import mujoco
import numpy as np

import sinew
from sinew.tasks import ASSETS

TWO_LINK = """<mujoco><option gravity="0 0 0" timestep="{dt}"/><worldbody>
<body name="a" pos="0 0 1"><freejoint/><geom type="capsule" fromto="0 0 0 .3 0 0" size=".05"/>
  <body name="b" pos=".3 0 0">
    <joint name="h1" type="hinge" axis="0 1 0" range="-10 10" limited="true" damping="1" armature=".02"/>
    <joint name="h2" type="hinge" axis="0 0 1" range="-10 10" limited="true" damping="1" armature=".02"/>
    <geom type="capsule" fromto="0 0 0 .3 0 .1" size=".05"/></body></body></worldbody>
<actuator><motor joint="h1" gear="20"/><motor joint="h2" gear="20"/></actuator></mujoco>"""


class Momentum:
    """Angular momentum of the whole tree about its com, by MuJoCo, at a (qpos, qvel): its
    magnitude (a call) or the vector (`vector`)."""

    def __init__(self, mj):
        self.m, self.d = mj, mujoco.MjData(mj)

    def vector(self, qpos, qvel):
        self.d.qpos[:], self.d.qvel[:] = qpos, qvel
        mujoco.mj_forward(self.m, self.d)
        mujoco.mj_subtreeVel(self.m, self.d)
        return self.d.subtree_angmom[1].copy()

    def __call__(self, qpos, qvel):
        return float(np.linalg.norm(self.vector(qpos, qvel)))


def drift(sinew_model, mj, seconds, every):
    """|L| at the end of `seconds` of random controls (a new one every `every` steps), sinew and
    MuJoCo from the same controls; sinew's is 'diverged at t' when it diverges."""
    steps = int(round(seconds / mj.opt.timestep))
    measure = Momentum(mj)
    sim, d = sinew.Sim(sinew_model), mujoco.MjData(mj)
    rng = np.random.default_rng(1)
    ours = None
    for k in range(steps):
        if k % every == 0:
            c = rng.uniform(-1, 1, mj.nu)
            d.ctrl[:] = c
            sim.ctrl = c
        mujoco.mj_step(mj, d)
        if ours is None:
            try:
                sim.step(1)
            except sinew.SimulationError:
                ours = f"diverged at t = {k * mj.opt.timestep:.1f} s"
    return ours or f"{measure(sim.qpos, sim.qvel):.3f}", f"{measure(d.qpos, d.qvel):.3f}"


def same_state(xml, seconds):
    """Along an acceleration-level trajectory, each constrained step redone from its start state
    with velocity-level time stepping: per kind of step (with or without an impact solve), the
    count, the summed difference of the end angular momenta along the start's, and the largest
    difference of end velocities."""
    mj = mujoco.MjModel.from_xml_string(xml)
    momentum = Momentum(mj).vector

    m = sinew.Model.from_mjcf_string(xml)
    sim, probe = sinew.Sim(m), sinew.Sim(m.with_options(constraint_mode="velocity"))
    rng = np.random.default_rng(1)
    out = {"with an impact solve": [0, 0.0, 0.0], "without": [0, 0.0, 0.0]}
    for k in range(int(round(seconds / mj.opt.timestep))):
        if k % 10 == 0:
            sim.ctrl = rng.uniform(-1, 1, m.nu)
        start, impacts = sim.get_state(), sim.constraint_stats["impacts"]
        l0 = momentum(sim.qpos, sim.qvel)
        sim.step(1)
        if sim.constraint_stats["rows"] == 0:
            continue
        probe.set_state(start)
        probe.step(1)
        row = out["with an impact solve" if sim.constraint_stats["impacts"] > impacts else "without"]
        row[0] += 1
        row[1] += (momentum(sim.qpos, sim.qvel) - momentum(probe.qpos, probe.qvel)) @ (l0 / max(np.linalg.norm(l0), 1e-300))
        row[2] = max(row[2], float(np.abs(sim.qvel - probe.qvel).max()))
    return out


def by_step_kind(xml, seconds):
    """Along `seconds` of random controls: per kind of step (no rows, rows, rows and an impact
    solve; a post-stabilisation projection marked), the count and the summed change of angular
    momentum (a vector); and |L| at the end."""
    mj = mujoco.MjModel.from_xml_string(xml)
    momentum = Momentum(mj).vector

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = sinew.Model.from_mjcf_string(xml).with_options(gravity=[0, 0, 0], contact=False)
    sim = sinew.Sim(m)
    rng = np.random.default_rng(1)
    out = {}
    for k in range(int(round(seconds / mj.opt.timestep))):
        if k % 10 == 0:
            sim.ctrl = rng.uniform(-1, 1, m.nu)
        before, l0 = dict(sim.constraint_stats), momentum(sim.qpos, sim.qvel)
        sim.step(1)
        after = sim.constraint_stats
        kind = ("with rows" if after["rows"] else "without rows") + (", impact solve" if after["impacts"] > before["impacts"] else "") \
            + (", projected" if after["projections"] > before["projections"] else "")
        row = out.setdefault(kind, [0, np.zeros(3)])
        row[0] += 1
        row[1] += momentum(sim.qpos, sim.qvel) - l0
    return out, float(np.linalg.norm(momentum(sim.qpos, sim.qvel)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["| model | dt | sinew configuration | sinew \\|L\\| | MuJoCo \\|L\\| |", "|---|---|---|---|---|"]
    for dt in (3e-3, 1e-3, 3e-4):
        xml = TWO_LINK.format(dt=dt)
        mj = mujoco.MjModel.from_xml_string(xml)
        for mode in ("acceleration", "velocity"):
            m = sinew.Model.from_mjcf_string(xml).with_options(constraint_mode=mode)
            ours, theirs = drift(m, mj, 30.0, max(1, round(0.03 / dt)))
            lines.append(f"| two links, 30 s | {dt:g} | {mode} | {ours} | {theirs} |")
            print(lines[-1], flush=True)
    path = os.path.join(ASSETS, "humanoid.xml")
    mj = mujoco.MjModel.from_xml_path(path)
    mj.opt.gravity[:] = 0
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    for limit in (True, False):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m = sinew.Model.from_mjcf(path).with_options(gravity=[0, 0, 0], contact=False, limit=limit)
        ours, theirs = drift(m, mj, 33.0, 10)
        lines.append(f"| humanoid, 33 s | {mj.opt.timestep:g} | limits {'on' if limit else 'off'} | {ours} | {theirs} |")
        print(lines[-1], flush=True)
    euler = open(path).read().replace('integrator="RK4"', 'integrator="Euler"')
    for dt in (3e-3, 1e-3, 3e-4):
        xml = euler.replace('timestep="0.003"', f'timestep="{dt}"')
        mj = mujoco.MjModel.from_xml_string(xml)
        mj.opt.gravity[:] = 0
        mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
        for mode in ("acceleration", "velocity"):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                m = sinew.Model.from_mjcf_string(xml).with_options(gravity=[0, 0, 0], contact=False, constraint_mode=mode)
            ours, theirs = drift(m, mj, 10.0, max(1, round(0.03 / dt)))
            lines.append(f"| humanoid switched to Euler, 10 s | {dt:g} | limits on, {mode} | {ours} | {theirs} |")
            print(lines[-1], flush=True)
    lines += ["", "| humanoid, limits on, 10 s | kind of step | steps | Σ ΔL (vector) | \\|L\\| at the end |", "|---|---|---|---|---|"]
    for integrator in ("RK4", "Euler"):
        xml = open(path).read().replace('integrator="RK4"', f'integrator="{integrator}"')
        kinds, end = by_step_kind(xml, 10.0)
        for kind, (n, dl) in sorted(kinds.items()):
            lines.append(f"| {integrator} | {kind} | {n} | ({dl[0]:+.2f}, {dl[1]:+.2f}, {dl[2]:+.2f}) | {end:.2f} |")
            print(lines[-1], flush=True)
    lines += ["", "| two links, dt = 0.003, 20 s of constrained steps | steps | Σ (L_acceleration − L_velocity) · L̂ | max \\|Δq̇\\| |",
              "|---|---|---|---|"]
    for kind, (n, gain, dv) in same_state(TWO_LINK.format(dt=3e-3), 20.0).items():
        lines.append(f"| {kind} | {n} | {gain:+.4f} | {dv:.1e} |")
        print(lines[-1], flush=True)
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/free_flight.py --out {args.out} -->\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
