"""Unitree Go1's Playground tasks (``mujoco_playground/_src/locomotion/go1``): joystick
velocity tracking on flat and rough terrain, written from Playground's ``joystick.py``,
``base.py`` and ``randomize.py``."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, drop_pose, joystick_step, redraw_commands, servo_gains, limit_cost, site_rot, site_world, soft_limits, uniform_noise

GO1 = "mujoco_playground/_src/locomotion/go1/xmls"
#: Playground's order of the feet (its ``FEET_SITES`` and ``FEET_GEOMS``).
FEET = ("FR", "FL", "RR", "RL")

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(
    tracking_lin_vel=1.0, tracking_ang_vel=0.5, lin_vel_z=-0.5, ang_vel_xy=-0.05, orientation=-5.0,
    dof_pos_limits=-1.0, pose=0.5, termination=-1.0, stand_still=-1.0, torques=-0.0002, action_rate=-0.01,
    energy=-0.001, feet_clearance=-2.0, feet_height=-0.2, feet_slip=-0.1, feet_air_time=0.1)
#: Observation noise half-widths (``noise_config.scales``).
NOISE = dict(joint_pos=0.03, joint_vel=1.5, gyro=0.2, gravity=0.05, linvel=0.1)


class Go1(Task):
    """What Playground's ``Go1Env`` and ``randomize.py`` give every Go1 task: the servo gains, the
    model's ids, domain randomization, the IMU's readings and the servos' forces."""

    camera = dict(distance=1.6, elevation=-20.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.15]))
    #: Each task's soft joint limits: scaled about zero (joystick) or about the range's middle.
    soft_about_middle = True

    def _config(self, Kp, Kd, action_scale, noise_level, soft_joint_pos_limit_factor, defaults: dict, reward_scales):
        self.Kp, self.Kd, self.action_scale, self.noise_level = float(Kp), float(Kd), float(action_scale), float(noise_level)
        self.soft = float(soft_joint_pos_limit_factor)
        unknown = set(reward_scales or {}) - set(defaults)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(defaults)}")
        self.reward_scales = {**defaults, **(reward_scales or {})}

    def setup(self, model, n: int) -> None:
        self.model = model
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[7:].copy()
        lo, hi = model.jnt_range[1:].T
        self.soft_lo, self.soft_hi = soft_limits(lo, hi, self.soft, self.soft_about_middle)
        self.lowers, self.uppers = lo, hi
        self.imu = model.site_names.index("imu")
        self.trunk = model.body_names.index("trunk")
        self.floor = model.geom_names.index("floor")
        self.ctrl_lo, self.ctrl_hi = model.actuator_ctrlrange.T
        self.force_lo, self.force_hi = model.actuator_forcerange.T
        self.kp = np.full(model.nu, self.Kp)
        self.last_act, self.last_last_act = np.zeros((n, model.nu)), np.zeros((n, model.nu))

    def model_edits(self) -> dict:
        """Playground's ``Go1Env`` sets the joints' damping to Kd and the servos' gains to Kp."""
        return servo_gains(self.model, self.Kp, self.Kd)

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """``randomize.domain_randomize``: floor friction U(0.4, 1), joint friction ×U(0.9, 1.1),
        armature ×U(1, 1.05), trunk centre of mass +U(−5, 5) cm, every mass ×U(0.9, 1.1) and the
        trunk's +U(−1, 1) kg."""
        m, k = self.model, len(idx)
        friction = np.repeat(m.param("geom_friction")[None], k, axis=0)
        fl, arm = np.repeat(m.param("dof_frictionloss")[None], k, 0), np.repeat(m.param("dof_armature")[None], k, 0)
        ipos, mass = np.repeat(m.param("body_ipos")[None], k, 0), np.repeat(m.param("body_mass")[None], k, 0)
        for j, rng in enumerate(rngs):
            friction[j, self.floor, 0] = rng.uniform(0.4, 1.0)
            fl[j, 6:] *= rng.uniform(0.9, 1.1, 12)
            arm[j, 6:] *= rng.uniform(1.0, 1.05, 12)
            ipos[j, self.trunk] += rng.uniform(-0.05, 0.05, 3)
            mass[j] *= rng.uniform(0.9, 1.1, m.nbody)
            mass[j, self.trunk] += rng.uniform(-1.0, 1.0)
        for field, values in (("geom_friction", friction), ("dof_frictionloss", fl), ("dof_armature", arm),
                              ("body_ipos", ipos), ("body_mass", mass)):
            batch.set_params(field, values, idx)

    def _imu_rot(self, r) -> np.ndarray:
        """The IMU site's world rotation (worlds, 3, 3)."""
        return site_rot(r, self.model, self.imu)

    def _gravity(self, r) -> np.ndarray:
        """The world's −z in the IMU's frame."""
        return -self._imu_rot(r)[:, 2, :]

    def _torso_height(self, r) -> np.ndarray:
        return site_world(r, self.model, self.imu)[:, 2]

    def _actuator_force(self, r) -> np.ndarray:
        """The position servos' forces: Kp (clamped target − q), clamped to the force range."""
        target = np.clip(r.ctrl, self.ctrl_lo, self.ctrl_hi)
        return np.clip(self.kp * (target - r.qpos[:, 7:]), self.force_lo, self.force_hi)

    def _noise(self, rngs: list, n: int) -> np.ndarray:
        return uniform_noise(rngs, n, self.noise_level)


