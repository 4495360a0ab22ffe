"""A crowd in one world: N copies of gymnasium's humanoid (passive: no actuators or tendons)
dropped together onto the floor in two layers, dt 0.005, one thread; sinew's wall time beside
MuJoCo's on the same MJCF, with the contacts at the end and sinew's fallback solves.

    python benches/crowd.py [--humanoids 22] [--steps 400] [--rounds 3] [--xml FILE ...] [--alone] [--out results/crowd.md]

The scene is written from gymnasium's humanoid.xml (every name prefixed per copy). MuJoCo's own
22-humanoid model (`model/humanoid/22_humanoids.xml` in MuJoCo's repository, which its Python
package does not ship) is timed as well when given with `--xml`, as is any other file (passive:
zero controls). With `--alone`, each file's first character (its first body in the worldbody,
without actuators, tendons, sensors, keyframes, contact pairs or equalities) is timed alone too:
what the crowd costs beside what its characters cost one by one.
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
    ap.add_argument("--xml", nargs="*", default=[], help="more scenes to time, as files")
    ap.add_argument("--alone", action="store_true", help="time each file's first character alone too")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["| scene | steps | sinew wall time (s) | MuJoCo (s) | sinew / MuJoCo | contacts at the end, sinew / MuJoCo | sinew fallback solves |",
             "|---|---|---|---|---|---|---|"]
    scenes = [(f"{args.humanoids} gymnasium humanoids dropped together, dt 0.005", scene(args.humanoids))]
    for path in args.xml:
        name, xml = f"`{path.split('/')[-1]}`", open(path).read()
        scenes.append((name, xml))
        if args.alone:
            scenes.append((f"{name}'s first character alone", first_character(xml)))
    for name, xml in scenes:
        lines.append(f"| {name}, 1 thread | {args.steps} | " + time_scene(xml, args.steps, args.rounds))
    emit("\n".join([invocation(), *lines]) + "\n", args.out)


def first_character(xml: str) -> str:
    """The scene with only the first body of its worldbody, and nothing that names the others."""
    root = ET.fromstring(xml)
    for tag in ("actuator", "tendon", "contact", "equality", "sensor", "keyframe"):
        for e in root.findall(tag):
            root.remove(e)
    world = root.find("worldbody")
    for body in world.findall("body")[1:]:
        world.remove(body)
    return ET.tostring(root, encoding="unicode")


def time_scene(xml: str, steps: int, rounds: int) -> str:
    """The table's cells after the step count: median wall times over `rounds`, contacts at the
    end and fallback solves."""
    times = {"sinew": [], "mujoco": []}
    for _ in range(rounds):
        sim = sinew.Sim(sinew.Model.from_mjcf_string(xml))
        t = time.perf_counter()
        sim.step(steps)
        times["sinew"].append(time.perf_counter() - t)
        mj = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(mj)
        t = time.perf_counter()
        mujoco.mj_step(mj, d, steps)
        times["mujoco"].append(time.perf_counter() - t)
    stats = sim.constraint_stats
    ours, theirs = np.median(times["sinew"]), np.median(times["mujoco"])
    return (f"{ours:.3g} | {theirs:.3g} | {ours / theirs:.1f}× | {len(sim.contacts)} / {d.ncon} | "
            f"{stats['fallback_pgs'] + stats['fallback_zero']} |")


if __name__ == "__main__":
    main()
