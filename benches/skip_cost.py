"""What a scene does not use should cost nothing: step cost of each gymnasium model with its floor
moved 100 m below (collision runs, no contact), with the floor removed (self-collision only), with
contacts switched off, and with contacts and limits off (the bare ABA step), single thread, semi-implicit Euler, gravity off so nothing falls,
every limited hinge started 10% of its range inside it (at qpos0 hopper's and walker's joints sit on
their limits). The last column counts the constraint rows of the far-floor run's last step: the
humanoid's joint springs pull its knees to 0, beyond their −2° limit, so a limit row stays active
there.

    python benches/skip_cost.py [--out results/skip_cost.md]
"""

import argparse
import os
import re
import time
import warnings

import sinew
from sinew.tasks import ASSETS


def inside_limits(model):
    """qpos0 with every limited hinge or slide moved at least 10% of its range inside it."""
    q = model.qpos0.copy()
    for j, (limited, kind) in enumerate(zip(model.jnt_limited, model.joint_types)):
        if limited and kind in ("hinge", "slide"):
            lo, hi = model.jnt_range[j]
            a = model.jnt_qposadr[j]
            q[a] = min(max(q[a], lo + 0.1 * (hi - lo)), hi - 0.1 * (hi - lo))
    return q


def rates(models, steps=50000, rounds=9):
    """Best steps/s of each model over `rounds` rounds that time every model once in turn, so a
    slow drift of the machine's speed affects all alike; and the rows of the first model's last step."""
    sims = [sinew.Sim(m) for m in models]
    starts = [inside_limits(m) for m in models]
    best = [0.0] * len(models)
    for _ in range(rounds):
        for k, (sim, start) in enumerate(zip(sims, starts)):
            sim.reset()
            sim.qpos[:] = start
            t = time.perf_counter()
            sim.step(steps)
            best[k] = max(best[k], steps / (time.perf_counter() - t))
    return best, sims[0].constraint_stats["rows"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    lines = ["| model | far floor (steps/s) | no floor | contacts off | contacts and limits off (bare ABA) | far floor / no floor | far floor / contacts off | far floor / bare | rows (far floor) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name in ("hopper", "walker2d_v5", "half_cheetah", "ant", "humanoid"):
        xml = open(os.path.join(ASSETS, name + ".xml")).read()
        # the floor 100 m down: the broadphase still checks every pair each step
        xml = re.sub(r'(<geom[^>]*name="floor"[^>]*?)pos="0 0 0"', r'\1pos="0 0 -100"', xml)
        if 'pos="0 0 -100"' not in xml:
            xml = re.sub(r'(<geom[^>]*name="floor")', r'\1 pos="0 0 -100"', xml)
        no_floor_xml = re.sub(r'<geom[^>]*name="floor"[^>]*/>', "", xml)
        assert no_floor_xml != xml
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            m, m_no_floor = (sinew.Model.from_mjcf_string(x).with_options(integrator="Euler", gravity=[0, 0, 0])
                             for x in (xml, no_floor_xml))
        (far, no_floor, off, bare), rows = rates([m, m_no_floor, m.with_options(contact=False),
                                                   m.with_options(contact=False, limit=False)])
        lines.append(f"| {name} | {far:,.0f} | {no_floor:,.0f} | {off:,.0f} | {bare:,.0f} | {far / no_floor:.2f} | {far / off:.2f} | {far / bare:.2f} | {rows} |")
        print(lines[-1], flush=True)
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- python benches/skip_cost.py --out {args.out} -->\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
