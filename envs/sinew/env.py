"""Gymnasium environments over ``sinew.Batch``: one task, N worlds stepped in Rust.

- :class:`SinewEnv`: a single ``gymnasium.Env`` (a batch of one), made by
  ``gymnasium.make("sinew/Hopper-v0")``.
- :class:`SinewVectorEnv`: a native ``gymnasium.vector.VectorEnv`` made by
  ``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``, with gymnasium's
  next-step autoreset. Its rollouts equal N single envs seeded ``seed, seed + 1, ...``.

Actions (keyword ``action_mode``):

- ``"torque"`` (default): motor controls in the twin's action Box (gymnasium v5 semantics:
  ctrl = action, clamped to ctrlrange inside the physics; ctrl × gear is the joint torque in N·m,
  or force in N for slides).
- ``"pd"``: joint position targets (rad, or m for slides) in the actuated joints' ranges (±π rad
  or ±1 m where unlimited). Every physics step, torque = gear · clamp(kp (target − q) − kd q̇,
  ctrlrange) with ``pd_gains=(kp, kd)`` in control units per rad and per rad/s (default (5, 0.1)),
  so each motor's own torque limit bounds its servo. Reward terms named ``reward_ctrl`` then
  penalise the targets, not torques.
- ``"trajectory"``: the same joint position targets, followed by the seed's motion-control rows
  (Kokkevis 2004, §8.3): every physics step the LCP finds the torques that give
  q̈ = kp (target − q) − kd q̇ together with contacts and limits, each bounded by its motor's
  gear · max|ctrlrange|; ``trajectory_gains=(kp, kd)`` in 1/s² and 1/s (default (100, 20)).

Physics: ``friction="pyramid"`` (default) or ``"one_tangent"`` (the paper's one tangent; ``"seed"``
is the old name of it);
``constraint_mode="acceleration"`` (default: the seed's impact solve for rebounding contacts,
e > 0, then the acceleration-level solve) or
``"velocity"`` (velocity-level time stepping).

Actions that are not finite or beyond ±1e10 (where the control cost alone would overflow the
reward) raise ``ValueError``, as do wrong shapes. Finite actions outside the action Box are
accepted: the physics clamps controls to ctrlrange, the control cost sees them as given (as
the twin does). A world
whose state becomes non-finite or exceeds 1e10 is reset alone and reported with
``info["sim_diverged"]``, ``terminated=True`` and reward 0. In the vector env it is a step entry
like the reward terms: masked by ``info["_sim_diverged"]``, and absent in a step where every env
resets (no env stepped), as gymnasium's SyncVectorEnv leaves such entries out.
"""

from __future__ import annotations

import os
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.utils import EzPickle, seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from sinew._core import Model
from sinew.core import MAX_ACTION, Worlds
from sinew.dmc import TASKS as DMC_TASKS
from sinew.dmc.core import DmcCore
from sinew.playground import TASKS as PLAYGROUND_TASKS
from sinew.playground.core import PlaygroundCore
from sinew.rendering import RENDER_MODES, Viewer
from sinew.tasks import ASSETS, TASKS


def _model_path(xml_file: str) -> str:
    """As gymnasium's MujocoEnv resolves ``xml_file``: a path when it starts with ".", "/" or "~",
    else a file of gymnasium's bundled assets."""
    if xml_file.startswith((".", "/", "~")):
        return os.path.expanduser(xml_file)
    return os.path.join(ASSETS, xml_file)


class WorldData:
    """One world's arrays with MuJoCo's ``MjData`` names (``env.unwrapped.data``): qpos, qvel,
    act (actuator activations, ``na`` of them) and ctrl are writable views (call
    ``env.unwrapped.set_state`` or ``forward`` after writing qpos or qvel); the body quantities
    are those of the last step or reset."""

    def __init__(self, batch, i: int):
        self._b, self._i = batch, i

    qpos = property(lambda self: self._b.qpos[self._i])
    qvel = property(lambda self: self._b.qvel[self._i])
    ctrl = property(lambda self: self._b.ctrl[self._i])
    act = property(lambda self: self._b.act[self._i])
    time = property(lambda self: float(self._b.time[self._i]))
    xpos = property(lambda self: self._b.xpos[self._i])
    xmat = property(lambda self: self._b.xmat[self._i])
    xipos = property(lambda self: self._b.xipos[self._i])
    cvel = property(lambda self: self._b.cvel[self._i])
    cinert = property(lambda self: self._b.cinert[self._i])
    cfrc_ext = property(lambda self: self._b.cfrc_ext[self._i])
    qfrc_constraint = property(lambda self: self._b.qfrc_constraint[self._i])

    def forward(self) -> None:
        """Recomputes the body quantities (and the observation) for qpos and qvel as written."""
        mask = np.zeros(self._b.num_envs, dtype=bool)
        mask[self._i] = True
        self._b.forward_kinematics(mask)


