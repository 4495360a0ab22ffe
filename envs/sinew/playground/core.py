"""A Playground task over N worlds: Playground's model file and timing, actions in [-1, 1] as
position targets about the default pose, the noisy ``state`` observation (float32), the
privileged state, reward terms and command in ``info``, and domain randomization drawn once per
world when its generator is seeded."""

from __future__ import annotations

import inspect
import os
import warnings

import numpy as np
from gymnasium import spaces

from sinew._core import ModelWarning
from sinew.core import Worlds, camera_index


class Readings:
    """What a task reads of its worlds after a step or reset: the watched sensors by name, qpos,
    qvel, controls and body poses, one row per world."""

    def __init__(self, batch, sensors: dict, rows: np.ndarray, readings: np.ndarray):
        self.rows = rows
        self._sensors = sensors
        self._watched = readings
        self.qpos, self.qvel, self.ctrl = batch.qpos[rows], batch.qvel[rows], batch.ctrl[rows]
        self._batch = batch

    def sensor(self, name: str) -> np.ndarray:
        """The sensor's readings (worlds, dim)."""
        at, dim = self._sensors[name]
        return self._watched[:, at:at + dim]

    def xmat(self, body: int) -> np.ndarray:
        """A body's world rotation (worlds, 3, 3)."""
        return self._batch.xmat[self.rows, body].reshape(-1, 3, 3)

    def xpos(self, body: int) -> np.ndarray:
        """A body's world origin (worlds, 3)."""
        return self._batch.xpos[self.rows, body]


