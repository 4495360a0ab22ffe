"""Meshes and height fields beside MuJoCo: single-world steps/s of sinew's `Sim.step(n)` and
MuJoCo's `mj_step` (one thread, the same MJCF, each simulator's own contacts) over 2 s of each
scene, with the deepest penetration either shows (sinew's contacts are exact; MuJoCo's soft), and
sinew's fallback solves. Scenes: ten convex meshes dropped into a bin; dm_control's dog (mesh
masses, capsule contacts) under random controls; dm_control's quadruped walking on random terrain
(its height field filled as its escape task does); example-robot-data's A1 (URDF, meshes and
primitives) under random torques on a bumpy height field; the same A1 on a plane.

    python benches/geometry.py [--out results/geometry.md] [--stills results/stills]

With --stills it also draws the A1 on its terrain and the Panda arm's collision meshes
(A1_terrain.png, Panda.png).
"""

import argparse
import importlib.metadata
import importlib.util
import os
import re
import time
import warnings

import mujoco
import numpy as np

import sinew

SUITE = os.path.join(importlib.util.find_spec("dm_control").submodule_search_locations[0], "suite")
SHARE = str(importlib.metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share"))
A1 = os.path.join(SHARE, "example-robot-data", "robots", "a1_description", "urdf", "a1.urdf")
TESTS = os.path.join(os.path.dirname(__file__), "..", "tests")

FRUSTUM = ("0.1 0 -0.04  0.05 0.08660254 -0.04  -0.05 0.08660254 -0.04  -0.1 0 -0.04  -0.05 -0.08660254 -0.04  "
           "0.05 -0.08660254 -0.04 0.06 0 0.04  0.03 0.05196152 0.04  -0.03 0.05196152 0.04  -0.06 0 0.04  "
           "-0.03 -0.05196152 0.04  0.03 -0.05196152 0.04")
BOX = "-.1 -.05 -.025  .1 -.05 -.025  -.1 .05 -.025  .1 .05 -.025  -.1 -.05 .025  .1 -.05 .025  -.1 .05 .025  .1 .05 .025"


def bin_scene():
    rng = np.random.default_rng(7)
    bodies = ""
    for k in range(10):
        x, y = rng.uniform(-0.15, 0.15, 2)
        q = rng.uniform(-1, 1, 4)
        q /= np.linalg.norm(q)
        mesh = "gem" if k % 2 == 0 else "box"
        bodies += (f'<body pos="{x} {y} {0.3 + 0.25 * k}" quat="{q[0]} {q[1]} {q[2]} {q[3]}"><freejoint/>'
                   f'<geom type="mesh" mesh="{mesh}" mass="0.5"/></body>')
    walls = "".join(f'<geom type="box" pos="{p}" size="{s}"/>' for p, s in [
        ("0.4 0 0.3", "0.05 0.45 0.3"), ("-0.4 0 0.3", "0.05 0.45 0.3"), ("0 0.4 0.3", "0.45 0.05 0.3"), ("0 -0.4 0.3", "0.45 0.05 0.3")])
    return (f'<mujoco><option timestep="0.002"/><asset><mesh name="gem" vertex="{FRUSTUM}"/><mesh name="box" vertex="{BOX}"/>'
            f'</asset><worldbody><light pos="0 0 3"/><geom type="plane" size="5 5 0.1"/>{walls}{bodies}</worldbody></mujoco>')


def bumps(nrow, ncol, seed, scale):
    """Smooth random terrain in [0, 1]: a sum of random bumps."""
    rng = np.random.default_rng(seed)
    y, x = np.meshgrid(np.linspace(-1, 1, nrow), np.linspace(-1, 1, ncol), indexing="ij")
    z = np.zeros((nrow, ncol))
    for _ in range(40):
        cx, cy, w, h = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.02, 0.1) * scale, rng.uniform(0.2, 1.0)
        z += h * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / w ** 2)
    return (z - z.min()) / (z.max() - z.min())


def a1_scene(terrain):
    xml = sinew.urdf_to_mjcf(A1, package_dirs=[SHARE], floating_base=True, motors=True)
    ground = ('<geom type="hfield" hfield="terrain" rgba=".35 .4 .3 1"/>' if terrain else '<geom type="plane" size="5 5 0.1"/>')
    xml = xml.replace("<worldbody>", f'<worldbody><light pos="0 0 3"/>{ground}', 1)
    if terrain:
        xml = xml.replace("<asset>", '<asset><hfield name="terrain" nrow="61" ncol="61" size="3 3 0.08 0.1"/>', 1)
    return re.sub(r'(<body name="[^"]*") pos="[^"]*"', r'\1 pos="0 0 0.45"', xml, count=1)