class BatchTask(Worlds):
    """A gymnasium task over N worlds: reset with per-world generators, step with a batch of
    actions."""

    #: The camera ``render`` uses by default (None: the free camera with the task's config).
    camera_id = None

    def __init__(self, task: str, num_envs: int, num_threads: int | None = None, xml_file: str | None = None,
                 friction: str = "pyramid", constraint_mode: str = "acceleration", action_mode: str = "torque",
                 pd_gains: tuple = (5.0, 0.1), trajectory_gains: tuple = (100.0, 20.0), **task_kwargs):
        if task not in TASKS:
            raise ValueError(f"unknown task {task!r}; known: {sorted(TASKS)}")
        cls = TASKS[task]
        frame_skip = task_kwargs.pop("frame_skip", None)
        path = _model_path(xml_file or cls.xml)
        # a URDF robot is driven by a motor on every joint with an effort limit
        model = Model.from_urdf(path, motors=True) if path.lower().endswith(".urdf") else Model.from_mjcf(path)
        model = model.with_options(friction=friction, constraint_mode=constraint_mode)
        if action_mode == "pd":
            model = model.with_options(pd_gains=tuple(pd_gains))
        elif action_mode == "trajectory":
            model = model.with_options(trajectory_gains=tuple(trajectory_gains))
        elif action_mode != "torque":
            raise ValueError(f"action_mode must be 'torque', 'pd' or 'trajectory', got {action_mode!r}")
        super().__init__(model, num_envs, num_threads)
        self.task = cls(self.model, **task_kwargs)
        if frame_skip is not None:
            if isinstance(frame_skip, bool) or not isinstance(frame_skip, (int, np.integer)) or frame_skip < 1:
                raise ValueError(f"frame_skip must be a positive integer, got {frame_skip!r}")
            self.task.frame_skip = int(frame_skip)
        # observation, reward terms and termination: computed in Rust with every step
        self.batch.set_task(self.task.kind, **self.task.params())
        self.info_names = self.batch.info_names
        if action_mode in ("pd", "trajectory"):
            jnt = [self.model.jnt_dofadr.index(d) for d in self.model.actuator_dofadr]
            unlimited = [np.pi if self.model.joint_types[j] == "hinge" else 1.0 for j in jnt]
            rng = self.model.jnt_range
            lo = np.array([rng[j, 0] if self.model.jnt_limited[j] else -u for j, u in zip(jnt, unlimited)])
            hi = np.array([rng[j, 1] if self.model.jnt_limited[j] else u for j, u in zip(jnt, unlimited)])
        else:
            lo, hi = self.model.actuator_ctrlrange.T
        self.action_space = spaces.Box(low=lo.astype(np.float32), high=hi.astype(np.float32), dtype=np.float32)
        self.observation_space = spaces.Box(-np.inf, np.inf, shape=self.batch.obs.shape[1:], dtype=np.float64)

    def reset_worlds(self, idx: np.ndarray, rngs: list, keyframe=None) -> None:
        """Resets the worlds `idx` (ascending), drawing their noise from `rngs` (one per world, in
        the same order) as the twin does, or to the model's `keyframe` (a name or index; no noise)."""
        if keyframe is None:
            qpos, qvel = self.task.reset_state(rngs)
        else:
            key = self.model.keyframe(keyframe)
            qpos, qvel = np.tile(key["qpos"], (len(idx), 1)), np.tile(key["qvel"], (len(idx), 1))
        self.reset_batch(idx, rngs, qpos, qvel)

    def observe(self) -> np.ndarray:
        return self.batch.obs.copy()

    def reset_info(self) -> dict:
        return self.batch.reset_info

    def step(self, actions: np.ndarray, active: np.ndarray | None = None, blank: np.ndarray | None = None):
        """One env step of the worlds `active` (all when None); the others' results are to be
        discarded (the vector env resets them), and their info rows `blank` are zero. A diverged
        world gets reward 0 and terminates."""
        b = self.batch
        b.ctrl[:] = actions
        b.step(self.task.frame_skip, active)
        info_rows = b.info.copy()
        if blank is not None:
            info_rows[blank] = 0.0
        info = {name: info_rows[:, k] for k, name in enumerate(self.info_names)}
        info["sim_diverged"] = b.diverged.copy()
        return self.observe(), b.reward.copy(), b.terminated.copy(), info


