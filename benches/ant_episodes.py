"""Why sinew's Ant episodes outlast its twin's under random actions: episode lengths, why each
ended, and how high the torso went, for seeds 0–9.

    python benches/ant_episodes.py

Actions are clipped standard normals (the same numbers for both simulators), episodes at most
1000 steps. Ant-v5 terminates when the torso's height leaves healthy_z_range = (0.2, 1.0).
"""

import warnings

import gymnasium as gym
import numpy as np

import sinew  # noqa: F401  (registers sinew/*)


def episode(env_id, seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        env = gym.make(env_id)
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    top, steps, z = 0.0, 0, 0.0
    for steps in range(1, 1001):
        a = np.clip(rng.standard_normal(8), -1, 1)
        _, _, terminated, truncated, _ = env.step(a)
        z = float(env.unwrapped.data.qpos[2])
        top = max(top, z)
        if terminated or truncated:
            break
    why = "time limit" if not terminated else ("torso above 1.0" if z > 1.0 else "torso below 0.2")
    return steps, why, top


def main():
    print("| seed | sinew steps | sinew end | sinew highest torso (m) | MuJoCo steps | MuJoCo end | MuJoCo highest torso (m) |")
    print("|---|---|---|---|---|---|---|")
    for seed in range(10):
        s, t = episode("sinew/Ant-v0", seed), episode("Ant-v5", seed)
        print(f"| {seed} | {s[0]} | {s[1]} | {s[2]:.3f} | {t[0]} | {t[1]} | {t[2]:.3f} |")


if __name__ == "__main__":
    main()
