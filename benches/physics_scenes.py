"""Analytic scenes of the classes sinew was inexact on, each beside MuJoCo on the same MJCF where
MuJoCo can pose it (it has no restitution coefficient): a box just past and short of its friction
angle, a grasp with 1% more and 1% less squeeze than it needs, a box just past and short of its
tipping angle, a torque-free top under RK4, a limited chain landing, a plastic ball, three spheres colliding in sequence and a ball
resting on a ball dropped on the floor (e = 1). The Rust tests in `tests/contact_scenes.rs` and
`tests/conservation.rs` assert the same scenes over every integrator and mode.

    python benches/physics_scenes.py [--out results/physics_scenes.md]
"""

import argparse
import math
import os

import mujoco
import numpy as np

import sinew
from emit import emit

MU = 0.5
SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "scenes")


def scene(name, **values):
    """The MJCF of tests/scenes/NAME (shared with the Rust tests), each {key} replaced by its value."""
    with open(os.path.join(SCENES, name)) as f:
        return f.read().format(**values)


class Sinew:
    name = "sinew"

    def __init__(self, xml, dt, **options):
        self.sim = sinew.Sim(sinew.Model.from_mjcf_string(xml).with_options(timestep=dt, **options))

    def run(self, seconds, each=None):
        steps = int(round(seconds / self.dt))
        for _ in range(steps):
            self.sim.step()
            if each:
                each(self.qpos, self.qvel)

    qpos = property(lambda self: np.array(self.sim.qpos))
    qvel = property(lambda self: np.array(self.sim.qvel))
    time = property(lambda self: self.sim.time)

    def set(self, qvel=None, ctrl=None):
        if qvel is not None:
            self.sim.qvel = np.asarray(qvel, float)
        if ctrl is not None:
            self.sim.ctrl = np.asarray(ctrl, float)


class MuJoCo:
    name = "MuJoCo"

    def __init__(self, xml, dt, **_):
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.model.opt.timestep = dt
        self.data = mujoco.MjData(self.model)

    def run(self, seconds, each=None):
        for _ in range(int(round(seconds / self.model.opt.timestep))):
            mujoco.mj_step(self.model, self.data)
            if each:
                each(self.qpos, self.qvel)

    qpos = property(lambda self: self.data.qpos.copy())
    qvel = property(lambda self: self.data.qvel.copy())
    time = property(lambda self: self.data.time)

    def set(self, qvel=None, ctrl=None):
        if qvel is not None:
            self.data.qvel[:] = qvel
        if ctrl is not None:
            self.data.ctrl[:] = ctrl


def make(engine, name, dt, options=None, **values):
    world = engine(scene(name, **values), dt, **(options or {}))
    world.dt = dt
    return world


def slope(engine, dt, ratio):
    """Acceleration down the slope over Coulomb's g (sin θ − µ cos θ) (the speed after 1 s where
    Coulomb's answer is rest), and the largest yaw rate."""
    theta = ratio * math.atan(MU)
    w = make(engine, "slope_box.xml", dt, gx=9.81 * math.sin(theta), gz=-9.81 * math.cos(theta), mu=MU, z=0.1, size="0.1 0.1 0.1")
    yaw = [0.0]
    w.run(1.0, lambda q, v: yaw.__setitem__(0, max(yaw[0], abs(v[5]))))
    exact = 9.81 * (math.sin(theta) - MU * math.cos(theta))
    a = w.qvel[0] / w.time
    return (f"{a / exact:.4f} of Coulomb's" if exact > 0 else f"{w.qvel[0]:.1e} m/s after 1 s"), f"{yaw[0]:.1e}"


def grasp(engine, dt, ratio):
    w = make(engine, "grasp.xml", dt)
    w.set(ctrl=[ratio * 9.81, ratio * 9.81])
    w.run(1.0)
    exact = -9.81 * max(0.0, 1 - ratio)
    a = w.qvel[4] / w.time
    return f"{a / exact:.4f} of Coulomb's" if exact else f"{w.qvel[4]:.1e} m/s after 1 s"


def tipping(engine, dt, ratio):
    """Largest tilt in 2 s (degrees) and how far the downhill edge slid up to a tilt of 30°."""
    theta = ratio * math.atan(1 / 3)
    w = make(engine, "slope_box.xml", dt, gx=9.81 * math.sin(theta), gz=-9.81 * math.cos(theta), mu=1, z=0.3, size="0.1 0.1 0.3")

    def edge(q):
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, q[3:7])
        return q[0] + rot.reshape(3, 3)[0] @ np.array([0.1, 0.0, -0.3])

    x0, out = edge(w.qpos), {"tilt": 0.0, "slid": 0.0}

    def each(q, v):
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, q[3:7])
        out["tilt"] = max(out["tilt"], math.degrees(math.acos(np.clip(rot[8], -1, 1))))
        if out["tilt"] < 30:
            out["slid"] = max(out["slid"], abs(edge(q) - x0))

    w.run(2.0, each)
    return f"{out['tilt']:.1f}°", f"{out['slid']:.1e} m"


def top(engine, dt):
    """Quaternion error after 5 s against a reference RK4 of q̇ = ½ q ⊗ ω, I ω̇ = −ω × I ω at 1e-4."""
    w = make(engine, "top.xml", dt, joint="free")
    w.set(qvel=[0, 0, 0, 1.0, 0.1, 0.2])
    w.run(5.0)
    return f"{np.abs(w.qpos[3:] - REFERENCE_TOP).max():.1e}"


