"""Frames/s at 480 × 480 RGB: sinew's renderer beside MuJoCo's own (the twin env's renderer,
software OpenGL through mesa's EGL here: no GPU), and the cost of batched frames.

    MUJOCO_GL=egl python benches/render.py [--frames 30] [--out results/render.md]

Per model: the twin env's and sinew's env's step + render (random actions, ``render_mode=
"rgb_array"``, the twin's default camera in both), render alone, and sinew's ``Batch.render`` of
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


def env_rates(env_id, frames, **kw):
    """(step + render, render alone) frames/s of a single env."""
    env = gym.make(env_id, render_mode="rgb_array", width=480, height=480, **kw)
    env.reset(seed=0)
    space = env.action_space
    space.seed(0)

    def step_render():
        _, _, term, trunc, _ = env.step(space.sample())
        if term or trunc:
            env.reset()
        env.render()

    out = rate(step_render, frames), rate(env.render, frames)
    env.close()
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    rows = []
    for name in MODELS:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                mj = env_rates(f"{name}-v5", args.frames)
        except Exception as e:  # no GL on this machine
            print(f"MuJoCo {name}: cannot render ({type(e).__name__}: {e})")
            mj = (float("nan"), float("nan"))
        sw = env_rates(f"sinew/{name}-v0", args.frames)
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
            f.write(f"<!-- MUJOCO_GL=egl python benches/render.py --frames {args.frames} --out {args.out} -->\n"
                    "Frames/s at 480 × 480 RGB on this machine (2 cores, no GPU; MuJoCo through mesa's software EGL).\n\n"
                    f"{table}\n")


if __name__ == "__main__":
    main()
