"""What per-world parameters cost: env-steps/s of sinew's native vector env (64 worlds, random
actions) with every world holding its own value of every field (each scaled by a draw in
[0.9, 1.1], gravity's too; the inertias through the masses: independent draws of the three
moments can break the triangle inequality) beside the same env without, timed in alternating
rounds.

    python benches/params_cost.py [--threads 1 2] [--steps 500] [--rounds 5] [--out results/params_cost.md]
"""

import argparse
import time

import gymnasium as gym
import numpy as np

import sinew
from emit import emit, invocation

TASKS = ["Hopper", "Walker2d", "HalfCheetah", "Ant", "Humanoid"]
FIELDS = ["body_mass", "body_ipos", "geom_friction", "dof_damping", "dof_armature", "dof_frictionloss",
          "jnt_stiffness", "actuator_gain", "actuator_bias", "actuator_gear", "actuator_ctrlrange", "gravity"]


def make(task, threads, varied):
    env = gym.make_vec(f"sinew/{task}-v0", num_envs=64, vectorization_mode="vector_entry_point", num_threads=threads)
    if varied:
        env = sinew.VectorRandomizeParams(env, {f: ("scale", 0.9, 1.1) for f in FIELDS}, when="start")
    env.reset(seed=0)
    return env


def rate(env, actions):
    t = time.perf_counter()
    for a in actions:
        env.step(a)
    return len(actions) * env.num_envs / (time.perf_counter() - t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tasks", nargs="+", default=TASKS)
    ap.add_argument("--threads", nargs="+", type=int, default=[1, 2])
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for task in args.tasks:
        for threads in args.threads:
            envs = {v: make(task, threads, v) for v in (False, True)}
            space = envs[False].single_action_space
            a = np.random.default_rng(0).uniform(space.low, space.high, (args.steps, 64) + space.shape)
            got = {False: [], True: []}
            for _ in range(args.rounds):
                for v, env in envs.items():
                    got[v].append(rate(env, a))
            plain, varied = np.median(got[False]), np.median(got[True])
            rows.append((task, threads, plain, varied, varied / plain))
            print(f"{task} {threads}t plain {plain:,.0f} varied {varied:,.0f} ratio {varied / plain:.3f}", flush=True)
    lines = ["| task | threads | env-steps/s, shared model | every field varied in every world | ratio |", "|---|---|---|---|---|"]
    lines += [f"| {t} | {k} | {p:,.0f} | {v:,.0f} | {r:.3f} |" for t, k, p, v, r in rows]
    emit("\n".join([invocation(), *lines]) + "\n", args.out)


if __name__ == "__main__":
    main()
