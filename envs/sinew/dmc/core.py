"""A dm_control suite task over N worlds: resets as the task initialises an episode, steps of
``n_sub_steps`` physics steps (times ``action_repeat``), its observations and reward, and frames
from one of the model's cameras when the observation is pixels."""

from __future__ import annotations

import inspect
import math
import os
import warnings
from collections import OrderedDict

import numpy as np
from gymnasium import spaces

from sinew._core import Model, ModelWarning
from sinew.core import Worlds, camera_index
from sinew.dmc.physics import Names, Physics


#: The keywords every dm_control env takes (beside a task's own).
_ENV_KEYWORDS = ["action_repeat", "camera_id", "camera_name", "constraint_mode", "flat_observation", "frame_stack",
                 "friction", "from_pixels", "height", "num_threads", "pixels_only", "render_mode", "time_limit", "width"]


def n_sub_steps(control_timestep: float | None, timestep: float) -> int:
    """Physics steps per control step, as dm_control's ``control.compute_n_steps``."""
    if control_timestep is None:
        return 1
    n = control_timestep / timestep
    if abs(n - round(n)) > 1e-8:
        raise ValueError(f"control timestep {control_timestep} is not a multiple of the physics timestep {timestep}")
    return int(round(n))


def _obs_space(obs: OrderedDict, flat: bool) -> spaces.Space:
    """Unbounded float64 Boxes of one world's observation shapes (one row of `obs`)."""
    if flat:
        dim = sum(int(np.prod(v.shape[1:])) for v in obs.values())
        return spaces.Box(-np.inf, np.inf, shape=(dim,), dtype=np.float64)
    return spaces.Dict({k: spaces.Box(-np.inf, np.inf, shape=v.shape[1:], dtype=np.float64) for k, v in obs.items()})