def make_core(task: str, num_envs: int, num_threads: int | None = None, width: int | None = None,
              height: int | None = None, camera_id: int | None = None, camera_name: str | None = None, **kwargs):
    """The worlds of `task`: a gymnasium task's ``BatchTask``, a dm_control task's ``DmcCore``
    (whose pixel observations take the render size and camera) or a Playground task's
    ``PlaygroundCore``; the render size it implies."""
    if task in PLAYGROUND_TASKS:
        if kwargs.get("from_pixels"):
            size = (84 if width is None else width, 84 if height is None else height)
            camera = camera_name if camera_id is None else camera_id
            return PlaygroundCore(task, num_envs, num_threads, width=size[0], height=size[1], camera_id=camera, **kwargs), size
        return PlaygroundCore(task, num_envs, num_threads, **kwargs), (480 if width is None else width, 480 if height is None else height)
    if task in DMC_TASKS:
        size = (84 if width is None else width, 84 if height is None else height)
        camera = camera_name if camera_id is None else camera_id
        return DmcCore(task, num_envs, num_threads, width=size[0], height=size[1], camera_id=camera, **kwargs), size
    return BatchTask(task, num_envs, num_threads=num_threads, **kwargs), (480 if width is None else width, 480 if height is None else height)


def row(obs, i: int):
    """World `i`'s observation (a row, or a dict of rows)."""
    return {k: np.asarray(v[i]) for k, v in obs.items()} if isinstance(obs, dict) else obs[i]


