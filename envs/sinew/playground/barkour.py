"""Google Barkour vB's Playground task (``mujoco_playground/_src/locomotion/barkour``): joystick
velocity tracking through kicks of the trunk, written from Playground's ``joystick.py`` (no
domain randomization: Playground has none for Barkour)."""

from __future__ import annotations

import numpy as np

from sinew._core import Model
from sinew.playground.task import Task, servo_force, servo_gains, uniform_noise

#: Playground's order of the feet (its ``_FEET_SITES`` and ``_FEET_GEOMS``).
FEET = ("foot_front_left", "foot_hind_left", "foot_front_right", "foot_hind_right")
#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(tracking_lin_vel=1.5, tracking_ang_vel=0.8, lin_vel_z=-2.0, ang_vel_xy=-0.05, orientation=-5.0,
                       torques=-0.0002, action_rate=-0.1, stand_still=-0.5, termination=-1.0, feet_air_time=0.2)
#: The floor contact sensor Playground's env adds for each foot (through ``MjSpec``).
CONTACT_SENSOR = '<contact name="{0}_floor_found" geom1="{0}" geom2="floor" reduce="mindist" num="1" data="found"/>'


class BarkourJoystick(Task):
    """``BarkourJoystick``: track a commanded planar velocity and yaw rate (``info["command"]``,
    redrawn every 501 steps) from the last 15 noisy readings (yaw rate, up vector, scaled command,
    joint angles, last action: 31 each, newest first), through kicks of the trunk (a half-sine
    force every 50–149 steps, for 1–9 steps, worth 0.1–1 m/s); the episode ends on a fall, a joint
    beyond its range or the trunk below 0.18 m."""

    xml = "mujoco_menagerie/google_barkour_vb/scene_mjx.xml"
    camera = dict(distance=1.5, elevation=-20.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.15]))
    sensors = ("gyro", "upvector", "local_linvel", "global_linvel", "global_angvel", *(f"{f}_floor_found" for f in FEET))
    obs_sizes = (465, 465)
    reward_scales = JOYSTICK_SCALES
    state = ("command", "step", "last_act", "last_contact", "feet_air_time", "history", "kick_wait_steps",
             "kick_duration_steps", "vel_kick", "kick_dir", "last_kick_step")
    #: The servo targets' range (Playground's ``_lowers``, ``_uppers``).
    lowers, uppers = np.array([-0.7, -1.0, 0.05] * 4), np.array([0.52, 2.1, 2.1] * 4)

    def __init__(self, action_scale: float = 0.3, obs_noise: float = 0.05, lin_vel_x=(-0.6, 1.5), lin_vel_y=(-0.8, 0.8),
                 ang_vel_yaw=(-0.7, 0.7), tracking_sigma: float = 0.25, velocity_kick=(0.1, 1.0), kick_duration_steps=(1, 10),
                 kick_wait_steps=(50, 150), reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(JOYSTICK_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(JOYSTICK_SCALES)}")
        self.reward_scales = {**JOYSTICK_SCALES, **(reward_scales or {})}
        self.action_scale, self.obs_noise, self.sigma = float(action_scale), float(obs_noise), float(tracking_sigma)
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)
        self.kick_speed = tuple(map(float, velocity_kick))
        self.kick_steps, self.kick_wait = tuple(map(int, kick_duration_steps)), tuple(map(int, kick_wait_steps))

    def load(self, path: str) -> Model:
        """The file with the feet's floor contact sensors Playground's env adds."""
        with open(path) as f:
            xml = f.read()
        sensors = "<sensor>" + "".join(CONTACT_SENSOR.format(g) for g in FEET) + "</sensor>"
        at = xml.rindex("</mujoco>")
        return Model.from_mjcf_string(xml[:at] + sensors + xml[at:], path)

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        self.torso = model.body_names.index("torso")
        # the whole robot hangs from the trunk (Playground's ``body_subtreemass``)
        self.torso_mass = float(model.param("body_mass")[1:].sum())
        edits = self.model_edits()
        self.gain, self.bias = edits["actuator_gain"][:, 0], edits["actuator_bias"]
        self.ranges = (tuple(model.actuator_ctrlrange.T), tuple(model.actuator_forcerange.T))
        nu = model.nu
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.last_act, self.feet_air_time = np.zeros((n, nu)), np.zeros((n, 4))
        self.last_contact = np.zeros((n, 4), dtype=bool)
        self.history = np.zeros((n, 465))
        self.kick_wait_steps, self.kick_duration_steps = np.ones(n, dtype=np.int64), np.ones(n, dtype=np.int64)
        self.vel_kick, self.kick_dir = np.zeros(n), np.zeros((n, 3))
        self.last_kick_step = np.full(n, -np.inf)

    def model_edits(self) -> dict:
        """Playground's env sets the joints' damping to 0.5239 and the servos' gains to 35."""
        return servo_gains(self.model, 35.0, 0.5239)

    def reset(self, idx: np.ndarray, rngs: list):
        """The home keyframe at rest, with a kick schedule and a command drawn."""
        for j, rng in enumerate(rngs):
            i = idx[j]
            self.kick_wait_steps[i] = rng.integers(*self.kick_wait)
            self.kick_duration_steps[i] = rng.integers(*self.kick_steps)
            self.vel_kick[i] = rng.uniform(*self.kick_speed)
            self.command[i] = rng.uniform(self.cmd_lo, self.cmd_hi)
        self.last_kick_step[idx] = -np.inf
        for a in (self.step, self.last_act, self.feet_air_time, self.last_contact, self.history, self.kick_dir):
            a[idx] = 0
        return np.tile(self.init_q, (len(idx), 1)), np.zeros((len(idx), self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Zero, as Playground's reset leaves it."""
        return np.zeros((len(qpos), self.model.nu))

    def body_forces(self, idx: np.ndarray, rngs: list) -> np.ndarray:
        """Playground's kick: every ``kick_wait_steps`` steps of an episode (not at its start) a new
        direction U(0, 2π) in the plane; for ``kick_duration_steps`` steps from then the trunk is
        pushed by 0.5 sin(π k / D) · M · v_kick / (D · ctrl_dt) at step k of the kick (D its
        duration, M the robot's mass)."""
        step = self.step[idx]
        start = (step % self.kick_wait_steps[idx] == 0) & (step != 0)
        angle = np.array([rng.uniform(0.0, 2 * np.pi) for rng in rngs])
        self.last_kick_step[idx] = np.where(start, step, self.last_kick_step[idx])
        self.kick_dir[idx] = np.where(start[:, None], np.stack([np.cos(angle), np.sin(angle), np.zeros(len(idx))], axis=1),
                                      self.kick_dir[idx])
        k = np.clip(step - self.last_kick_step[idx], 0, 100_000)
        d = self.kick_duration_steps[idx]
        magnitude = 0.5 * np.sin(np.pi * k / d) * self.torso_mass * self.vel_kick[idx] / (d * self.dt) * (k < d)
        forces = np.zeros((len(idx), self.model.nbody, 6))
        forces[:, self.torso, :3] = magnitude[:, None] * self.kick_dir[idx]
        return forces

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(self.default_pose + actions * self.action_scale, self.lowers, self.uppers)

    def actuator_force(self, r) -> np.ndarray:
        return servo_force(r, self.gain, self.bias, *self.ranges)

    def observe(self, r, idx: np.ndarray, rngs: list):
        obs = np.hstack([r.sensor("gyro")[:, 2:3] * 0.25, r.sensor("upvector"), self.command[idx] * [2.0, 2.0, 0.25],
                         r.qpos[:, 7:] - self.default_pose, self.last_act[idx]])
        obs = np.clip(obs, -100.0, 100.0)
        if self.obs_noise >= 0.0:
            obs += uniform_noise(rngs, 31, self.obs_noise)
        self.history[idx] = np.hstack([obs, self.history[idx][:, :-31]])
        state = self.history[idx].astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        q = r.qpos[:, 7:]
        contact = np.hstack([r.sensor(f"{f}_floor_found") for f in FEET]) > 0
        first_contact = (self.feet_air_time[idx] > 0.0) & (contact | self.last_contact[idx])
        self.feet_air_time[idx] += self.dt
        done = (r.sensor("upvector")[:, 2] < 0) | np.any((q < self.lowers) | (q > self.uppers), axis=1)
        done |= r.xpos(self.torso)[:, 2] < 0.18
        cmd, tau = self.command[idx], self.actuator_force(r)
        planar = np.linalg.norm(cmd[:, :2], axis=1)
        terms = {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - r.sensor("local_linvel")[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - r.sensor("gyro")[:, 2]) ** 2) / self.sigma),
            "lin_vel_z": r.sensor("global_linvel")[:, 2] ** 2,
            "ang_vel_xy": np.sum(r.sensor("global_angvel")[:, :2] ** 2, axis=1),
            "orientation": np.sum(r.sensor("upvector")[:, :2] ** 2, axis=1),
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((actions - self.last_act[idx]) ** 2, axis=1),
            # Playground's gate: the command's unit planar direction's y below 0.1
            "stand_still": np.sum(np.abs(q - self.default_pose), axis=1) * (cmd[:, 1] / planar < 0.1),
            "termination": (done & (self.step[idx] < 500)).astype(np.float64),
            "feet_air_time": np.sum((self.feet_air_time[idx] - 0.1) * first_contact, axis=1) * (planar > 0.05),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()) * self.dt, 0.0, 10000.0)
        self.last_act[idx] = actions
        self.step[idx] += 1
        self.feet_air_time[idx] *= ~contact
        self.last_contact[idx] = contact
        for j, rng in enumerate(rngs):
            if self.step[idx[j]] > 500:
                self.command[idx[j]] = rng.uniform(self.cmd_lo, self.cmd_hi)
        self.step[idx] = np.where(done | (self.step[idx] > 500), 0, self.step[idx])
        return state, priv, reward, done, terms


TASKS = {"BarkourJoystick": BarkourJoystick}