class PlaygroundCore(Worlds):
    """Task ``playground-<Task>`` over N worlds with Playground's semantics (see
    ``sinew.playground``); ``domain_randomization`` draws each world's model values once, when
    ``reset(seed=...)`` seeds its generator."""

    camera_id = None

    def __init__(self, task: str, num_envs: int, num_threads: int | None = None, *,
                 domain_randomization: bool = True, from_pixels: bool = False, width: int = 84, height: int = 84,
                 camera_id: int | str | None = None, **task_kwargs):
        from sinew.playground import TASKS, assets_dir
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r}; known: {sorted(TASKS)}")
        cls = TASKS[task]
        own = sorted(inspect.signature(cls).parameters)
        unknown = sorted(set(task_kwargs) - set(own))
        if unknown:
            raise TypeError(f"sinew/{task}-v0: __init__() got an unexpected keyword argument '{unknown[0]}' (its "
                            f"keywords: domain_randomization, from_pixels, num_threads{''.join(', ' + k for k in own)})")
        self.task = cls(**task_kwargs)
        with warnings.catch_warnings():
            # Playground's files declare sensors no task reads, and texture their floors
            warnings.filterwarnings("ignore", message=".*not computed by sinew.*", category=ModelWarning)
            warnings.filterwarnings("ignore", message=".*image files are not drawn.*", category=ModelWarning)
            model = self.task.load(os.path.join(assets_dir(self.task.assets), self.task.xml))
        super().__init__(model.with_options(timestep=self.task.sim_dt), num_envs, num_threads)
        n_sub = self.task.ctrl_dt / self.task.sim_dt
        if abs(n_sub - round(n_sub)) > 1e-8:
            raise ValueError(f"ctrl_dt {self.task.ctrl_dt} is not a multiple of sim_dt {self.task.sim_dt}")
        self.n_sub_steps = int(round(n_sub))
        self.task.frame_skip, self.task.dt = self.n_sub_steps * self.task.action_repeat, self.task.ctrl_dt
        self.task.max_episode_steps = self.task.episode_length
        self.task.setup(self.model, num_envs)
        for field, values in self.task.model_edits().items():
            if not np.array_equal(np.broadcast_to(values, self.model.param(field).shape), self.model.param(field)):
                self.batch.set_params(field, values)
        self.domain_randomization = bool(domain_randomization)
        # the task's sensors are read by each step, in its parallel pass
        names, adr, dim = self.model.sensor_names, self.model.sensor_adr, self.model.sensor_dim
        ids = self._sensor_ids = [names.index(s) for s in self.task.sensors]
        self.batch.watch_sensors(ids)
        offsets = np.cumsum([0] + [dim[i] for i in ids])
        self.sensors = {s: (int(offsets[k]), dim[i]) for k, (s, i) in enumerate(zip(self.task.sensors, ids))}
        self.action_size = self.task.action_size or self.model.nu
        self.action_space = spaces.Box(-1.0, 1.0, shape=(self.action_size,), dtype=np.float32)
        n_state, n_priv = self.task.obs_sizes
        self.observation_space = spaces.Box(-np.inf, np.inf, shape=(n_state,), dtype=np.float32)
        self._state = np.zeros((num_envs, n_state), dtype=np.float32)
        self.from_pixels, self.camera_id, self._frames = bool(from_pixels), None, None
        if self.from_pixels:
            self.camera_id = camera_index(self.model, self.task.pixels_camera if camera_id is None else camera_id)
            self.size = (int(height), int(width))
            self._frames = np.zeros((num_envs, *self.size, 3), dtype=np.uint8)
            self.observation_space = spaces.Box(0, 255, shape=(*self.size, 3), dtype=np.uint8)
        self._priv = np.zeros((num_envs, n_priv), dtype=np.float32)
        self.info_names = list(self.task.reward_scales)

    @property
    def dt(self) -> float:
        """Simulated time per env step: ``ctrl_dt`` times the task's ``action_repeat``."""
        return self.task.ctrl_dt * self.task.action_repeat

    def reset_worlds(self, idx: np.ndarray, rngs: list, keyframe=None) -> None:
        """Resets the worlds `idx` (ascending) as the task starts an episode (or at the model's
        `keyframe`, without noise), each drawing from its generator in `rngs`."""
        # a world draws its model values when its generator is new (reset(seed=...)), as it
        # seeds its physics stream
        fresh = [k for k, (i, r) in enumerate(zip(idx, rngs)) if self._seeded_by[i] is not r]
        if self.domain_randomization and fresh:
            self.task.randomize(self.batch, idx[fresh], [rngs[k] for k in fresh])
        qpos, qvel = self.task.reset(idx, rngs)
        if keyframe is not None:
            key = self.model.keyframe(keyframe)
            qpos, qvel = np.tile(key["qpos"], (len(idx), 1)), np.tile(key["qvel"], (len(idx), 1))
        self.reset_batch(idx, rngs, qpos, qvel)
        self.task.place(self.batch, idx)
        self.batch.ctrl[idx] = self.task.initial_ctrl(qpos, idx)
        mask = np.zeros(self.num_envs, dtype=bool)
        mask[idx] = True
        if self.task.settle_steps and keyframe is None:
            self.batch.step(self.task.settle_steps, mask)
        self.batch.forward_kinematics(mask)
        readings = self.batch.read_sensors(self._sensor_ids, idx.tolist())
        self._state[idx], self._priv[idx] = self.task.observe(Readings(self.batch, self.sensors, idx, readings), idx, rngs)
        self._draw(idx)

    def _draw(self, rows: np.ndarray) -> None:
        """The pixel observations of the worlds `rows` (from the task's camera)."""
        if self.from_pixels:
            self._frames[rows] = self.batch.render(self.size[1], self.size[0], self.camera_id, rows.tolist())

    def observe(self) -> np.ndarray:
        """The noisy state of each world, or its frame with ``from_pixels`` (the state then in
        ``info["state"]``)."""
        return self._frames.copy() if self.from_pixels else self._state.copy()

    def obs_cache(self):
        """The observations and the task's per-world state (commands, timers, last actions)."""
        frames = None if self._frames is None else self._frames.copy()
        return self._state.copy(), self._priv.copy(), frames, {k: getattr(self.task, k).copy() for k in self.task.state}

    def restore_obs(self, cache) -> None:
        state, priv, frames, task = cache
        self._state[:], self._priv[:] = state, priv
        if frames is not None:
            self._frames[:] = frames
        for k, v in task.items():
            getattr(self.task, k)[:] = v

    def reset_info(self) -> dict:
        n = self.num_envs
        info = {"privileged_state": self._priv.copy(), **{k: np.zeros(n) for k in self.info_names}}
        if self.from_pixels:
            info["state"] = self._state.copy()
        if hasattr(self.task, "command"):
            info["command"] = self.task.command.copy()
        return info

    def _substeps(self, actions: np.ndarray, rows: np.ndarray, rngs: list, active: np.ndarray | None):
        """The physics steps of one task step of the worlds ``rows`` and the task's results."""
        b = self.batch
        qvel = b.qvel[rows]
        if self.task.perturb(qvel, rows, rngs):
            b.qvel[rows] = qvel
        forces = self.task.body_forces(rows, rngs)
        if forces is not None:
            b.set_xfrc_applied(forces, rows)
        b.ctrl[rows] = self.task.motor_targets(actions[rows], b.qpos[rows], b.ctrl[rows], rows)
        if self.task.needs_qacc:
            # the last physics step's accelerations: its change of velocity over the step (Euler)
            b.step(self.n_sub_steps - 1, active)
            before = b.qvel[rows]
            b.step(1, active)
            qacc = (b.qvel[rows] - before) / self.task.sim_dt
        else:
            b.step(self.n_sub_steps, active)
        r = Readings(b, self.sensors, rows, b.watched_readings[rows])
        if self.task.needs_qacc:
            r.qacc = qacc
        return self.task.after_step(r, actions[rows], rows, rngs)

    def step(self, actions: np.ndarray, active: np.ndarray | None = None, blank: np.ndarray | None = None):
        """One control step (``ctrl_dt``) of the worlds `active` (all when None); the others'
        results are discarded (the vector env resets them). A diverged world gets reward 0 and
        terminates."""
        b = self.batch
        rows = np.arange(self.num_envs) if active is None else np.flatnonzero(active)
        rngs = [self._seeded_by[i] for i in rows]
        state, priv, reward, terminated, terms = self._substeps(actions, rows, rngs, active)
        # an action repeated (Playground's action_repeat): each repeat a whole step of the task,
        # its rewards and terms summed
        for _ in range(self.task.action_repeat - 1):
            state, priv, r, done, t = self._substeps(actions, rows, rngs, active)
            reward, terminated = reward + r, terminated | done
            terms = {k: terms[k] + v for k, v in t.items()}
        n = self.num_envs
        self._state[rows], self._priv[rows] = state, priv
        self._draw(rows)
        out_reward, out_term = np.zeros(n), np.zeros(n, dtype=bool)
        out_reward[rows], out_term[rows] = reward, terminated
        diverged = b.diverged.copy()
        out_reward[diverged] = 0.0
        out_term |= diverged
        info = {k: np.zeros(n) for k in terms}
        for k, v in terms.items():
            info[k][rows] = v
        if hasattr(self.task, "command"):
            info["command"] = self.task.command.copy()
        info["privileged_state"] = self._priv.copy()
        if self.from_pixels:
            info["state"] = self._state.copy()
        info["sim_diverged"] = diverged
        return self.observe(), out_reward, out_term, info
