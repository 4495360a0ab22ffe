"""The largest energy a single step adds to an 8-link chain (free root, hinges limited to ±60°)
thrown at the floor with seeded random velocities, per constraint mode, integrator, time step and
with limits on or off: a landing should never add energy (no actuators, no restitution).

    python benches/landing_energy.py
"""

import numpy as np

import sinew


def chain(n=8, dt=0.01):
    body, close = "", ""
    for i in range(n):
        joint = "<freejoint/>" if i == 0 else "<joint type='hinge' axis='0 1 0' range='-60 60' limited='true'/>"
        body += f"<body pos='{'0 0 0.5' if i == 0 else '0.2 0 0'}'>{joint}<geom type='capsule' fromto='0 0 0 0.2 0 0' size='0.03'/>"
        close += "</body>"
    return f"<mujoco><option timestep='{dt}'/><worldbody><geom type='plane' size='5 5 .1'/>{body}{close}</worldbody></mujoco>"


def energy(m, s):
    """Kinetic (½ q̇ᵀ M q̇) plus gravitational potential energy."""
    mass_matrix = s.constraint_system()["M"]
    coms = s.xpos[1:] + np.einsum("bij,bj->bi", s.xmat[1:], m.body_ipos[1:])
    return 0.5 * s.qvel @ mass_matrix @ s.qvel + 9.81 * np.dot(m.body_mass[1:], coms[:, 2])


def main():
    print("| mode | integrator | dt | limits | largest gain in one step (J) | at step | energy at start (J) |")
    print("|---|---|---|---|---|---|---|")
    for mode in ["acceleration", "velocity"]:
        for integrator in ["Euler", "leapfrog"]:
            for dt in [0.01, 0.002]:
                for limit in [True, False]:
                    m = sinew.Model.from_mjcf_string(chain(dt=dt)).with_options(constraint_mode=mode, integrator=integrator, limit=limit)
                    s = sinew.Sim(m)
                    s.qvel[:] = np.random.default_rng(0).normal(0.0, 1.0, m.nv)
                    start = prev = energy(m, s)
                    worst = (0.0, 0)
                    for k in range(int(1.5 / dt)):
                        s.step()
                        e = energy(m, s)
                        worst = max(worst, (e - prev, k))
                        prev = e
                    print(f"| {mode} | {integrator} | {dt} | {'on' if limit else 'off'} | {worst[0]:.4f} | {worst[1]} | {start:.2f} |")


if __name__ == "__main__":
    main()