class Go1Joystick(Go1):
    """``Go1JoystickFlatTerrain`` / ``Go1JoystickRoughTerrain``: track a commanded planar velocity
    and yaw rate (``info["command"]``: vx, vy, ωz, redrawn after exponentially distributed
    times with mean 5 s)."""

    xml = f"{GO1}/scene_mjx_feetonly_flat_terrain.xml"
    sensors = ("gyro", "local_linvel", "accelerometer", "upvector", "global_linvel", "global_angvel",
               *(f"{f}_global_linvel" for f in FEET), *(f"{f}_floor_found" for f in FEET))
    obs_sizes = (48, 123)
    reward_scales = JOYSTICK_SCALES
    state = ("command", "steps_until_next_cmd", "last_act", "last_last_act", "feet_air_time", "swing_peak", "last_contact")
    soft_about_middle = False

    def __init__(self, Kp: float = 35.0, Kd: float = 0.5, action_scale: float = 0.5, noise_level: float = 1.0,
                 tracking_sigma: float = 0.25, max_foot_height: float = 0.1, soft_joint_pos_limit_factor: float = 0.95,
                 command_a=(1.5, 0.8, 1.2), command_b=(0.9, 0.25, 0.5), reward_scales: dict | None = None):
        self.kwargs = dict(Kp=Kp, Kd=Kd, action_scale=action_scale, noise_level=noise_level, tracking_sigma=tracking_sigma,
                           max_foot_height=max_foot_height, soft_joint_pos_limit_factor=soft_joint_pos_limit_factor,
                           command_a=command_a, command_b=command_b)
        self._config(Kp, Kd, action_scale, noise_level, soft_joint_pos_limit_factor, JOYSTICK_SCALES, reward_scales)
        self.sigma, self.max_foot_height = float(tracking_sigma), float(max_foot_height)
        self.cmd_a, self.cmd_b = np.asarray(command_a, dtype=np.float64), np.asarray(command_b, dtype=np.float64)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.feet_sites = [model.site_names.index(f) for f in FEET]
        self.command = np.zeros((n, 3))
        self.steps_until_next_cmd = np.zeros(n, dtype=np.int64)
        self.feet_air_time, self.swing_peak = np.zeros((n, 4)), np.zeros((n, 4))
        self.last_contact = np.zeros((n, 4), dtype=bool)

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos, qvel = np.tile(self.init_q, (k, 1)), np.zeros((k, self.model.nv))
        drop_pose(rngs, qpos, qvel)
        for j, rng in enumerate(rngs):
            self.steps_until_next_cmd[idx[j]] = round(rng.exponential() * 5.0 / self.dt)
            self.command[idx[j]] = rng.uniform(-self.cmd_a, self.cmd_a)
        for a in (self.last_act, self.last_last_act, self.feet_air_time, self.swing_peak, self.last_contact):
            a[idx] = 0
        return qpos, qvel

    def observe(self, r, idx: np.ndarray, rngs: list):
        gyro, linvel, gravity = r.sensor("gyro"), r.sensor("local_linvel"), self._gravity(r)
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        u = self._noise(rngs, 33)
        state = np.hstack([
            linvel + u[:, 0:3] * NOISE["linvel"], gyro + u[:, 3:6] * NOISE["gyro"],
            gravity + u[:, 6:9] * NOISE["gravity"], q + u[:, 9:21] * NOISE["joint_pos"] - self.default_pose,
            qd + u[:, 21:33] * NOISE["joint_vel"], self.last_act[idx], self.command[idx]])
        feet_vel = np.hstack([r.sensor(f"{f}_global_linvel") for f in FEET])
        push = np.zeros((len(idx), 4))     # the applied push (3) and whether one is under way: none
        priv = np.hstack([state, gyro, r.sensor("accelerometer"), gravity, linvel, r.sensor("global_angvel"),
                          q - self.default_pose, qd, self._actuator_force(r), self.last_contact[idx], feet_vel,
                          self.feet_air_time[idx], push])
        return state.astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        contact = np.hstack([r.sensor(f"{f}_floor_found") for f in FEET]) > 0
        foot_z = np.stack([site_world(r, self.model, s)[:, 2] for s in self.feet_sites], axis=1)
        done = r.sensor("upvector")[:, 2] < 0.0
        return joystick_step(self, r, actions, idx, rngs, contact, foot_z, done, redraw_commands)

    def sample_command(self, rng, x: np.ndarray) -> np.ndarray:
        """``sample_command``: each component kept with probability 1/2, else redrawn from
        U(−a, a) and zeroed with probability 1 − b."""
        y = rng.uniform(-self.cmd_a, self.cmd_a)
        z = rng.random(3) < self.cmd_b
        w = rng.random(3) < 0.5
        return x - w * (x - y * z)

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        cmd = self.command[idx]
        local, gyro = r.sensor("local_linvel"), r.sensor("gyro")
        glin, gang, up = r.sensor("global_linvel"), r.sensor("global_angvel"), r.sensor("upvector")
        q, qd, tau = r.qpos[:, 7:], r.qvel[:, 6:], self._actuator_force(r)
        moving = np.linalg.norm(cmd, axis=1) > 0.01
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in FEET], axis=1)
        vel_xy2 = np.sum(feet_vel[..., :2] ** 2, axis=-1)
        dq = q - self.default_pose
        return {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "lin_vel_z": glin[:, 2] ** 2,
            "ang_vel_xy": np.sum(gang[:, :2] ** 2, axis=1),
            "orientation": np.sum(up[:, :2] ** 2, axis=1),
            "dof_pos_limits": limit_cost(q, self.soft_lo, self.soft_hi),
            "pose": np.exp(-np.sum(dq ** 2 * np.tile([1.0, 1.0, 0.1], 4), axis=1)),
            "termination": done.astype(np.float64),
            "stand_still": np.sum(np.abs(dq), axis=1) * ~moving,
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((a - self.last_act[idx]) ** 2, axis=1),
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
            "feet_clearance": np.sum(np.abs(foot_z - self.max_foot_height) * np.sqrt(np.sqrt(vel_xy2)), axis=1),
            "feet_height": np.sum((self.swing_peak[idx] / self.max_foot_height - 1.0) ** 2 * first_contact, axis=1) * moving,
            "feet_slip": np.sum(vel_xy2 * contact, axis=1) * moving,
            "feet_air_time": np.sum((self.feet_air_time[idx] - 0.1) * first_contact, axis=1) * moving,
        }


