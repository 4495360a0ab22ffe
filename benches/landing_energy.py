"""The largest energy a single step adds to an 8-link chain (free root, hinges limited to ±60°)
thrown at the floor with seeded random velocities, per constraint mode, integrator, time step and
with limits on or off: a landing should never add energy (no actuators, no restitution). E is
T + U (`Sim.energy`); H = E + (h/2) g·P is the energy semi-implicit Euler keeps (P the linear
momentum), which its steps with contacts are bounded by (`integrate::energy_bound`). Then how
often the bound scales the velocities on gymnasium's floors (3000 steps of seeded random
controls from each model's reference state).

    python benches/landing_energy.py > results/landing_energy.md
"""

import numpy as np

import sinew
from sinew.tasks import ASSETS


def chain(n=8, dt=0.01):
    body, close = "", ""
    for i in range(n):
        joint = "<freejoint/>" if i == 0 else "<joint type='hinge' axis='0 1 0' range='-60 60' limited='true'/>"
        body += f"<body name='b{i}' pos='{'0 0 0.5' if i == 0 else '0.2 0 0'}'>{joint}<geom type='capsule' fromto='0 0 0 0.2 0 0' size='0.03'/>"
        close += "</body>"
    return (f"<mujoco><option timestep='{dt}'/><worldbody><geom type='plane' size='5 5 .1'/>{body}{close}</worldbody>"
            "<sensor><subtreelinvel body='b0'/></sensor></mujoco>")


def energies(m, s):
    """E = T + U, and H = E + (h/2) g·P."""
    e = s.energy.sum()
    momentum = m.body_mass.sum() * s.sensordata[:3]
    return e, e + 0.5 * m.timestep * np.dot(m.gravity, momentum)


def main():
    print("| mode | integrator | dt | limits | largest gain of E in one step (J) | at step | largest gain of H in a step with contacts (J) | E at start (J) |")
    print("|---|---|---|---|---|---|---|---|")
    for mode in ["acceleration", "velocity"]:
        for integrator in ["Euler", "leapfrog"]:
            for dt in [0.01, 0.002]:
                for limit in [True, False]:
                    m = sinew.Model.from_mjcf_string(chain(dt=dt)).with_options(constraint_mode=mode, integrator=integrator, limit=limit)
                    s = sinew.Sim(m)
                    s.qvel[:] = np.random.default_rng(0).normal(0.0, 1.0, m.nv)
                    start, h = energies(m, s)
                    prev = (start, h)
                    worst, worst_h = (0.0, 0), 0.0
                    for k in range(int(1.5 / dt)):
                        s.step()
                        now = energies(m, s)
                        worst = max(worst, (now[0] - prev[0], k))
                        if s.contacts:
                            worst_h = max(worst_h, now[1] - prev[1])
                        prev = now
                    print(f"| {mode} | {integrator} | {dt} | {'on' if limit else 'off'} | {worst[0]:.4f} | {worst[1]} | {worst_h:.2e} | {start:.2f} |")

    print()
    print("| model | integrator | steps with contacts | steps the bound scaled |")
    print("|---|---|---|---|")
    for name in ["hopper", "walker2d", "half_cheetah", "ant", "humanoid"]:
        m = sinew.Model.from_mjcf(f"{ASSETS}/{name}.xml")
        s, rng = sinew.Sim(m), np.random.default_rng(0)
        contact_steps = 0
        for _ in range(3000):
            s.ctrl[:] = rng.uniform(-1, 1, m.nu)
            s.step()
            contact_steps += bool(s.contacts)
        bounded = s.constraint_stats["energy_bounded"]
        print(f"| {name} | {m.integrator} | {contact_steps} | {bounded} ({100 * bounded / contact_steps:.0f}%) |")


if __name__ == "__main__":
    main()
