"""Evaluate a saved model: python training/evaluate.py runs/sinew_InvertedPendulum-v0/ppo_0 [--episodes 10] [--video DIR]

Prints the mean return of deterministic episodes, then each episode's length, return and, for
tasks that report it, its final x_position (how far the agent went). With ``--video DIR`` each of
those episodes is also recorded to DIR/episode_K.mp4 (the env's default camera, 480 × 480)."""

import argparse
import glob
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from train import make_env  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("--episodes", type=int, default=10)
    ap.add_argument("--video", metavar="DIR", help="record each episode to DIR/episode_K.mp4")
    args = ap.parse_args()
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.evaluation import evaluate_policy

    result_file = os.path.join(args.run_dir, "result.json")
    if not os.path.isfile(result_file):
        runs = sorted(os.path.dirname(p) for p in glob.glob(os.path.join("runs", "*", "*", "result.json")))
        ap.error(f"{args.run_dir} holds no finished run (no result.json); runs here: {', '.join(runs) or 'none'}")
    with open(result_file) as f:
        result = json.load(f)
    algo = {"ppo": PPO, "sac": SAC}[result["algo"]]
    model = algo.load(os.path.join(args.run_dir, "model"), device="cpu")
    env = make_env(result["env"], 1, result["seed"] + 2000)
    returns, lengths = evaluate_policy(model, env, n_eval_episodes=args.episodes, deterministic=True, return_episode_rewards=True)
    print(f"{result['env']} {result['algo'].upper()}: return {np.mean(returns):.1f} ± {np.std(returns):.1f} over {args.episodes} episodes")
    # the same episodes again (same seed), one line each, with where the agent ended up
    env = make_env(result["env"], 1, result["seed"] + 2000, render_mode="rgb_array" if args.video else None)
    if args.video:
        from sinew.video import write_video

        os.makedirs(args.video, exist_ok=True)
    obs = env.reset()
    for k in range(args.episodes):
        done, steps, ret, x = False, 0, 0.0, None
        frames = [env.get_images()[0]] if args.video else []
        while not done:
            action, _ = model.predict(obs, deterministic=True)
            obs, reward, dones, infos = env.step(action)
            steps, ret, done = steps + 1, ret + float(reward[0]), bool(dones[0])
            x = infos[0].get("x_position", x)
            # the last frame would show the next episode's reset
            if args.video and not done:
                frames.append(env.get_images()[0])
        where = "" if x is None else f", final x_position {x:.2f}"
        print(f"  episode {k}: {steps} steps, return {ret:.1f}{where}")
        if args.video:
            fps = env.get_attr("metadata")[0].get("render_fps", 30)
            write_video(os.path.join(args.video, f"episode_{k}.mp4"), frames, fps=fps)


if __name__ == "__main__":
    main()
