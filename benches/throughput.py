"""Env-steps/s of sinew's native vector env beside EnvPool and gymnasium's SyncVectorEnv of the
MuJoCo twins, random actions, each task at its v5 frame_skip, on this machine.

    python benches/throughput.py [--num-envs 64] [--steps 1000] [--rounds 3] [--constraint-mode velocity] [--out results/throughput.md]

sinew runs with 1 and 2 threads (scaling efficiency = rate(2) / (2 · rate(1))); EnvPool with 2
threads (``num_threads=2``, its v4 envs: same models and frame_skip); SyncVectorEnv is one thread.
Each task's four configurations are timed in turn, ``--rounds`` times over, and each keeps its
best rate: slow drift in the machine's speed then affects them alike.
sinew's environments run the seed's acceleration-level scheme unless ``--constraint-mode velocity``
selects velocity-level time stepping.
"""

import argparse
import os
import time
import warnings

import gymnasium as gym
import numpy as np

import sinew  # noqa: F401  (registers sinew/*)

TASKS = ["Hopper", "Walker2d", "HalfCheetah", "Ant", "Humanoid"]


def rate_gym_vec(env, actions):
    """Env-steps/s of a gymnasium vector env over `actions` (steps, N, ·), from a seeded reset."""
    env.reset(seed=0)
    env.step(actions[0])
    t = time.perf_counter()
    for a in actions:
        env.step(a)
    return len(actions) * env.num_envs / (time.perf_counter() - t)


def rate_envpool(env, actions):
    """Env-steps/s of an EnvPool env over `actions`, from a reset."""
    env.reset()
    t = time.perf_counter()
    for a in actions:
        env.step(a)
    return len(actions) * len(actions[0]) / (time.perf_counter() - t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--num-envs", type=int, default=64)
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--constraint-mode", default="acceleration", choices=["acceleration", "velocity"])
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    mode = {"constraint_mode": args.constraint_mode}
    n, steps = args.num_envs, args.steps
    rng = np.random.default_rng(0)
    rows = []
    import envpool

    for name in TASKS:
        vec = {k: gym.make_vec(f"sinew/{name}-v0", num_envs=n, vectorization_mode="vector_entry_point", num_threads=k, **mode) for k in (1, 2)}
        pool = envpool.make_gymnasium(f"{name}-v4", num_envs=n, num_threads=2, seed=0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sync = gym.make_vec(f"{name}-v5", num_envs=n, vectorization_mode="sync")
        space = vec[1].single_action_space
        a = rng.uniform(space.low, space.high, size=(steps, n) + space.shape)
        runs = {
            "1t": lambda: rate_gym_vec(vec[1], a),
            "2t": lambda: rate_gym_vec(vec[2], a),
            "envpool": lambda: rate_envpool(pool, a.astype(np.float32)),
            "sync": lambda: rate_gym_vec(sync, a[: max(10, steps // 4)]),
        }
        best = dict.fromkeys(runs, 0.0)
        for _ in range(args.rounds):
            for k, run in runs.items():
                best[k] = max(best[k], run())
        r1, r2, ep, sv = best["1t"], best["2t"], best["envpool"], best["sync"]
        rows.append((name, r1, r2, r2 / (2 * r1), ep, sv))
        print(f"{name:12s} sinew 1t {r1:10,.0f}  2t {r2:10,.0f}  eff {r2/(2*r1):.2f}  envpool {ep:10,.0f}  sync {sv:10,.0f}  sinew/envpool {r2/ep:.2f}", flush=True)
    lines = [
        f"| task | sinew, 1 thread | sinew, 2 threads | scaling efficiency | EnvPool, 2 threads | gymnasium SyncVectorEnv | sinew / EnvPool |",
        "|---|---|---|---|---|---|---|",
    ] + [f"| {a} | {b:,.0f} | {c:,.0f} | {d:.2f} | {e:,.0f} | {f:,.0f} | {c / e:.2f}× |" for a, b, c, d, e, f in rows]
    table = "\n".join(lines)
    print(table)
    if args.out:
        with open(args.out, "w") as f:
            flag = "" if args.constraint_mode == "acceleration" else f" --constraint-mode {args.constraint_mode}"
            f.write(f"<!-- python benches/throughput.py --num-envs {n} --steps {steps} --rounds {args.rounds}{flag} --out {args.out} -->\n{table}\n")


if __name__ == "__main__":
    main()