class SinewEnv(gymnasium.Env, EzPickle):
    """One sinew world with a gymnasium MuJoCo v5 task (see module docstring). Pickles (and
    deep-copies) as its constructor arguments plus its world's full state and random generator:
    the copy steps on bit-identically.

    Rendering takes the twin's keywords (``render_mode``, ``width``, ``height``, ``camera_id``,
    ``camera_name``, ``default_camera_config``, ``visual_options``); see ``sinew.rendering``."""

    metadata = {"render_modes": RENDER_MODES}

    def __init__(self, task: str, render_mode: str | None = None, width: int | None = None, height: int | None = None,
                 camera_id: int | None = None, camera_name: str | None = None,
                 default_camera_config: dict | None = None, visual_options: dict | None = None, **kwargs):
        EzPickle.__init__(self, task, render_mode, width, height, camera_id, camera_name, default_camera_config,
                          visual_options, **kwargs)
        self._core, (width, height) = make_core(task, 1, 1, width, height, camera_id, camera_name, **kwargs)
        if self._core.camera_id is not None:
            camera_id, camera_name = self._core.camera_id, None
        if default_camera_config is None:
            default_camera_config = self._core.task.camera
        self.viewer = Viewer(self._core.model, render_mode, width, height, camera_id, camera_name,
                             default_camera_config, visual_options)
        self.render_mode = render_mode
        self.width, self.height = self.viewer.width, self.viewer.height
        # the twin's attribute names for its parameters (reward weights, ranges, noise)
        for k, v in self._core.task.kwargs.items():
            setattr(self, "_" + k, v)
        self.action_space = self._core.action_space
        self.observation_space = self._core.observation_space
        self.model = self._core.model
        self.frame_skip = self._core.task.frame_skip
        self.dt = self._core.dt
        self.metadata = {"render_modes": RENDER_MODES, "render_fps": int(np.round(1.0 / self.dt))}
        self._needs_reset = True
        # a dm_control task counts its own steps (its length depends on action_repeat); a
        # gymnasium task's TimeLimit wrapper counts them
        self._limit = self._core.task.max_episode_steps if task in DMC_TASKS else None
        self._elapsed = 0

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        self._core.reset_worlds(np.array([0]), [self.np_random], (options or {}).get("keyframe"))
        self._needs_reset = False
        self._elapsed = 0
        info = {k: v[0] for k, v in self._core.reset_info().items()}
        return row(self._core.observe(), 0), info

    def step(self, action):
        if self._needs_reset:
            raise gymnasium.error.ResetNeeded("call reset() before step()")
        a = self._core.check_actions(action, single=True)
        obs, reward, terminated, info = self._core.step(a)
        if self.render_mode == "human":
            self.render()
        self._elapsed += 1
        truncated = self._limit is not None and self._elapsed >= self._limit
        return row(obs, 0), float(reward[0]), bool(terminated[0]), truncated, {k: v[0] for k, v in info.items()}

    def __getstate__(self):
        state = EzPickle.__getstate__(self)
        core = self._core
        seeded = self._np_random is not None and core._seeded_by[0] is self._np_random
        state["_sinew"] = (core.batch.get_state(0, full=True), self._np_random, self._np_random_seed, seeded,
                           self._needs_reset, dict(self.viewer._free), self._elapsed, core.obs_cache(),
                           core.batch._varied_params())
        return state

    def __setstate__(self, state):
        world, rng, rng_seed, seeded, needs_reset, free, self._elapsed, obs, params = state.pop("_sinew")
        EzPickle.__setstate__(self, state)
        self._core.batch._restore_params(params)
        self._core.batch.set_state(world, 0)
        self._core.restore_obs(obs)
        self._np_random, self._np_random_seed = rng, rng_seed
        self._core._seeded_by[0] = rng if seeded else None
        self._needs_reset = needs_reset
        self.viewer._free = free

    def render(self):
        """The frame the twin's ``render()`` returns for this ``render_mode``: RGB (H, W, 3) uint8,
        depth (H, W) float32, or both as a tuple; None for "human" (drawn in a window) and, with a
        warning, without a render mode."""
        frames = self.viewer.render(self._core.batch, [0])
        return None if frames is None else frames[0]

    def close(self):
        self.viewer.close()

    @property
    def data_qpos(self) -> np.ndarray:
        """The world's qpos (MuJoCo layout)."""
        return self._core.batch.qpos[0]

    @property
    def data_qvel(self) -> np.ndarray:
        """The world's qvel (MuJoCo layout)."""
        return self._core.batch.qvel[0]

    @property
    def data(self) -> WorldData:
        """The world's arrays under MuJoCo's ``MjData`` names (see ``WorldData``)."""
        return WorldData(self._core.batch, 0)

    @property
    def init_qpos(self) -> np.ndarray:
        """The reference configuration, as the twin's ``init_qpos``."""
        return self.model.qpos0.copy()

    @property
    def init_qvel(self) -> np.ndarray:
        """Zero velocities, as the twin's ``init_qvel``."""
        return np.zeros(self.model.nv)

    def state_vector(self) -> np.ndarray:
        """qpos and qvel together, as MujocoEnv.state_vector."""
        return np.concatenate([self.data_qpos, self.data_qvel])

    def get_body_com(self, body_name: str) -> np.ndarray:
        """The body's frame origin in world, as MujocoEnv.get_body_com (MuJoCo's ``xpos``)."""
        names = self.model.body_names
        if body_name not in names:
            raise KeyError(f"no body named {body_name!r}; bodies: {names}")
        return self._core.batch.xpos[0, names.index(body_name)].copy()

    def do_simulation(self, ctrl, n_frames: int) -> None:
        """Sets the controls and advances ``n_frames`` physics steps, as MujocoEnv.do_simulation."""
        c = np.asarray(ctrl, dtype=np.float64)
        if c.shape != (self.model.nu,):
            raise ValueError(f"Action dimension mismatch. Expected {(self.model.nu,)}, found {c.shape}")
        self._core.check_actions(c)
        self._core.batch.ctrl[0] = c
        self._core.batch.step(int(n_frames))

    def set_state(self, qpos, qvel) -> None:
        """Sets qpos and qvel, as MujocoEnv.set_state."""
        qpos, qvel = np.asarray(qpos, dtype=np.float64), np.asarray(qvel, dtype=np.float64)
        if qpos.shape != (self.model.nq,) or qvel.shape != (self.model.nv,):
            raise ValueError(f"set_state needs qpos ({self.model.nq},) and qvel ({self.model.nv},), got {qpos.shape} and {qvel.shape}")
        self._core.batch.qpos[0] = qpos
        self._core.batch.qvel[0] = qvel
        self._core.batch.forward_kinematics()


