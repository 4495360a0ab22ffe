"""Train a stable-baselines3 agent on a sinew environment (or, for comparison, on its MuJoCo twin)
and print the evaluated return.

    python training/train.py                                   # PPO on sinew/InvertedPendulum-v0
    python training/train.py --env sinew/Hopper-v0 --algo sac --steps 100000
    python training/train.py --env Hopper-v5 --algo ppo        # the gymnasium MuJoCo twin
    python training/train.py --env sinew/dmc-cheetah-run-v0 --algo sac --steps 100000 \
        --env-kwargs '{"from_pixels": true, "frame_stack": 3, "action_repeat": 4}'   # dm_control's task from pixels
    PYTHONPATH=~/.cache/sinew-tests/mujoco-3.17.0 python training/train.py --env dm_control/cheetah-run-v0 --algo sac
                                                               # dm_control itself (through shimmy; MuJoCo 3.17)

Writes runs/<env>/<algo>_<seed>/: CSV and TensorBoard logs (when tensorboard is installed),
checkpoints, the final model and result.json (return, wall time).
"""

import argparse
import json
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import hyperparams  # noqa: E402


def make_env(env_id: str, n_envs: int, seed: int, render_mode=None, **env_kwargs):
    if env_id.startswith("sinew/"):
        import sinew.sb3

        return sinew.sb3.make_vec_env(env_id, n_envs=n_envs, seed=seed, num_threads=1, render_mode=render_mode, **env_kwargs)
    from stable_baselines3.common.env_util import make_vec_env

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if env_id.startswith("dm_control/"):
            # dm_control itself through shimmy (needs a MuJoCo dm_control loads), observations
            # flattened in dm_control's key order as sinew's dmc envs give them
            import gymnasium
            import shimmy  # noqa: F401

            return make_vec_env(env_id, n_envs=n_envs, seed=seed, wrapper_class=gymnasium.wrappers.FlattenObservation)
        return make_vec_env(env_id, n_envs=n_envs, seed=seed, env_kwargs={"render_mode": render_mode, **env_kwargs})


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--env", default="sinew/InvertedPendulum-v0")
    ap.add_argument("--algo", choices=["ppo", "sac"], default="ppo")
    ap.add_argument("--steps", type=int, default=None, help="environment steps (default: per-env budget)")
    ap.add_argument("--n-envs", type=int, default=1)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--eval-episodes", type=int, default=10)
    ap.add_argument("--out", default="runs")
    ap.add_argument("--no-progress", action="store_true")
    ap.add_argument("--env-kwargs", type=json.loads, default={}, help="JSON keyword arguments of the environment")
    args = ap.parse_args()

    import torch
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.evaluation import evaluate_policy
    from stable_baselines3.common.logger import configure

    torch.set_num_threads(1)
    task = hyperparams.task_of(args.env)
    steps = args.steps or hyperparams.BUDGET.get(task, hyperparams.BUDGET["default"])
    run_dir = os.path.join(args.out, args.env.replace("/", "_"), f"{args.algo}_{args.seed}")
    os.makedirs(run_dir, exist_ok=True)
    env = make_env(args.env, args.n_envs, args.seed, **args.env_kwargs)
    eval_env = make_env(args.env, 1, args.seed + 1000, **args.env_kwargs)
    algo = {"ppo": PPO, "sac": SAC}[args.algo]
    # frames (H, W, C) go through SB3's CNN; its replay buffer then holds 50,000 of them (6 GB at 84 × 84 × 9)
    pixels = len(env.observation_space.shape) == 3
    extra = {"buffer_size": 50_000} if pixels and args.algo == "sac" else {}
    model = algo("CnnPolicy" if pixels else "MlpPolicy", env, seed=args.seed, verbose=0, device="cpu",
                 **{**hyperparams.get(args.algo, args.env), **extra})
    formats = ["csv"]
    try:
        import tensorboard  # noqa: F401

        formats.append("tensorboard")
    except ImportError:
        pass
    model.set_logger(configure(run_dir, formats))
    checkpoints = CheckpointCallback(save_freq=max(steps // 5 // args.n_envs, 1), save_path=os.path.join(run_dir, "checkpoints"))
    t0 = time.perf_counter()
    model.learn(total_timesteps=steps, callback=checkpoints, progress_bar=not args.no_progress)
    wall = time.perf_counter() - t0
    model.save(os.path.join(run_dir, "model"))
    mean, std = evaluate_policy(model, eval_env, n_eval_episodes=args.eval_episodes, deterministic=True)
    result = {"env": args.env, "algo": args.algo, "steps": steps, "seed": args.seed, "return_mean": float(mean),
              "return_std": float(std), "train_wall_s": wall}
    with open(os.path.join(run_dir, "result.json"), "w") as f:
        json.dump(result, f, indent=1)
    print(f"{args.env} {args.algo.upper()} {steps} steps in {wall:.0f} s: evaluated return {mean:.1f} ± {std:.1f} "
          f"({args.eval_episodes} deterministic episodes)")


if __name__ == "__main__":
    np.set_printoptions(precision=3)
    main()