class Go1JoystickRough(Go1Joystick):
    """``Go1JoystickRoughTerrain``: the same task on Playground's height-field terrain."""

    xml = f"{GO1}/scene_mjx_feetonly_rough_terrain.xml"


#: Reward scales of Playground's ``handstand.default_config()``.
HANDSTAND_SCALES = dict(height=1.0, orientation=1.0, contact=-0.1, action_rate=0.0, termination=0.0, dof_pos_limits=-0.5,
                        torques=0.0, pose=-0.1, stay_still=0.0, energy=0.0, dof_acc=0.0)
#: The geoms whose touching the floor ends a handstand or footstand (Playground's
#: ``sensor_fullcollision.xml``: the front legs' for both tasks).
FRONT_LEG = ("fl_calf1", "fl_calf2", "fr_calf1", "fr_calf2", "fl_thigh1", "fl_thigh2", "fl_thigh3", "fr_thigh1", "fr_thigh2",
             "fr_thigh3", "fl_hip", "fr_hip")


class Go1Handstand(Go1):
    """``Go1Handstand``: rise onto the front legs and hold the trunk pointing down at 0.55 m;
    each action moves the servo targets by ``action_scale`` · a from the last targets."""

    xml = f"{GO1}/scene_mjx_flat_terrain.xml"
    sensors = ("gyro", "local_linvel", "accelerometer", "upvector", "global_angvel",
               *(f"{f}_floor_found" for f in FEET), *(f"{g}_floor_found" for g in FRONT_LEG))
    obs_sizes = (45, 94)
    reward_scales = HANDSTAND_SCALES
    state = ("last_act",)
    episode_length = 500
    #: The trunk's desired height, its x axis's desired direction and the joints held at home.
    z_des, forward_des, held = 0.55, np.array([0.0, 0.0, -1.0]), slice(6, 12)

    def __init__(self, Kp: float = 35.0, Kd: float = 0.5, action_scale: float = 0.3, noise_level: float = 1.0,
                 soft_joint_pos_limit_factor: float = 0.9, reward_scales: dict | None = None):
        self.kwargs = dict(Kp=Kp, Kd=Kd, action_scale=action_scale, noise_level=noise_level,
                           soft_joint_pos_limit_factor=soft_joint_pos_limit_factor)
        self._config(Kp, Kd, action_scale, noise_level, soft_joint_pos_limit_factor, HANDSTAND_SCALES, reward_scales)
        self.needs_qacc = self.reward_scales["dof_acc"] != 0.0

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos, qvel = np.tile(self.init_q, (k, 1)), np.zeros((k, self.model.nv))
        drop_pose(rngs, qpos, qvel)
        self.last_act[idx] = 0
        return qpos, qvel

    def motor_targets(self, actions, qpos, ctrl, idx):
        return ctrl + actions * self.action_scale

    def observe(self, r, idx: np.ndarray, rngs: list):
        gyro, linvel, gravity = r.sensor("gyro"), r.sensor("local_linvel"), self._gravity(r)
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        u = self._noise(rngs, 33)
        state = np.hstack([linvel + u[:, 0:3] * 0.1, gyro + u[:, 3:6] * 0.2, gravity + u[:, 6:9] * 0.05,
                           q + u[:, 9:21] * 0.01 - self.default_pose, qd + u[:, 21:33] * 1.5, self.last_act[idx]])
        priv = np.hstack([state, gyro, r.sensor("accelerometer"), linvel, r.sensor("global_angvel"), q, qd,
                          self._actuator_force(r), self._torso_height(r)[:, None]])
        return state.astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        touching = np.hstack([r.sensor(f"{g}_floor_found") for g in FRONT_LEG]) > 0
        done = (r.sensor("upvector")[:, 2] < -0.25) | touching.any(axis=1)
        tau, q, qd = self._actuator_force(r), r.qpos[:, 7:], r.qvel[:, 6:]
        height = np.minimum(self._torso_height(r), self.z_des)
        forward = self._imu_rot(r)[:, :, 0]
        feet = np.hstack([r.sensor(f"{f}_floor_found") for f in FEET]) > 0
        terms = {
            "height": np.exp(-(self.z_des - height)),
            "orientation": (0.5 * forward @ self.forward_des + 0.5) ** 2,
            "contact": feet.any(axis=1).astype(np.float64),
            "action_rate": np.sum((actions - self.last_act[idx]) ** 2, axis=1),
            "torques": np.sum(tau ** 2, axis=1),
            "termination": done.astype(np.float64),
            "dof_pos_limits": limit_cost(q, self.soft_lo, self.soft_hi),
            "dof_acc": np.sum(r.qacc[:, 6:] ** 2, axis=1) if self.needs_qacc else np.zeros(len(idx)),
            "pose": np.sum((q[:, self.held] - self.default_pose[self.held]) ** 2, axis=1),
            "stay_still": np.sum(r.qvel[:, :2] ** 2, axis=1) + r.qvel[:, 5] ** 2,
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()) * self.dt, 0.0, 10000.0)
        self.last_act[idx] = actions
        return state, priv, reward, done, terms