def _reset_mask(mask, n: int) -> np.ndarray:
    """``options["reset_mask"]`` checked as ``SyncVectorEnv`` checks it."""
    if not isinstance(mask, np.ndarray):
        raise TypeError(f"`options['reset_mask']` must be a numpy array, got {type(mask)}")
    if mask.shape != (n,):
        raise ValueError(f"`options['reset_mask']` must have shape `({n},)`, got {mask.shape}")
    if mask.dtype != np.bool_:
        raise TypeError(f"`options['reset_mask']` must have `dtype=np.bool_`, got {mask.dtype}")
    if not mask.any():
        raise ValueError(f"`options['reset_mask']` must contain a boolean array with at least one True value, got reset_mask={mask}")
    return mask


def _seeds(seed, n):
    if seed is None:
        return [None] * n
    if isinstance(seed, (int, np.integer)):
        return [int(seed) + i for i in range(n)]
    seed = list(seed)
    if len(seed) != n:
        raise ValueError(f"expected {n} seeds, got {len(seed)}")
    return seed


class SinewVectorEnv(VectorEnv):
    """N sinew worlds of one task as a native gymnasium VectorEnv, with gymnasium's three autoreset
    modes (``autoreset_mode``: next-step, the default; same-step; disabled, where the caller resets
    ended worlds with ``reset(options={"reset_mask": mask})``), each equal step by step to
    ``SyncVectorEnv`` in that mode over single sinew envs."""

    def __init__(self, task: str, num_envs: int = 1, max_episode_steps: int | None = None,
                 num_threads: int | None = None, render_mode: str | None = None, width: int | None = None,
                 height: int | None = None, camera_id: int | None = None, camera_name: str | None = None,
                 default_camera_config: dict | None = None, visual_options: dict | None = None,
                 autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP, **kwargs):
        self._args = dict(task=task, num_envs=num_envs, max_episode_steps=max_episode_steps, num_threads=num_threads,
                          render_mode=render_mode, width=width, height=height, camera_id=camera_id,
                          camera_name=camera_name, default_camera_config=default_camera_config,
                          visual_options=visual_options, autoreset_mode=autoreset_mode, **kwargs)
        try:
            self.autoreset_mode = AutoresetMode(autoreset_mode)
        except ValueError:
            raise ValueError(f"autoreset_mode must be one of {[m.value for m in AutoresetMode]} (or AutoresetMode), "
                             f"got {autoreset_mode!r}") from None
        self._core, (width, height) = make_core(task, num_envs, num_threads, width, height, camera_id, camera_name, **kwargs)
        if self._core.camera_id is not None:
            camera_id, camera_name = self._core.camera_id, None
        if default_camera_config is None:
            default_camera_config = self._core.task.camera
        self.viewer = Viewer(self._core.model, render_mode, width, height, camera_id, camera_name,
                             default_camera_config, visual_options)
        if render_mode == "human":
            raise ValueError('the vector env draws many worlds: use render_mode="rgb_array", "depth_array" or '
                             '"rgbd_tuple" (or a single env for "human")')
        self.render_mode = render_mode
        self.num_envs = num_envs
        self.single_action_space = self._core.action_space
        self.single_observation_space = self._core.observation_space
        self.action_space = gymnasium.vector.utils.batch_space(self.single_action_space, num_envs)
        self.observation_space = gymnasium.vector.utils.batch_space(self.single_observation_space, num_envs)
        self.max_episode_steps = max_episode_steps or self._core.task.max_episode_steps
        self.metadata = {"autoreset_mode": self.autoreset_mode, "render_modes": RENDER_MODES[1:],
                         "render_fps": int(np.round(1.0 / self._core.dt))}
        self._rngs = [seeding.np_random()[0] for _ in range(num_envs)]
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._autoreset = np.zeros(num_envs, dtype=bool)
        # every info entry is set for every env: one shared, read-only mask
        self._all = np.ones(num_envs, dtype=bool)
        self._all.flags.writeable = False

    def reset(self, *, seed=None, options=None):
        """Resets every world, or with ``options={"reset_mask": mask}`` (a bool array of shape
        (num_envs,)) those where the mask is true; seeds as ``SyncVectorEnv`` takes them. With
        ``options={"keyframe": name}`` the worlds start at that keyframe of the model, without
        noise."""
        mask = None if not options or "reset_mask" not in options else _reset_mask(options["reset_mask"], self.num_envs)
        idx = np.arange(self.num_envs) if mask is None else np.flatnonzero(mask)
        seeds = _seeds(seed, self.num_envs)
        for i in idx:
            if seeds[i] is not None or self._rngs[i] is None:
                self._rngs[i] = seeding.np_random(seeds[i])[0]
        self._core.reset_worlds(idx, [self._rngs[i] for i in idx], (options or {}).get("keyframe"))
        self._steps[idx] = 0
        self._autoreset[idx] = False
        reset_info = self._core.reset_info()
        if mask is None:
            return self._core.observe(), self._info(reset_info, self._all, reset_info)
        # only the reset worlds report, as SyncVectorEnv's masked reset
        info = {}
        for k, v in reset_info.items():
            info[k], info["_" + k] = np.where(mask, v, np.zeros_like(v)), mask.copy()
        return self._core.observe(), info

    def step(self, actions):
        if self.autoreset_mode == AutoresetMode.SAME_STEP:
            return self._step_same(actions)
        if self.autoreset_mode == AutoresetMode.DISABLED and self._autoreset.any():
            raise ValueError(f"autoreset is disabled and worlds {np.flatnonzero(self._autoreset).tolist()} ended their "
                             'episodes: reset them with reset(options={"reset_mask": mask}) before stepping')
        a = self._core.check_actions(actions)
        # worlds that ended on the previous call are reset below instead of stepped
        done_before = np.flatnonzero(self._autoreset)
        resetting = len(done_before) > 0
        obs, reward, terminated, info = self._core.step(a, ~self._autoreset if resetting else None,
                                                        blank=done_before if resetting else None)
        self._steps += 1
        if not resetting:
            truncated = self._steps >= self.max_episode_steps
            self._autoreset = terminated | truncated
            return obs, reward, terminated, truncated, self._info(info, self._all)
        # next-step autoreset: worlds that ended on the previous call start over now
        self._core.reset_worlds(done_before, [self._rngs[i] for i in done_before])
        obs = self._core.observe()
        reward[done_before] = 0.0
        terminated[done_before] = False
        self._steps[done_before] = 0
        truncated = self._steps >= self.max_episode_steps
        # those worlds report their reset info, as SyncVectorEnv does, and no step entries
        stepped = np.ones(self.num_envs, dtype=bool)
        stepped[done_before] = False
        stepped.flags.writeable = False
        reset_info = self._core.reset_info()
        for k, v in reset_info.items():
            if k in info:
                info[k][done_before] = v[done_before]
        self._autoreset = terminated | truncated
        return obs, reward, terminated, truncated, self._info(info, stepped, reset_info)

    def __getstate__(self):
        core = self._core
        seeded = [s is r for s, r in zip(core._seeded_by, self._rngs)]
        return {"args": self._args, "worlds": core.batch.get_state(full=True), "rngs": self._rngs, "seeded": seeded,
                "steps": self._steps, "autoreset": self._autoreset, "free": dict(self.viewer._free),
                "obs": core.obs_cache(), "params": core.batch._varied_params()}

    def __setstate__(self, state):
        """A copy: the same construction, then every world's full state, generator and counters."""
        self.__init__(**state["args"])
        self._core.batch._restore_params(state["params"])
        self._core.batch.set_state(state["worlds"])
        self._core.restore_obs(state["obs"])
        self._rngs = state["rngs"]
        self._core._seeded_by = [r if s else None for r, s in zip(self._rngs, state["seeded"])]
        self._steps, self._autoreset = state["steps"].copy(), state["autoreset"].copy()
        self.viewer._free = state["free"]

    def _step_same(self, actions):
        """Same-step autoreset: a world that ends is reset within the step; its final observation
        and step info are in ``info["final_obs"]`` and ``info["final_info"]``."""
        obs, reward, terminated, info = self._core.step(self._core.check_actions(actions))
        self._steps += 1
        truncated = self._steps >= self.max_episode_steps
        infos = self._info(info, self._all)
        ended = np.flatnonzero(terminated | truncated)
        if len(ended):
            final = [(i, row(obs, i), {k: v[i] for k, v in info.items()}) for i in ended]
            self._core.reset_worlds(ended, [self._rngs[i] for i in ended])
            obs = self._core.observe()
            self._steps[ended] = 0
            reset_info = self._core.reset_info()
            # gymnasium's _add_info writes into the masks: give it copies of the shared one
            infos = {k: v.copy() if k.startswith("_") else v for k, v in infos.items()}
            # an ended world reports its step only in final_info, as SyncVectorEnv's same-step does
            for k in info:
                infos[k][ended] = 0
                infos["_" + k][ended] = False
            for i, final_obs, final_info in final:
                infos = self._add_info(infos, {"final_obs": final_obs, "final_info": final_info}, i)
                infos = self._add_info(infos, {k: v[i] for k, v in reset_info.items()}, i)
        return obs, reward, terminated, truncated, infos

    def render(self):
        """Every world's frame, drawn in one parallel call, as a tuple (as ``SyncVectorEnv``
        returns its envs' frames); None without a render mode."""
        frames = self.viewer.render(self._core.batch, list(range(self.num_envs)))
        return None if frames is None else tuple(frames)

    def _info(self, info: dict, stepped: np.ndarray, reset_info=()) -> dict:
        """gymnasium's vector info: each entry with its mask of the envs that report it (every env
        for the entries reset info shares, else `stepped`)."""
        out = {}
        any_stepped = stepped is self._all or stepped.any()
        for k, v in info.items():
            if k in reset_info:
                out[k], out["_" + k] = v, self._all
            elif any_stepped:
                # an entry no env reports is left out, as SyncVectorEnv leaves it out
                out[k], out["_" + k] = v, stepped
        return out