class DmcCore(Worlds):
    """Task ``dmc-<domain>-<task>`` over N worlds, with dm_control's semantics and the env's
    keywords (see ``sinew.dmc``)."""

    def __init__(self, task: str, num_envs: int, num_threads: int | None = None, *, from_pixels: bool = False,
                 pixels_only: bool = True, height: int = 84, width: int = 84, camera_id: int | str | None = None,
                 action_repeat: int = 1, frame_stack: int = 1, flat_observation: bool = True,
                 time_limit: float | None = None, friction: str = "pyramid", constraint_mode: str = "acceleration",
                 **task_kwargs):
        from sinew.dmc import TASKS, suite_dir
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r}; known: {sorted(TASKS)}")
        for name, v in (("action_repeat", action_repeat), ("frame_stack", frame_stack)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"{name} must be a positive integer, got {v!r}")
        cls = TASKS[task]
        unknown = sorted(set(task_kwargs) - set(inspect.signature(cls).parameters))
        if unknown:
            # Python's own wording (wrappers recognise it), with the keywords the env does take
            own = sorted(inspect.signature(cls).parameters)
            raise TypeError(f"sinew/{task}-v0: __init__() got an unexpected keyword argument '{unknown[0]}' (its keywords: "
                            f"{', '.join(_ENV_KEYWORDS)}{''.join(', ' + k for k in own)})")
        if time_limit is not None and not (isinstance(time_limit, (int, float, np.integer, np.floating))
                                           and not isinstance(time_limit, bool) and time_limit > 0):
            raise ValueError(f"time_limit must be a positive number of seconds (inf: no limit), got {time_limit!r}")
        self.task = cls(**task_kwargs)
        xml = self.task.model_xml()
        path = os.path.join(suite_dir(), self.task.xml)
        with warnings.catch_warnings():
            # the suite's files declare accelerometers and force sensors no task reads
            warnings.filterwarnings("ignore", message=".*not computed by sinew.*", category=ModelWarning)
            model = Model.from_mjcf(path) if xml is None else Model.from_mjcf_string(xml, path)
        super().__init__(model.with_options(friction=friction, constraint_mode=constraint_mode), num_envs, num_threads)
        self.names = Names(self.model)
        self.names.declared = [s for s in self.task.sensors if s in self.names.sensor]
        # the task's sensors are read by each step, in its parallel pass
        self.batch.watch_sensors([self.names.sensor[s][0] for s in self.names.declared])
        self.n_sub_steps = n_sub_steps(self.task.control_timestep, self.model.timestep)
        self.action_repeat = int(action_repeat)
        limit = self.task.time_limit if time_limit is None else time_limit
        # dm_control ends an episode at the first control step whose count reaches the limit
        steps = limit / (self.model.timestep * self.n_sub_steps)
        self.task.max_episode_steps = math.inf if math.isinf(steps) else math.ceil(math.ceil(steps) / self.action_repeat)
        self.task.frame_skip = self.n_sub_steps * self.action_repeat
        self.task.dt = self.model.timestep * self.task.frame_skip
        self.info_names = []
        self.from_pixels, self.pixels_only, self.flat = bool(from_pixels), bool(pixels_only), bool(flat_observation)
        self.camera_id = camera_index(self.model, self.task.pixels_camera if camera_id is None else camera_id)
        self.size, self.frame_stack = (int(height), int(width)), int(frame_stack)
        lo, hi = self.model.actuator_ctrlrange.T
        limited = np.asarray(self.model.actuator_ctrllimited)
        lo, hi = np.where(limited, lo, -np.inf), np.where(limited, hi, np.inf)
        self.action_space = spaces.Box(low=lo.astype(np.float32), high=hi.astype(np.float32), dtype=np.float32)
        self.batch.forward_kinematics()
        state = self.task.observation(Physics(self.batch, self.names))
        self._state = OrderedDict((k, np.array(v, dtype=np.float64).reshape(num_envs, *np.shape(v)[1:])) for k, v in state.items())
        self._frames = np.zeros((num_envs, *self.size, 3 * self.frame_stack), dtype=np.uint8) if self.from_pixels else None
        pixels = spaces.Box(0, 255, shape=(*self.size, 3 * self.frame_stack), dtype=np.uint8)
        if self.from_pixels and self.pixels_only:
            self.observation_space = pixels
        elif self.from_pixels:
            self.observation_space = spaces.Dict({"pixels": pixels, **_obs_space(self._state, False).spaces})
        else:
            self.observation_space = _obs_space(self._state, self.flat)

    def reset_worlds(self, idx: np.ndarray, rngs: list, keyframe=None) -> None:
        """Resets the worlds `idx` (ascending) as the task initialises an episode, each drawing
        from its generator in `rngs`, or to the model's `keyframe` (a name or index)."""
        n = len(idx)
        if keyframe is None:
            qpos, qvel = np.tile(self.model.qpos0, (n, 1)), np.zeros((n, self.model.nv))
        else:
            key = self.model.keyframe(keyframe)
            qpos, qvel = np.tile(key["qpos"], (n, 1)), np.tile(key["qvel"], (n, 1))
        self.reset_batch(idx, rngs, qpos, qvel)
        phys = Physics(self.batch, self.names, idx)
        if keyframe is None:
            self.task.initialize_episode(phys, rngs)
        self._observe(phys, fresh=True)

    def _observe(self, phys: Physics, fresh: bool = False) -> None:
        """Updates the observation rows of `phys`'s worlds; `fresh` fills a frame stack with the
        new frame."""
        for k, v in self.task.observation(phys).items():
            self._state[k][phys.rows] = np.reshape(v, self._state[k][phys.rows].shape)
        if not self.from_pixels:
            return
        worlds = np.arange(self.num_envs)[phys.rows]
        frames = self.batch.render(self.size[1], self.size[0], self.camera_id, worlds.tolist())
        if fresh:
            self._frames[worlds] = np.tile(frames, (1, 1, 1, self.frame_stack))
        else:
            self._frames[worlds] = np.concatenate([self._frames[worlds, :, :, 3:], frames], axis=-1)

    def observe(self):
        """Every world's observation: a Box array, or a dict of arrays in the task's key order."""
        if self.from_pixels and self.pixels_only:
            return self._frames.copy()
        if self.from_pixels:
            return OrderedDict(pixels=self._frames.copy(), **{k: v.copy() for k, v in self._state.items()})
        if self.flat:
            return np.concatenate([v.reshape(self.num_envs, -1) for v in self._state.values()], axis=1)
        return OrderedDict((k, v.copy()) for k, v in self._state.items())

    def obs_cache(self):
        """The observation's rows, frame stacks (a frame stack holds earlier states' frames) and
        the geoms and sites each world placed (targets)."""
        placed = []
        for kind, model in (("geom", self.names.geom_pos), ("site", self.names.site_pos)):
            for i, at in enumerate(model):
                pos = getattr(self.batch, f"{kind}_pos")(i)
                if (pos != at).any():
                    placed.append((kind, i, pos))
        return ({k: v.copy() for k, v in self._state.items()}, None if self._frames is None else self._frames.copy(), placed)

    def restore_obs(self, cache) -> None:
        state, frames, placed = cache
        for k, v in state.items():
            self._state[k][:] = v
        if frames is not None:
            self._frames[:] = frames
        for kind, i, pos in placed:
            getattr(self.batch, f"set_{kind}_pos")(i, pos)

    def reset_info(self) -> dict:
        return {}

    def step(self, actions: np.ndarray, active: np.ndarray | None = None, blank: np.ndarray | None = None):
        """One env step (``action_repeat`` control steps, their rewards summed) of the worlds
        `active` (all when None). A diverged world gets reward 0 and terminates."""
        b = self.batch
        b.ctrl[:] = actions
        phys = Physics(b, self.names)
        reward = np.zeros(self.num_envs)
        diverged = np.zeros(self.num_envs, dtype=bool)
        for _ in range(self.action_repeat):
            b.step(self.n_sub_steps, active)
            diverged |= b.diverged
            phys.stepped()
            reward += self.task.reward(phys)
        reward[diverged] = 0.0
        self._observe(phys, fresh=False)
        terminated = diverged | self.task.termination(phys)
        return self.observe(), reward, terminated, {"sim_diverged": diverged}