def euclidean_top(t=5.0, h=1e-4):
    inertia = np.array([1.0, 2.0, 3.0])

    def f(x):
        q, w = x[:4], x[4:]
        dq = 0.5 * np.array([-q[1] * w[0] - q[2] * w[1] - q[3] * w[2], q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                             q[0] * w[1] + q[3] * w[0] - q[1] * w[2], q[0] * w[2] + q[1] * w[1] - q[2] * w[0]])
        return np.concatenate([dq, -np.cross(w, inertia * w) / inertia])

    x = np.array([1.0, 0, 0, 0, 1.0, 0.1, 0.2])
    for _ in range(int(round(t / h))):
        k1 = f(x)
        k2 = f(x + h / 2 * k1)
        k3 = f(x + h / 2 * k2)
        k4 = f(x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x[:4]


def chain_limits(engine, dt):
    """Largest violation of a ±30° limit at the end of any step while the chain lands (degrees)."""
    w = make(engine, "limited_chain.xml", dt)
    worst = [0.0]
    w.run(1.5, lambda q, v: worst.__setitem__(0, max(worst[0], np.degrees(np.abs(q[7:]).max()) - 30)))
    return f"{max(worst[0], 0.0):.1e}°"


def plastic_ball(engine, dt):
    """Largest upward speed of a ball dropped 0.9 m once it has touched the floor (no restitution)."""
    w = make(engine, "ball.xml", dt)
    state = {"touched": False, "up": 0.0}

    def each(q, v):
        state["touched"] |= q[2] < 0.101
        if state["touched"]:
            state["up"] = max(state["up"], v[2])

    w.run(2.0, each)
    return f"{state['up']:.1e} m/s"


def spheres(dt, mode):
    w = make(Sinew, "three_spheres.xml", dt, dict(restitution=1.0, constraint_mode=mode), m1=1, m2=1, m3=1)
    w.set(qvel=np.r_[1.0, np.zeros(17)])
    w.run(0.5)
    v = w.qvel[[0, 6, 12]]
    return f"({v[0]:.3f}, {v[1]:.3f}, {v[2]:.3f})", f"{0.5 * (v ** 2).sum() / 0.5:.4f}", f"{v.sum() - 1:.0e}"


def stack(dt, mode):
    w = make(Sinew, "ball_on_ball.xml", dt, dict(restitution=1.0, constraint_mode=mode))
    best = {"top": 0.0}
    w.run(1.6, lambda q, v: best.__setitem__("top", max(best["top"], q[9])))
    return f"{best['top'] - 0.5:.3f} m"


def main():
    global REFERENCE_TOP
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the tables here (Markdown)")
    args = parser.parse_args()
    REFERENCE_TOP = euclidean_top()
    lines = ["<!-- python benches/physics_scenes.py --out results/physics_scenes.md -->",
             "| scene | dt | sinew (pyramid, acceleration mode) | MuJoCo (defaults) |", "|---|---|---|---|"]
    for dt in (0.002, 0.01):
        for ratio in (1.005, 0.99):
            (sa, sy), (ma, my) = slope(Sinew, dt, ratio), slope(MuJoCo, dt, ratio)
            lines.append(f"| box on a slope {ratio} × its friction angle (µ = 0.5): acceleration; largest yaw rate | {dt} | {sa}; {sy} rad/s | {ma}; {my} rad/s |")
        for ratio in (1.01, 0.99):
            lines.append(f"| grasp squeezed {ratio} × what holding needs: the box's acceleration | {dt} | {grasp(Sinew, dt, ratio)} | {grasp(MuJoCo, dt, ratio)} |")
        for ratio in (1.01, 0.99):
            (st, ss), (mt, ms) = tipping(Sinew, dt, ratio), tipping(MuJoCo, dt, ratio)
            lines.append(f"| box {ratio} × its tipping angle (µ = 1): tilt in 2 s; edge slid before 30° | {dt} | {st}; {ss} | {mt}; {ms} |")
        lines.append(f"| torque-free top (I = 1, 2, 3), RK4: quaternion error after 5 s | {dt} | {top(Sinew, dt)} | {top(MuJoCo, dt)} |")
        lines.append(f"| 10-link chain with ±30° limits landing: worst limit violation at a step's end | {dt} | {chain_limits(Sinew, dt)} | {chain_limits(MuJoCo, dt)} |")
        lines.append(f"| ball dropped 0.9 m, no restitution: largest upward speed after touching | {dt} | {plastic_ball(Sinew, dt)} | {plastic_ball(MuJoCo, dt)} |")
    lines += ["", "MuJoCo has no restitution coefficient; sinew alone, e = 1:", "",
              "| scene | dt | constraint mode | result |", "|---|---|---|---|"]
    for dt in (0.002, 0.01):
        for mode in ("acceleration", "velocity"):
            v, ke, p = spheres(dt, mode)
            lines.append(f"| three spheres 1 mm apart, the first at 1 m/s: velocities; kinetic energy kept; momentum error | {dt} | {mode} | {v}; {ke}; {p} |")
            lines.append(f"| 1 kg ball resting on a 3 kg ball, dropped 1 m: the small ball's rise (2v: 4 m) | {dt} | {mode} | {stack(dt, mode)} |")
    emit("\n".join(lines) + "\n", args.out)


if __name__ == "__main__":
    main()
