"""RLlib: one PPO iteration with two EnvRunner processes on a local Ray instance, each holding
sinew's native vector env; then each runner's episodes from its seed equal the same runner built
in this process (training/rllib_ppo.py's configuration)."""

import os
import sys

import pytest
import ray

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "training"))
from rllib_ppo import config  # noqa: E402


@pytest.fixture(scope="module")
def local_ray():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def test_two_env_runner_processes_train_and_sample_what_one_process_samples(local_ray):
    from ray.rllib.env.single_agent_env_runner import SingleAgentEnvRunner

    cfg = config("sinew/Hopper-v0", runners=2, envs_per_runner=4, fragment=64).env_runners(num_cpus_per_env_runner=0.5)
    algo = cfg.build_algo()
    try:
        result = algo.train()
        assert result["env_runners"]["num_env_steps_sampled"] >= 2 * 4 * 64
        state = algo.get_module().get_state()

        def returns(runner, state=state):
            # the trained weights, and a reset from the runner's own seed (config seed + index)
            runner.module.set_state(state)
            runner._needs_initial_reset = True
            return sorted(float(e.get_return()) for e in runner.sample(num_timesteps=400, explore=False))

        remote = algo.env_runner_group.foreach_env_runner(returns, local_env_runner=False)
        here = [returns(SingleAgentEnvRunner(config=algo.config, worker_index=k)) for k in (1, 2)]
    finally:
        algo.stop()
    assert len(remote) == 2 and all(len(r) >= 4 for r in remote)
    assert remote == here
    assert remote[0] != remote[1]  # the two runners' seeds differ


def test_ray_ships_a_sim_that_steps_on_bit_identically(local_ray):
    import sinew
    from conftest import gym_model_path

    sim = sinew.Sim(sinew.Model.from_mjcf(gym_model_path("hopper")))
    sim.step(10)

    @ray.remote
    def step(s):
        s.step(50)
        return s

    remote = ray.get(step.remote(sim))
    sim.step(50)
    assert remote.get_state(full=True).tolist() == sim.get_state(full=True).tolist()