def scenes():
    """(name, sinew model, MuJoCo model, elevations to set, torque scale)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sinew.ModelWarning)
        out = []
        xml = bin_scene()
        out.append(("ten meshes in a bin", sinew.Model.from_mjcf_string(xml), mujoco.MjModel.from_xml_string(xml), None, 0.0))
        dog = os.path.join(SUITE, "dog.xml")
        out.append(("dm_control dog", sinew.Model.from_mjcf(dog), mujoco.MjModel.from_xml_path(dog), None, 1.0))
        quad = os.path.join(SUITE, "quadruped.xml")
        out.append(("dm_control quadruped, terrain", sinew.Model.from_mjcf(quad), mujoco.MjModel.from_xml_path(quad), bumps(201, 201, 1, 0.1), 1.0))
        for terrain in (True, False):
            xml = a1_scene(terrain)
            name = "A1 (URDF) on a height field" if terrain else "A1 (URDF) on a plane"
            out.append((name, sinew.Model.from_mjcf_string(xml), mujoco.MjModel.from_xml_string(xml), bumps(61, 61, 2, 1.0) if terrain else None, 5.0))
    return out


def run(name, m, mj, elevations, torque):
    if elevations is not None:
        m = m.with_hfield_data(0, elevations)
        mj.hfield_data[:] = elevations.ravel()
    steps = int(round(2.0 / m.timestep))
    lo, hi = (m.actuator_ctrlrange.T if m.nu else (np.zeros(0), np.zeros(0)))
    ctrl = np.clip(np.random.default_rng(0).uniform(-torque, torque, (steps, m.nu)), lo, hi)
    sim, d = sinew.Sim(m), mujoco.MjData(mj)
    deep_s = deep_m = 0.0
    t_s = t_m = 0.0
    for k in range(steps):
        sim.ctrl[:] = ctrl[k]
        t = time.perf_counter()
        sim.step(1)
        t_s += time.perf_counter() - t
        deep_s = max(deep_s, -min((c["dist"] for c in sim.contacts), default=0.0))
        d.ctrl[:] = ctrl[k]
        t = time.perf_counter()
        mujoco.mj_step(mj, d)
        t_m += time.perf_counter() - t
        if d.ncon:
            deep_m = max(deep_m, -float(d.contact.dist[:d.ncon].min()))
    stats = sim.constraint_stats
    return {"name": name, "sinew": steps / t_s, "mujoco": steps / t_m, "deep_m": deep_m, "deep_s": deep_s,
            "fallbacks": stats["fallback_pgs"] + stats["fallback_zero"], "solves": stats["solves"], "finite": bool(np.isfinite(sim.qpos).all())}


def stills(folder):
    import imageio

    name, m, _, elevations, _ = scenes()[3]
    sim = sinew.Sim(m.with_hfield_data(0, elevations))
    for _ in range(150):
        sim.step()
    camera = {"lookat": [sim.qpos[0], sim.qpos[1], 0.15], "distance": 1.6, "azimuth": 135, "elevation": -25}
    imageio.imwrite(os.path.join(folder, "A1_terrain.png"), sim.render(480, 480, camera=camera))
    panda = os.path.join(SHARE, "example-robot-data", "robots", "panda_description", "urdf", "panda.urdf")
    xml = sinew.urdf_to_mjcf(panda, package_dirs=[SHARE])
    xml = xml.replace("<worldbody>", '<worldbody><light pos="1 1 3"/><geom type="plane" size="2 2 0.1" rgba=".5 .5 .55 1"/>', 1)
    xml = re.sub(r'type="mesh" mesh', 'rgba=".9 .9 .92 1" type="mesh" mesh', xml)
    sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
    sim.qpos[:7] = [0.0, -0.5, 0.0, -2.2, 0.0, 1.8, 0.8]
    camera = {"lookat": [0.2, 0.0, 0.45], "distance": 1.7, "azimuth": 150, "elevation": -20}
    imageio.imwrite(os.path.join(folder, "Panda.png"), sim.render(480, 480, camera=camera))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    ap.add_argument("--stills", default=None)
    args = ap.parse_args()
    if args.stills:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", sinew.ModelWarning)
            stills(args.stills)
    rows = [run(*s) for s in scenes()]
    lines = ["| scene | sinew steps/s | MuJoCo steps/s | sinew / MuJoCo | deepest penetration: sinew, MuJoCo (m) | sinew fallback solves |",
             "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['name']} | {r['sinew']:,.0f} | {r['mujoco']:,.0f} | {r['sinew'] / r['mujoco']:.2f} | "
                     f"{r['deep_s']:.1e}, {r['deep_m']:.1e} | {r['fallbacks']} of {r['solves']} |")
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write("# Meshes and height fields beside MuJoCo\n\n`python benches/geometry.py --out results/geometry.md`"
                    " (one thread; single-world `Sim.step` against `mj_step`, 2 s of each scene)\n\n" + text + "\n")


if __name__ == "__main__":
    main()
