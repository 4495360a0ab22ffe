"""PPO on Ray RLlib: several EnvRunner processes, each stepping sinew's native vector env on one
thread (gymnasium's VECTOR_ENTRY_POINT mode), the learner in the driver.

    pip install ".[rllib]"
    python training/rllib_ppo.py --env sinew/Hopper-v0 --runners 2 --envs-per-runner 8 --iterations 50

Ray starts a local instance by default. On a cluster started with `ray start --head` (and
`ray start --address=HEAD:6379` on the other machines), the one change is `--address auto`
(`ray.init(address="auto")`): the EnvRunners spread over the cluster's machines.
"""

import argparse
import time

import gymnasium as gym


def config(env, runners, envs_per_runner, seed=0, fragment=128, batch=None):
    """An RLlib PPOConfig whose EnvRunners each hold one sinew vector env of `envs_per_runner`
    worlds on one thread. `sinew:` in the id makes each runner's process import sinew first."""
    from ray.rllib.algorithms.ppo import PPOConfig

    batch = batch or max(1, runners) * envs_per_runner * fragment
    return (
        PPOConfig()
        .environment(f"sinew:{env}" if ":" not in env else env, env_config={"num_threads": 1})
        .env_runners(
            num_env_runners=runners,
            num_envs_per_env_runner=envs_per_runner,
            gym_env_vectorize_mode=gym.VectorizeMode.VECTOR_ENTRY_POINT,
            rollout_fragment_length=fragment,
            num_cpus_per_env_runner=1,
        )
        .training(train_batch_size_per_learner=batch, minibatch_size=min(batch, 256), num_epochs=4, lr=3e-4)
        .debugging(seed=seed)
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="sinew/Hopper-v0")
    parser.add_argument("--runners", type=int, default=2, help="EnvRunner processes")
    parser.add_argument("--envs-per-runner", type=int, default=8)
    parser.add_argument("--iterations", type=int, default=50)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--address", default=None, help='a running Ray cluster ("auto"); default: a local instance')
    args = parser.parse_args()

    import ray

    ray.init(address=args.address, include_dashboard=False)
    algo = config(args.env, args.runners, args.envs_per_runner, args.seed).build_algo()
    start = time.time()
    for i in range(args.iterations):
        result = algo.train()
        runners = result["env_runners"]
        print(f"iteration {i + 1:3d}  env steps {int(runners['num_env_steps_sampled_lifetime']):8d}  "
              f"mean return {runners.get('episode_return_mean', float('nan')):9.2f}  {time.time() - start:6.0f} s", flush=True)
    algo.stop()
    ray.shutdown()


if __name__ == "__main__":
    main()
