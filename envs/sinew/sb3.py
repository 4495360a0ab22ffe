"""Stable-Baselines3 adapter: SB3 rejects gymnasium VectorEnvs, so this VecEnv drives a sinew
Batch directly with SB3's conventions (autoreset within the step, ``infos[i]["terminal_observation"]``
and ``infos[i]["TimeLimit.truncated"]``). Requires ``stable-baselines3`` (``pip install sinew[train]``).
"""

from __future__ import annotations

from typing import Any, Sequence

import time

import gymnasium
import numpy as np
from gymnasium.utils import seeding
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from sinew.env import make_core, row
from sinew.rendering import Viewer
from sinew.registration import ENTRY_TASKS


class SinewVecEnv(VecEnv):
    """N sinew worlds of one task as an SB3 VecEnv."""

    def __init__(self, task: str, n_envs: int, max_episode_steps: int | None = None, seed: int | None = None,
                 num_threads: int | None = None, render_mode: str | None = None, width: int | None = None,
                 height: int | None = None, camera_id: int | None = None, camera_name: str | None = None,
                 default_camera_config: dict | None = None, **kwargs):
        self._core, (width, height) = make_core(task, n_envs, num_threads, width, height, camera_id, camera_name, **kwargs)
        if self._core.camera_id is not None:
            camera_id, camera_name = self._core.camera_id, None
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f'the SB3 VecEnv renders render_mode="rgb_array" (or None), got {render_mode!r}')
        self.render_mode = render_mode
        self._viewer = Viewer(self._core.model, "rgb_array", width, height, camera_id, camera_name,
                              self._core.task.camera if default_camera_config is None else default_camera_config)
        super().__init__(n_envs, self._core.observation_space, self._core.action_space)
        # as the gymnasium envs': a video of the frames plays at the simulation's pace
        self.metadata = {"render_modes": ["rgb_array"], "render_fps": int(np.round(1.0 / self._core.dt))}
        self.max_episode_steps = max_episode_steps or self._core.task.max_episode_steps
        self._base_seed = seed
        self._rngs = [seeding.np_random(None if seed is None else seed + i)[0] for i in range(n_envs)]
        self._steps = np.zeros(n_envs, dtype=np.int64)
        self._returns = np.zeros(n_envs)
        self._actions: np.ndarray | None = None
        self._t0 = time.perf_counter()

    def reset(self) -> np.ndarray:
        for i, s in enumerate(self._seeds):
            if s is not None:
                self._rngs[i] = seeding.np_random(int(s))[0]
        self._reset_seeds()
        self._core.reset_worlds(np.arange(self.num_envs), self._rngs)
        self._steps[:] = 0
        self._returns[:] = 0
        return self._core.observe()

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = self._core.check_actions(actions)

    def step_wait(self):
        obs, reward, terminated, info = self._core.step(self._actions)
        self._steps += 1
        self._returns += reward
        truncated = (self._steps >= self.max_episode_steps) & ~terminated
        dones = terminated | truncated
        # one dict per env, its values as Python scalars
        names = list(info)
        infos: list[dict[str, Any]] = [dict(zip(names, row)) for row in zip(*(v.tolist() for v in info.values()))]
        ended = np.flatnonzero(dones)
        if len(ended):
            for i in ended:
                infos[i]["terminal_observation"] = row(obs, i)
                infos[i]["TimeLimit.truncated"] = bool(truncated[i])
                infos[i]["episode"] = {"r": float(self._returns[i]), "l": int(self._steps[i]),
                                       "t": round(time.perf_counter() - self._t0, 6)}
            self._core.reset_worlds(ended, [self._rngs[i] for i in ended])
            obs = self._core.observe()
            self._steps[ended] = 0
            self._returns[ended] = 0
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        pass

    def get_images(self) -> Sequence[np.ndarray]:
        """Every world's RGB frame, drawn in one parallel call (SB3's ``VecEnv.render`` tiles them)."""
        return self._viewer.render(self._core.batch, list(range(self.num_envs)))

    def get_attr(self, attr_name: str, indices=None) -> list[Any]:
        return [getattr(self, attr_name) for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices=None, **method_kwargs) -> list[Any]:
        raise NotImplementedError(f"sinew's SB3 VecEnv has no per-env method {method_name!r}")

    def env_is_wrapped(self, wrapper_class, indices=None) -> list[bool]:
        # episode statistics are reported in info["episode"] exactly as SB3's Monitor does
        return [wrapper_class is Monitor for _ in self._get_indices(indices)]


def make_vec_env(env_id: str, n_envs: int = 1, seed: int | None = None, **env_kwargs) -> SinewVecEnv:
    """An SB3 VecEnv of ``n_envs`` worlds of a registered sinew environment, e.g. ``"sinew/Hopper-v0"``.

    ``env_kwargs`` go to the task (reward weights, reset noise, ...) and to the batch
    (``num_threads``, ``friction``); the time limit is the environment's registered one unless
    ``max_episode_steps`` is given.
    """
    spec = gymnasium.spec(env_id)
    task = ENTRY_TASKS.get(spec.entry_point) if isinstance(spec.entry_point, str) else None
    if task is None:
        raise ValueError(f"{env_id} is not a sinew environment")
    kwargs = dict(spec.kwargs)
    kwargs.update(env_kwargs)
    max_steps = kwargs.pop("max_episode_steps", spec.max_episode_steps)
    return SinewVecEnv(task, n_envs=n_envs, max_episode_steps=max_steps, seed=seed, **kwargs)


__all__: Sequence[str] = ["SinewVecEnv", "make_vec_env"]