def class_name(task: str) -> str:
    """The env classes' stem of a task: ``Hopper``, ``DmcWalkerWalk`` for ``dmc-walker-walk``,
    ``PlaygroundGo1JoystickFlatTerrain`` for ``playground-Go1JoystickFlatTerrain``."""
    if task in PLAYGROUND_TASKS:
        return "Playground" + task.split("-", 1)[1]
    return task if task in TASKS else "".join(p[:1].upper() + p[1:].lower() for p in task.replace("-", "_").split("_"))


def _task_classes(name: str) -> tuple[type, type]:
    """The single and vector env classes of one task (``sinew.env.HopperEnv``,
    ``sinew.env.HopperVectorEnv``, ``sinew.env.DmcWalkerWalkEnv``): gymnasium's entry points, so
    that ``make`` passes only the caller's keywords."""
    doc = f"``sinew/{name}-v0``: see :class:`SinewEnv` and :class:`SinewVectorEnv`."
    stem = class_name(name)

    def single_init(self, task: str = name, *args, **kwargs):
        SinewEnv.__init__(self, task, *args, **kwargs)

    def vector_init(self, task: str = name, *args, **kwargs):
        SinewVectorEnv.__init__(self, task, *args, **kwargs)

    single = type(f"{stem}Env", (SinewEnv,), {"__init__": single_init, "__module__": __name__, "__doc__": doc})
    vector = type(f"{stem}VectorEnv", (SinewVectorEnv,), {"__init__": vector_init, "__module__": __name__, "__doc__": doc})
    return single, vector


for _name in [*TASKS, *DMC_TASKS, *PLAYGROUND_TASKS]:
    globals()[f"{class_name(_name)}Env"], globals()[f"{class_name(_name)}VectorEnv"] = _task_classes(_name)
