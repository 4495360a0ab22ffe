"""Boston Dynamics Spot's Playground tasks (``mujoco_playground/_src/locomotion/spot``): joystick
velocity tracking, joystick tracking with a commanded gait, and getting up from a fall, written
from Playground's ``joystick.py``, ``joystick_gait_tracking.py``, ``getup.py`` and ``base.py`` (no
domain randomization and no pushes: Playground has none for Spot by default)."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, draw_gait, gait_height, joystick_step, servo_force, servo_gains, site_world, uniform_command, uniform_noise

SPOT = "mujoco_playground/_src/locomotion/spot/xmls"
#: Playground's order of the feet (its ``FEET_SITES`` and ``FEET_GEOMS``).
FEET = ("FL", "FR", "HL", "HR")

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(
    tracking_lin_vel=1.5, tracking_ang_vel=0.8, lin_vel_z=-2.0, ang_vel_xy=-0.05, orientation=-5.0, termination=-1.0,
    posture=1.0, torques=-0.0002, action_rate=-0.01, energy=-0.001, feet_slip=-0.1, feet_clearance=-2.0, feet_height=-0.1,
    feet_air_time=0.1)
#: Reward scales of ``joystick_gait_tracking.default_config()``: the first three multiply the
#: exponential of the last three's sum.
GAIT_SCALES = dict(feet_phase=2.0, tracking_lin_vel=0.5, tracking_ang_vel=0.5, ang_vel_xy=-0.5, lin_vel_z=-0.5, hip_splay=-0.5)
#: Reward scales of ``getup.default_config()``.
GETUP_SCALES = dict(orientation=1.0, torso_height=1.0, posture=1.0, stand_still=1.0, torques=0.0, action_rate=0.0)
#: The gaits' phase offsets per foot: trot, walk, pace, bound, pronk (``_PHASES``).
PHASES = np.array([[0, np.pi, np.pi, 0], [0, 0.5 * np.pi, np.pi, 1.5 * np.pi], [0, np.pi, 0, np.pi], [0, 0, np.pi, np.pi],
                   [0, 0, 0, 0]])
#: The hips' abduction joints (``_hx_idxs``).
HX = [0, 3, 6, 9]


class Spot(Task):
    """What Playground's ``SpotEnv`` gives every Spot task: the servo gains and damping its config
    sets, the home keyframe, the servos' forces and the noisy readings."""

    camera = dict(distance=2.2, elevation=-20.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.3]))
    xml = f"{SPOT}/scene_mjx_feetonly_flat_terrain.xml"
    defaults: dict = {}

    def _configure(self, given: dict) -> None:
        """Reads the task's config knobs (its ``__init__``'s locals)."""
        self.kwargs = {k: v for k, v in given.items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(given["reward_scales"] or {}) - set(self.defaults)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(self.defaults)}")
        self.reward_scales = {**self.defaults, **(given["reward_scales"] or {})}
        self.Kp, self.Kd, self.action_scale = float(given["Kp"]), float(given["Kd"]), float(given["action_scale"])

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.feet_sites = [model.site_names.index(f) for f in FEET]
        edits = self.model_edits()
        self.gain, self.bias = edits["actuator_gain"][:, 0], edits["actuator_bias"]
        self.forces = tuple(model.actuator_forcerange.T)
        self.last_act, self.last_last_act = np.zeros((n, model.nu)), np.zeros((n, model.nu))

    def model_edits(self) -> dict:
        """Playground's ``SpotEnv`` sets the joints' damping to Kd and the servos' gains to Kp
        (their velocity gain stays the file's)."""
        return servo_gains(self.model, self.Kp, self.Kd)

    def actuator_force(self, r) -> np.ndarray:
        return servo_force(r, self.gain, self.bias, (self.lowers, self.uppers), self.forces)

    def noisy(self, r, rngs: list, scales: tuple) -> tuple:
        """The gyro, up vector and joint angles with U(−1, 1) · scale noise: ((noisy...), (clean...))."""
        clean = (r.sensor("gyro"), r.sensor("upvector"), r.qpos[:, 7:])
        u = uniform_noise(rngs, 18, 1.0)
        return (clean[0] + u[:, 0:3] * scales[0], clean[1] + u[:, 3:6] * scales[1], clean[2] + u[:, 6:18] * scales[2]), clean

    def foot_z(self, r) -> np.ndarray:
        return np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)

    def contact(self, r) -> np.ndarray:
        """Each foot on the floor (worlds, 4)."""
        return np.hstack([r.sensor(f"{f}_floor_found") for f in FEET]) > 0

    def action_rate(self, a: np.ndarray, idx: np.ndarray) -> np.ndarray:
        last, last_last = self.last_act[idx], self.last_last_act[idx]
        return np.sum((a - last) ** 2, axis=1) + np.sum((a - 2 * last + last_last) ** 2, axis=1)

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(self.default_pose + actions * self.action_scale, self.lowers, self.uppers)

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Zero, as Playground's reset leaves it (the servos' forces at reset read it)."""
        return np.zeros((len(qpos), self.model.nu))


class SpotJoystick(Spot):
    """``SpotFlatTerrainJoystick``: track a commanded planar velocity and yaw rate
    (``info["command"]``, redrawn every 201 steps, zero one time in ten) from noisy readings, the
    feet's positions and the servos' last three tracking errors."""

    sensors = ("gyro", "local_linvel", "accelerometer", "upvector", "global_linvel", "global_angvel",
               *(f"{f}_global_linvel" for f in FEET), *(f"{f}_pos" for f in FEET), *(f"{f}_floor_found" for f in FEET))
    obs_sizes = (81, 167)
    reward_scales = defaults = JOYSTICK_SCALES
    state = ("command", "step", "last_act", "last_last_act", "qpos_error_history", "feet_air_time", "last_contact", "swing_peak")

    def __init__(self, Kp: float = 300.0, Kd: float = 1.0, early_termination: bool = True, action_scale: float = 0.3,
                 joint_pos_noise: float = 0.05, gyro_noise: float = 0.1, gravity_noise: float = 0.03,
                 feet_pos_noise=(0.01, 0.005, 0.02), tracking_sigma: float = 0.25, max_foot_height: float = 0.12,
                 lin_vel_x=(-1.0, 1.0), lin_vel_y=(-0.8, 0.8), ang_vel_yaw=(-1.0, 1.0), reward_scales: dict | None = None):
        self._configure(locals())
        self.early_termination = bool(early_termination)
        self.scales = (float(gyro_noise), float(gravity_noise), float(joint_pos_noise))
        self.feet_noise = np.asarray(feet_pos_noise, dtype=np.float64)
        self.sigma, self.max_foot_height = float(tracking_sigma), float(max_foot_height)
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.qpos_error_history = np.zeros((n, 36))
        self.feet_air_time, self.swing_peak = np.zeros((n, 4)), np.zeros((n, 4))
        self.last_contact = np.zeros((n, 4), dtype=bool)

    def reset(self, idx: np.ndarray, rngs: list):
        """The home keyframe at rest (Playground draws no pose for Spot)."""
        for j, rng in enumerate(rngs):
            self.command[idx[j]] = uniform_command(rng, self.cmd_lo, self.cmd_hi)
        for a in (self.step, self.last_act, self.last_last_act, self.qpos_error_history, self.feet_air_time, self.swing_peak,
                  self.last_contact):
            a[idx] = 0
        return np.tile(self.init_q, (len(idx), 1)), np.zeros((len(idx), self.model.nv))

    def observe(self, r, idx: np.ndarray, rngs: list):
        (gyro_n, up_n, q_n), (gyro, up, q) = self.noisy(r, rngs, self.scales)
        feet = np.stack([r.sensor(f"{f}_pos") for f in FEET], axis=1)
        # Playground draws one noise per foot and scales it for each axis
        u = uniform_noise(rngs, 4, 1.0)
        feet_n = (feet + u[:, :, None] * self.feet_noise).reshape(len(idx), 12)
        # the servos' tracking errors, newest first (the targets of the last step; zero at reset)
        hist = self.qpos_error_history[idx]
        self.qpos_error_history[idx] = np.hstack([q_n - r.ctrl, hist[:, :24]])
        state = np.hstack([gyro_n, up_n, q_n - self.default_pose, self.qpos_error_history[idx], feet_n, self.last_act[idx],
                           self.command[idx]])
        feet_vel = np.hstack([r.sensor(f"{f}_global_linvel") for f in FEET])
        push = np.zeros((len(idx), 3))     # the applied push: none (Playground's are off for Spot)
        priv = np.hstack([state, gyro, r.sensor("accelerometer"), up, r.sensor("local_linvel"), r.sensor("global_angvel"),
                          q - self.default_pose, feet.reshape(len(idx), 12), r.qvel[:, 6:], self.actuator_force(r),
                          self.last_contact[idx], feet_vel, self.feet_air_time[idx], push])
        return state.astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        done = r.sensor("upvector")[:, 2] < 0.85 if self.early_termination else np.zeros(len(idx), dtype=bool)
        return joystick_step(self, r, actions, idx, rngs, self.contact(r), self.foot_z(r), done, next_commands)

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        cmd, q, qd, tau = self.command[idx], r.qpos[:, 7:], r.qvel[:, 6:], self.actuator_force(r)
        local, gyro, up = r.sensor("local_linvel"), r.sensor("gyro"), r.sensor("upvector")
        moving = np.linalg.norm(cmd, axis=1) >= 0.01
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in FEET], axis=1)
        vel_xy2 = np.sum(feet_vel[..., :2] ** 2, axis=-1)
        return {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "lin_vel_z": r.sensor("global_linvel")[:, 2] ** 2,
            "ang_vel_xy": np.sum(r.sensor("global_angvel")[:, :2] ** 2, axis=1),
            "orientation": np.sum(up[:, :2] ** 2, axis=1),
            # exp(0) = 1 while a command is given, the pose held at a zero one
            "posture": np.exp(np.where(moving, 0.0, -10.0) * np.sum((q - self.default_pose) ** 2, axis=1)),
            "termination": done.astype(np.float64),
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
            "action_rate": self.action_rate(a, idx),
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
            "feet_slip": np.sum(vel_xy2 * contact, axis=1),
            "feet_clearance": np.sum(np.abs(foot_z - self.max_foot_height) * np.sqrt(np.sqrt(vel_xy2)), axis=1),
            "feet_height": np.sum((self.swing_peak[idx] / self.max_foot_height - 1.0) ** 2 * first_contact, axis=1) * moving,
            "feet_air_time": np.sum((self.feet_air_time[idx] - 0.1) * first_contact, axis=1) * moving,
        }


def next_commands(task, idx: np.ndarray, rngs: list, done: np.ndarray) -> None:
    """Spot's command schedule: a new command after 201 steps (the counter restarts then or at a
    termination)."""
    task.step[idx] += 1
    for j, rng in enumerate(rngs):
        if task.step[idx[j]] > 200:
            task.command[idx[j]] = uniform_command(rng, task.cmd_lo, task.cmd_hi)
    task.step[idx] = np.where(done | (task.step[idx] > 200), 0, task.step[idx])


class SpotGaitTracking(Spot):
    """``SpotJoystickGaitTracking``: track a commanded velocity (not observed: Playground's
    observation leaves it out) stepping in a gait drawn per episode (trot, walk, pace, bound or
    pronk) at a drawn frequency and foot height, which the observation holds."""

    sensors = ("gyro", "local_linvel", "upvector", "global_linvel", "global_angvel", *(f"{f}_floor_found" for f in FEET))
    obs_sizes = (69, 69)
    reward_scales = defaults = GAIT_SCALES
    state = ("command", "step", "last_act", "last_last_act", "qpos_error_history", "swing_peak", "last_contact", "gait_freq",
             "gait", "phase", "foot_height")

    def __init__(self, Kp: float = 400.0, Kd: float = 10.0, early_termination: bool = True, action_scale: float = 0.6,
                 joint_pos_noise: float = 0.05, gyro_noise: float = 0.1, gravity_noise: float = 0.03,
                 tracking_sigma: float = 0.25, lin_vel_x=(-1.0, 1.0), lin_vel_y=(-0.5, 0.5), ang_vel_yaw=(-1.0, 1.0),
                 gait_frequency=(0.5, 4.0), foot_height=(0.08, 0.4), reward_scales: dict | None = None):
        self._configure(locals())
        self.early_termination = bool(early_termination)
        self.scales = (float(gyro_noise), float(gravity_noise), float(joint_pos_noise))
        self.sigma = float(tracking_sigma)
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)
        self.freq_range, self.height_range = tuple(map(float, gait_frequency)), tuple(map(float, foot_height))

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.qpos_error_history = np.zeros((n, 36))
        self.swing_peak, self.last_contact = np.zeros((n, 4)), np.zeros((n, 4), dtype=bool)
        self.gait_freq, self.gait, self.foot_height = np.zeros(n), np.zeros(n, dtype=np.int64), np.zeros(n)
        self.phase = np.zeros((n, 4))

    def reset(self, idx: np.ndarray, rngs: list):
        for j, rng in enumerate(rngs):
            draw_gait(self, idx[j], rng, PHASES)
            self.command[idx[j]] = uniform_command(rng, self.cmd_lo, self.cmd_hi)
        for a in (self.step, self.last_act, self.last_last_act, self.qpos_error_history, self.swing_peak, self.last_contact):
            a[idx] = 0
        return np.tile(self.init_q, (len(idx), 1)), np.zeros((len(idx), self.model.nv))

    def observe(self, r, idx: np.ndarray, rngs: list):
        (gyro_n, up_n, q_n), _ = self.noisy(r, rngs, self.scales)
        hist = self.qpos_error_history[idx]
        self.qpos_error_history[idx] = np.hstack([q_n - r.ctrl, hist[:, :24]])
        phase = self.phase[idx]
        state = np.hstack([gyro_n, up_n, q_n, self.qpos_error_history[idx], self.contact(r), np.cos(phase), np.sin(phase),
                           self.gait_freq[idx, None], self.gait[idx, None], self.foot_height[idx, None]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        contact = self.contact(r)
        foot_z = self.foot_z(r)
        self.swing_peak[idx] = np.maximum(self.swing_peak[idx], foot_z)
        state, priv = self.observe(r, idx, rngs)
        done = r.sensor("upvector")[:, 2] < 0.85 if self.early_termination else np.zeros(len(idx), dtype=bool)
        cmd, q = self.command[idx], r.qpos[:, 7:]
        local, gyro = r.sensor("local_linvel"), r.sensor("gyro")
        terms = {
            "feet_phase": np.exp(-np.sum((foot_z - gait_height(self.phase[idx], self.foot_height[idx, None])) ** 2, axis=1) / 0.1),
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "ang_vel_xy": np.sum(r.sensor("global_angvel")[:, :2] ** 2, axis=1),
            # bound and pronk may move the trunk up and down
            "lin_vel_z": r.sensor("global_linvel")[:, 2] ** 2 * (self.gait[idx] > 2),
            "hip_splay": np.sum((q[:, HX] - self.default_pose[HX]) ** 2, axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        gains = sum(terms[k] for k in ("feet_phase", "tracking_lin_vel", "tracking_ang_vel"))
        costs = sum(terms[k] for k in ("ang_vel_xy", "lin_vel_z", "hip_splay"))
        reward = gains * np.exp(0.2 * costs) * self.dt
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        self.phase[idx] = np.fmod(self.phase[idx] + 2 * np.pi * self.dt * self.gait_freq[idx, None] + np.pi, 2 * np.pi) - np.pi
        next_commands(self, idx, rngs, done)
        self.last_contact[idx] = contact
        self.swing_peak[idx] *= ~contact
        return state, priv, reward, done, terms


class SpotGetup(Spot):
    """``SpotGetup``: from a drop at 1 m in a random orientation and joint pose (probability 0.6,
    else standing at home), settled for 0.5 s, get up to the home height and pose and stay still;
    each action moves the servo targets by ``action_scale`` · a from the current joint angles; a
    joint beyond its range ends the episode."""

    xml = f"{SPOT}/scene_mjx_flat_terrain.xml"
    sensors = ("gyro", "upvector")
    obs_sizes = (30, 30)
    reward_scales = defaults = GETUP_SCALES
    state = ("last_act", "last_last_act")
    episode_length = 300

    def __init__(self, Kp: float = 400.0, Kd: float = 20.0, action_scale: float = 0.6, noise_level: float = 1.0,
                 joint_pos_noise: float = 0.01, gyro_noise: float = 0.2, gravity_noise: float = 0.05,
                 drop_from_height_prob: float = 0.6, settle_time: float = 0.5, reward_scales: dict | None = None):
        self._configure(locals())
        level = float(noise_level)
        self.scales = (level * float(gyro_noise), level * float(gravity_noise), level * float(joint_pos_noise))
        self.drop = float(drop_from_height_prob)
        self.settle_steps = int(round(settle_time / self.sim_dt))

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.z_des = self.init_q[2]

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos, qvel = np.tile(self.init_q, (k, 1)), np.zeros((k, self.model.nv))
        for j, rng in enumerate(rngs):
            if rng.random() < self.drop:
                quat = rng.normal(size=4)
                qpos[j] = 0.0
                qpos[j, 2:7] = [1.0, *(quat / (np.linalg.norm(quat) + 1e-6))]
                qpos[j, 7:] = rng.uniform(self.lowers, self.uppers)
        self.last_act[idx] = 0
        self.last_last_act[idx] = 0
        return qpos, qvel

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The drawn joint angles, which the servos hold while the robot settles."""
        return qpos[:, 7:7 + self.model.nu]

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(qpos[:, 7:] + actions * self.action_scale, self.lowers, self.uppers)

    def observe(self, r, idx: np.ndarray, rngs: list):
        (gyro_n, up_n, q_n), _ = self.noisy(r, rngs, self.scales)
        state = np.hstack([gyro_n, up_n, q_n - self.default_pose, self.last_act[idx]]).astype(np.float32)
        return state, state.copy()

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        q, up, tau = r.qpos[:, 7:], r.sensor("upvector"), self.actuator_force(r)
        done = np.any((q < self.lowers) | (q > self.uppers), axis=1)
        tilt = np.sum((np.array([0.0, 0.0, 1.0]) - up) ** 2, axis=1)
        short = np.clip((self.z_des - r.qpos[:, 2]) / self.z_des, 0.0, 1.0)
        upright = tilt < 0.01
        terms = {
            "orientation": np.exp(-2.0 * tilt),
            "torso_height": 1.0 - short,
            "posture": upright * np.exp(-0.5 * np.sum((q - self.default_pose) ** 2, axis=1)),
            "stand_still": (upright & (short < 0.005)) * np.exp(-0.5 * np.sum(actions ** 2, axis=1)),
            "action_rate": self.action_rate(actions, idx),
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()) * self.dt, 0.0, 10000.0)
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        return state, priv, reward, done, terms


TASKS = {"SpotFlatTerrainJoystick": SpotJoystick, "SpotJoystickGaitTracking": SpotGaitTracking, "SpotGetup": SpotGetup}
