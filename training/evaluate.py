"""Evaluate a saved model: python training/evaluate.py runs/sinew_Hopper-v0/ppo_0 [--episodes 10]"""

import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from train import make_env  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run_dir")
    ap.add_argument("--episodes", type=int, default=10)
    args = ap.parse_args()
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.evaluation import evaluate_policy

    result = json.load(open(os.path.join(args.run_dir, "result.json")))
    algo = {"ppo": PPO, "sac": SAC}[result["algo"]]
    model = algo.load(os.path.join(args.run_dir, "model"), device="cpu")
    env = make_env(result["env"], 1, result["seed"] + 2000)
    mean, std = evaluate_policy(model, env, n_eval_episodes=args.episodes, deterministic=True)
    print(f"{result['env']} {result['algo'].upper()}: return {mean:.1f} ± {std:.1f} over {args.episodes} episodes")


if __name__ == "__main__":
    main()