class Go1Footstand(Go1Handstand):
    """``Go1Footstand``: rise onto the hind legs, the trunk pointing up at 0.53 m (the front legs'
    geoms touching the floor end it, as in Playground, which keeps the handstand's list)."""

    z_des, forward_des, held = 0.53, np.array([0.0, 0.0, 1.0]), slice(0, 6)


#: Reward scales of Playground's ``getup.default_config()``.
GETUP_SCALES = dict(orientation=1.0, torso_height=1.0, posture=1.0, stand_still=1.0, action_rate=-0.001, dof_pos_limits=-0.1,
                    torques=-1e-5, dof_acc=-2.5e-7, dof_vel=-0.1)


class Go1Getup(Go1):
    """``Go1Getup``: from a drop at 0.5 m in a random orientation and joint pose (probability
    0.6, else standing), settled for 0.5 s, get up to the home pose at 0.275 m and stay still;
    each action moves the servo targets by ``action_scale`` · a from the current joint angles."""

    xml = f"{GO1}/scene_mjx_fullcollisions_flat_terrain.xml"
    sensors = ("gyro", "local_linvel", "accelerometer", "global_angvel")
    obs_sizes = (42, 91)
    reward_scales = GETUP_SCALES
    state = ("last_act", "last_last_act")
    episode_length = 300
    z_des = 0.275

    def __init__(self, Kp: float = 35.0, Kd: float = 0.5, action_scale: float = 0.5, noise_level: float = 1.0,
                 soft_joint_pos_limit_factor: float = 0.95, drop_from_height_prob: float = 0.6, settle_time: float = 0.5,
                 reward_scales: dict | None = None):
        self.kwargs = dict(Kp=Kp, Kd=Kd, action_scale=action_scale, noise_level=noise_level,
                           soft_joint_pos_limit_factor=soft_joint_pos_limit_factor,
                           drop_from_height_prob=drop_from_height_prob, settle_time=settle_time)
        self._config(Kp, Kd, action_scale, noise_level, soft_joint_pos_limit_factor, GETUP_SCALES, reward_scales)
        self.drop = float(drop_from_height_prob)
        self.settle_steps = int(settle_time / self.sim_dt)
        self.needs_qacc = self.reward_scales["dof_acc"] != 0.0

    def reset(self, idx: np.ndarray, rngs: list):
        k = len(idx)
        qpos, qvel = np.tile(self.init_q, (k, 1)), np.zeros((k, self.model.nv))
        for j, rng in enumerate(rngs):
            if rng.random() < self.drop:
                quat = rng.normal(size=4)
                qpos[j, :7] = [0.0, 0.0, 0.5, *(quat / (np.linalg.norm(quat) + 1e-6))]
                qpos[j, 7:] = rng.uniform(self.lowers, self.uppers)
            qvel[j, 0:6] = rng.uniform(-0.5, 0.5, 6)
        self.last_act[idx] = 0
        self.last_last_act[idx] = 0
        return qpos, qvel

    def motor_targets(self, actions, qpos, ctrl, idx):
        return qpos[:, 7:] + actions * self.action_scale

    def observe(self, r, idx: np.ndarray, rngs: list):
        gyro, gravity = r.sensor("gyro"), self._gravity(r)
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        u = self._noise(rngs, 30)
        state = np.hstack([gyro + u[:, 0:3] * 0.2, gravity + u[:, 3:6] * 0.05, q + u[:, 6:18] * 0.03 - self.default_pose,
                           qd + u[:, 18:30] * 1.5, self.last_act[idx]])
        priv = np.hstack([state, gyro, r.sensor("accelerometer"), r.sensor("local_linvel"), r.sensor("global_angvel"), q, qd,
                          self._actuator_force(r), self._torso_height(r)[:, None]])
        return state.astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        gravity, q, qd, tau = self._gravity(r), r.qpos[:, 7:], r.qvel[:, 6:], self._actuator_force(r)
        height = np.minimum(self._torso_height(r), self.z_des)
        tilt = np.sum((np.array([0.0, 0.0, -1.0]) - gravity) ** 2, axis=1)
        upright = tilt < 0.01
        gate = upright & (self.z_des - height < 0.005)
        last, last_last = self.last_act[idx], self.last_last_act[idx]
        terms = {
            "orientation": np.exp(-2.0 * tilt),
            "torso_height": np.exp(height) - 1.0,
            # Playground gates the posture on uprightness alone, the stillness on height too
            "posture": upright * np.exp(-0.5 * np.sum((q - self.default_pose) ** 2, axis=1)),
            "stand_still": gate * np.exp(-0.5 * np.sum(actions ** 2, axis=1)),
            "action_rate": np.sum((actions - last) ** 2, axis=1) + np.sum((actions - 2 * last + last_last) ** 2, axis=1),
            "torques": np.sqrt(np.sum(tau ** 2, axis=1)) + np.sum(np.abs(tau), axis=1),
            "dof_pos_limits": limit_cost(q, self.soft_lo, self.soft_hi),
            "dof_acc": np.sum(r.qacc[:, 6:] ** 2, axis=1) if self.needs_qacc else np.zeros(len(idx)),
            "dof_vel": np.sum(np.maximum(np.abs(qd) - 2.0 * np.pi, 0.0) ** 2, axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = np.clip(sum(terms.values()) * self.dt, 0.0, 10000.0)
        self.last_last_act[idx] = last
        self.last_act[idx] = actions
        # Playground ends a getup episode only above an energy threshold, infinite by default
        return state, priv, reward, np.zeros(len(idx), dtype=bool), terms


TASKS = {"Go1JoystickFlatTerrain": Go1Joystick, "Go1JoystickRoughTerrain": Go1JoystickRough, "Go1Getup": Go1Getup,
         "Go1Handstand": Go1Handstand, "Go1Footstand": Go1Footstand}
