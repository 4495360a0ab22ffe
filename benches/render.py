"""Frames/s at 480 × 480 RGB: sinew's renderer beside MuJoCo's own (the twin env's renderer,
software OpenGL through mesa's EGL here: no GPU), and the cost of batched frames.

    MUJOCO_GL=egl python benches/render.py [--frames 30] [--rounds 5] [--out results/render.md]

Per model: the twin env's and sinew's env's step + render (random actions, ``render_mode=
"rgb_array"``, the twin's default camera in both), render alone (each the median of rounds in
which the two are measured in turn, so that the machine's drift touches both), and sinew's
``Batch.render`` of
16 worlds in one call (frames/s counts every frame). The last table times a 1024-world batch
rendering every 64th world (16 frames) against all 1024 (frames/s is of frames drawn).
MuJoCo needs system GL (``apt-get install libegl-mesa0``); without it its columns are empty.
"""

import argparse
import os
import time
import warnings

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym
import numpy as np

import sinew

MODELS = ["Hopper", "Ant", "Humanoid"]


def rate(fn, frames):
    """Calls of `fn` per second over `frames` calls, after one warm-up call."""
    fn()
    t = time.perf_counter()
    for _ in range(frames):
        fn()
    return frames / (time.perf_counter() - t)


def env_calls(env_id):
    """(step + render, render alone) of a single env, as calls."""
    env = gym.make(env_id, render_mode="rgb_array", width=480, height=480)
    env.reset(seed=0)
    space = env.action_space
    space.seed(0)

    def step_render():
        _, _, term, trunc, _ = env.step(space.sample())
        if term or trunc:
            env.reset()
        env.render()

    return env, step_render, env.render


def paired_rates(ids, frames, rounds):
    """Per env id, the median over `rounds` of (step + render, render alone) frames/s, the ids
    measured in turn within each round, so that the machine's drift touches them alike; NaN for
    an env that cannot render here (MuJoCo without GL)."""
    calls, samples = {}, {}
    for i in ids:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                calls[i] = env_calls(i)
                calls[i][2]()
        except Exception as e:  # no GL on this machine
            print(f"{i}: cannot render ({type(e).__name__}: {e})")
        samples[i] = ([], [])
    per_round = max(1, frames // rounds)
    for _ in range(rounds):
        for i, (_, step_render, render) in calls.items():
            samples[i][0].append(rate(step_render, per_round))
            samples[i][1].append(rate(render, per_round))
    for env, _, _ in calls.values():
        env.close()
    return {i: tuple(float(np.median(x)) if x else float("nan") for x in samples[i]) for i in ids}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=30, help="frames per env and measure, over all rounds")
    ap.add_argument("--rounds", type=int, default=5, help="rounds, MuJoCo and sinew in turn; medians are reported")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for name in MODELS:
        got = paired_rates([f"{name}-v5", f"sinew/{name}-v0"], args.frames, args.rounds)
        mj, sw = got[f"{name}-v5"], got[f"sinew/{name}-v0"]
        venv = gym.make_vec(f"sinew/{name}-v0", num_envs=16, vectorization_mode="vector_entry_point", render_mode="rgb_array")
        venv.reset(seed=0)
        batched = 16 * rate(venv.render, max(2, args.frames // 4))
        rows.append((name, mj[0], sw[0], mj[1], sw[1], batched))
        print(f"{name:9s} step+render: MuJoCo {mj[0]:6.1f} sinew {sw[0]:6.1f} ({sw[0] / mj[0]:.1f}×)   render: MuJoCo {mj[1]:6.1f} "
              f"sinew {sw[1]:6.1f} ({sw[1] / mj[1]:.1f}×)   batched ×16: {batched:6.1f}", flush=True)
    m = sinew.Model.from_mjcf(os.path.join(os.path.dirname(gym.__file__), "envs", "mujoco", "assets", "ant.xml"))
    b = sinew.Batch(m, 1024)
    every = list(range(0, 1024, 64))
    sub = rate(lambda: b.render(480, 480, worlds=every), 3)
    whole = rate(lambda: b.render(480, 480), 1)
    lines = [
        "| model | step + render, MuJoCo | step + render, sinew | sinew / MuJoCo | render, MuJoCo | render, sinew | sinew / MuJoCo | sinew, 16 worlds per call |",
        "|---|---|---|---|---|---|---|---|",
    ] + [f"| {n} | {a:.1f} | {b:.1f} | {b / a:.1f}× | {c:.1f} | {d:.1f} | {d / c:.1f}× | {e:.1f} |" for n, a, b, c, d, e in rows]
    lines += [
        "",
        "| Ant batch of 1024 worlds | calls/s | frames/s |",
        "|---|---|---|",
        f"| every 64th world (16 frames) | {sub:.2f} | {16 * sub:.1f} |",
        f"| all 1024 worlds | {whole:.3f} | {1024 * whole:.1f} |",
    ]
    table = "\n".join(lines)
    print(table)
    if args.out:
        with open(args.out, "w") as f:
            f.write(f"<!-- MUJOCO_GL=egl python benches/render.py --frames {args.frames} --rounds {args.rounds} --out {args.out} -->\n"
                    "Frames/s at 480 × 480 RGB on this machine (2 cores, no GPU; MuJoCo through mesa's software EGL): "
                    f"medians of {args.rounds} rounds, MuJoCo and sinew measured in turn in each.\n\n"
                    f"{table}\n")


if __name__ == "__main__":
    main()
