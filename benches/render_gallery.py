"""Stills of every environment, and each beside its MuJoCo twin's frame of the same state.

    MUJOCO_GL=egl python benches/render_gallery.py [--out results]

Writes ``results/stills/<Env>.png`` (240 × 240, the env's default camera, the state after
``reset(seed=0)`` and 20 random steps), ``results/render_vs_mujoco/<Env>.png`` (sinew left, the
twin right, 320 × 320, same state and camera) and ``results/render_vs_mujoco.md``: per env, the
share of pixels whose depth agrees within 2% (over pixels where either image shows geometry;
MuJoCo's skybox, drawn as a box 0.6 × zfar away, is not geometry) and the mean absolute RGB
difference. MuJoCo needs system GL (``apt-get install libegl-mesa0``).
"""

import argparse
import os
import warnings

os.environ.setdefault("MUJOCO_GL", "egl")

import gymnasium as gym
import imageio.v2 as imageio
import numpy as np

import sinew  # noqa: F401  (registers sinew/*)
from sinew.tasks import TASKS

NAMES = list(TASKS)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="results")
    args = ap.parse_args()
    stills, pairs = os.path.join(args.out, "stills"), os.path.join(args.out, "render_vs_mujoco")
    os.makedirs(stills, exist_ok=True)
    os.makedirs(pairs, exist_ok=True)
    rows = []
    for name in NAMES:
        env = gym.make(f"sinew/{name}-v0", render_mode="rgb_array", width=240, height=240)
        env.reset(seed=0)
        env.action_space.seed(0)
        for _ in range(20):
            env.step(env.action_space.sample())
        imageio.imwrite(os.path.join(stills, f"{name}.png"), env.render())

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            twin = gym.make(f"{name}-v5", render_mode="rgbd_tuple", width=320, height=320).unwrapped
        twin.reset(seed=0)
        ours = gym.make(f"sinew/{name}-v0", render_mode="rgbd_tuple", width=320, height=320).unwrapped
        ours.reset(seed=0)
        ours.set_state(twin.data.qpos, twin.data.qvel)
        (c1, d1), (c2, d2) = ours.render(), twin.render()
        twin.close()
        n, f = ours.model.clip
        metric = lambda d: n * f / (f - d.astype(np.float64) * (f - n))  # noqa: E731
        seen = (d1 < 1) | (metric(d2) < 0.5 * f)
        agree = (np.abs(metric(d1) - metric(d2)) <= 0.02 * metric(d2))[seen].mean()
        diff = np.abs(c1.astype(int) - c2.astype(int)).mean()
        imageio.imwrite(os.path.join(pairs, f"{name}.png"), np.concatenate([c1, c2], axis=1))
        rows.append((name, agree, diff))
        print(f"{name:24s} depth within 2%: {agree:.4f}   mean |RGB difference|: {diff:.1f} / 255", flush=True)
    table = "\n".join(["| env | pixels with depth within 2% of MuJoCo's | mean RGB difference (of 255) |", "|---|---|---|"]
                      + [f"| {a} | {b:.2%} | {c:.1f} |" for a, b, c in rows])
    with open(os.path.join(args.out, "render_vs_mujoco.md"), "w") as fh:
        fh.write(f"<!-- MUJOCO_GL=egl python benches/render_gallery.py --out {args.out} -->\n"
                 "sinew's frame beside MuJoCo's for the same state and default camera, 320 × 320 "
                 "(pictures in render_vs_mujoco/, sinew left).\n\n" + table + "\n")
    print(table)


if __name__ == "__main__":
    main()
