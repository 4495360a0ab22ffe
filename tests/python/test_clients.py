"""The RL libraries' recipes of docs/python-api.md run: rl_zoo3's trainer with
training/rl_zoo3_ppo.yml, TorchRL's GymEnv and GymWrapper of the native vector env (same-step
autoreset), and CleanRL's continuous-PPO wrapper stack in gymnasium's SyncVectorEnv."""

import os
import subprocess
import sys

import gymnasium as gym
import numpy as np

import sinew  # noqa: F401  (registers sinew/*)

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def test_rl_zoo3_trains_ppo_with_the_sinew_hyperparameters(tmp_path):
    cmd = [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", "sinew/Hopper-v0", "--gym-packages", "sinew",
           "-conf", os.path.join(ROOT, "training", "rl_zoo3_ppo.yml"), "-n", "512", "--seed", "0", "--eval-freq", "-1",
           "--log-folder", str(tmp_path)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    saved = [f for _, _, files in os.walk(tmp_path) for f in files if f.endswith(".zip")]
    assert saved, "rl_zoo3 saved no model"


TORCHRL = """
import gymnasium as gym, numpy as np
import sinew
from torchrl.envs import GymEnv, GymWrapper

rollout = GymEnv("sinew:sinew/Hopper-v0").rollout(20)
assert rollout["next", "reward"].shape[-1] == 1 and len(rollout) > 0
vec = gym.make_vec("sinew/Hopper-v0", num_envs=4, vectorization_mode="vector_entry_point",
                   autoreset_mode=gym.vector.AutoresetMode.SAME_STEP)
rollout = GymWrapper(vec).rollout(300, break_when_any_done=False)
assert rollout["next", "reward"].shape == (4, 300, 1)
assert rollout["next", "done"].sum().item() > 0  # episodes ended and were reset in the same step
assert np.isfinite(rollout["next", "observation"].numpy()).all()
print("ok")
"""


def test_torchrl_gym_env_and_wrapper_of_the_vector_env_roll_out():
    # in a process of its own: torch's threads would make this process's later forks fragile
    done = subprocess.run([sys.executable, "-c", TORCHRL], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stderr[-2000:]


def test_cleanrl_continuous_ppo_wrappers_run():
    def make_env(gamma=0.99):
        def thunk():
            env = gym.make("sinew/Hopper-v0")
            env = gym.wrappers.FlattenObservation(env)
            env = gym.wrappers.RecordEpisodeStatistics(env)
            env = gym.wrappers.ClipAction(env)
            env = gym.wrappers.NormalizeObservation(env)
            env = gym.wrappers.TransformObservation(env, lambda obs: np.clip(obs, -10, 10), env.observation_space)
            env = gym.wrappers.NormalizeReward(env, gamma=gamma)
            env = gym.wrappers.TransformReward(env, lambda reward: np.clip(reward, -10, 10))
            return env
        return thunk

    envs = gym.vector.SyncVectorEnv([make_env() for _ in range(2)])
    obs, _ = envs.reset(seed=1)
    episodes = 0
    for _ in range(300):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        if "episode" in info:
            episodes += int(info["_episode"].sum())
    assert episodes > 0
