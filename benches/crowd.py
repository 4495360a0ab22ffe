"""A crowd in one world: N copies of gymnasium's humanoid (passive: no actuators or tendons)
dropped together onto the floor in two layers, dt 0.005, one thread; sinew's wall time beside
MuJoCo's on the same MJCF, with the contacts at the end and sinew's fallback solves.

    python benches/crowd.py [--humanoids 22] [--steps 400] [--rounds 3] [--out results/crowd.md]

The scene is written from gymnasium's humanoid.xml (every name prefixed per copy); it stands in
for MuJoCo's own 22-humanoid model, which its Python package does not ship. sinew keeps at most
128 contacts a step (the deepest; docs/physics.md): where the pile has more, as this one does by
the end, the two do not solve the same problem.
"""

import argparse
import copy
import time
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

import sinew
from sinew.tasks import ASSETS

from emit import emit, invocation


def scene(n: int) -> str:
    """gymnasium's humanoid n times over: two layers of up to 11, 0.7 m apart."""
    root = ET.parse(f"{ASSETS}/humanoid.xml").getroot()
    for tag in ("actuator", "tendon", "contact", "sensor", "keyframe"):
        for e in root.findall(tag):
            root.remove(e)
    root.find("option").attrib.update(timestep="0.005")
    world = root.find("worldbody")
    torso = world.find("body")
    world.remove(torso)
    for i in range(n):
        copy_ = copy.deepcopy(torso)
        for e in copy_.iter():
            if "name" in e.attrib:
                e.set("name", f"h{i}_{e.get('name')}")
        row, layer = i % 11, i // 11
        copy_.set("pos", f"{0.7 * (row - 5)} {0.35 * layer} {1.4 + 1.2 * layer}")
        world.append(copy_)
    return ET.tostring(root, encoding="unicode")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--humanoids", type=int, default=22)
    ap.add_argument("--steps", type=int, default=400)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    xml = scene(args.humanoids)
    times = {"sinew": [], "mujoco": []}
    for _ in range(args.rounds):
        sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
        t = time.perf_counter()
        sim.step(args.steps)
        times["sinew"].append(time.perf_counter() - t)
        mj = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(mj)
        t = time.perf_counter()
        mujoco.mj_step(mj, d, args.steps)
        times["mujoco"].append(time.perf_counter() - t)
    stats = sim.constraint_stats
    ours, theirs = np.median(times["sinew"]), np.median(times["mujoco"])
    lines = ["| scene | steps | sinew wall time (s) | MuJoCo (s) | sinew / MuJoCo | contacts at the end, sinew / MuJoCo | sinew fallback solves |",
             "|---|---|---|---|---|---|---|",
             f"| {args.humanoids} humanoids dropped together, dt 0.005, 1 thread | {args.steps} | {ours:.2f} | {theirs:.2f} | "
             f"{ours / theirs:.1f}× | {len(sim.contacts)} / {d.ncon} | {stats['fallback_pgs'] + stats['fallback_zero']} |"]
    emit("\n".join([invocation(), *lines]) + "\n", args.out)


if __name__ == "__main__":
    main()
