"""Booster T1's Playground tasks (``mujoco_playground/_src/locomotion/t1``): joystick velocity
tracking with a gait clock on flat and rough terrain, written from Playground's ``joystick.py``,
``base.py`` and ``randomize.py``: G1's task with T1's sensors, rewards and randomization."""

from __future__ import annotations

import numpy as np

from sinew.playground.g1 import FEET, G1Joystick
from sinew.playground.task import gait_height, limit_cost, site_rot, site_world

T1 = "mujoco_playground/_src/locomotion/t1/xmls"

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(
    tracking_lin_vel=1.0, tracking_ang_vel=0.5, lin_vel_z=0.0, ang_vel_xy=-0.15, orientation=-1.0, base_height=0.0,
    torques=0.0, action_rate=0.0, energy=0.0, dof_acc=0.0, dof_vel=0.0, feet_clearance=0.0, feet_air_time=2.0,
    feet_slip=-0.25, feet_height=0.0, feet_phase=1.0, stand_still=0.0, alive=0.25, termination=0.0,
    joint_deviation_knee=-0.1, joint_deviation_hip=-0.1, dof_pos_limits=-1.0, pose=-1.0, feet_distance=-1.0,
    collision=-1.0)
#: ``_weights`` of the pose cost: head, arms, waist, legs.
POSE_WEIGHTS = np.array([1.0, 1.0, 0.1, 1.0, 1.0, 1.0, 0.1, 1.0, 1.0, 1.0, 1.0,
                         0.01, 1.0, 1.0, 0.01, 1.0, 1.0, 0.01, 1.0, 1.0, 0.01, 1.0, 1.0])
#: The ankles' dofs, whose damping the randomization scales (``ANKLE_JOINT_IDS``).
ANKLE_DOFS = [21, 22, 27, 28]


class T1Joystick(G1Joystick):
    """``T1JoystickFlatTerrain`` / ``T1JoystickRoughTerrain``: track a commanded planar velocity
    and yaw rate (redrawn every 10 s) with a two-foot gait clock, held still at a zero command,
    through random pushes; the reward clipped at 0."""

    xml = f"{T1}/scene_mjx_feetonly_flat_terrain.xml"
    camera = dict(distance=2.5, elevation=-15.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.6]))
    foot_contacts = tuple(tuple(f"{f}_{i}_floor_found" for i in range(1, 5)) for f in FEET)
    sensors = ("gyro", "local_linvel", "accelerometer", "upvector", "global_linvel", "global_angvel",
               *(f"{f}_global_linvel" for f in FEET), *(s for foot in foot_contacts for s in foot), "left_foot_right_foot_found")
    obs_sizes = (85, 180)
    reward_scales = JOYSTICK_SCALES
    keyframe, imu_site, torso_body = "home", "imu", "Trunk"
    gyro, linvel, angvel, accel = "gyro", "local_linvel", "global_angvel", "accelerometer"
    hip_joints = ("Left_Hip_Roll", "Left_Hip_Yaw", "Right_Hip_Roll", "Right_Hip_Yaw")
    knee_joints = ("Left_Knee_Pitch", "Right_Knee_Pitch")
    gait_frequency, clip_reward = (1.25, 1.75), True
    pose_weights = POSE_WEIGHTS

    def __init__(self, action_scale: float = 1.0, noise_level: float = 1.0, soft_joint_pos_limit_factor: float = 0.95,
                 tracking_sigma: float = 0.25, max_foot_height: float = 0.12, base_height_target: float = 0.665,
                 push_enable: bool = True, push_interval_range=(5.0, 10.0), push_magnitude_range=(0.1, 1.0),
                 lin_vel_x=(-1.0, 1.0), lin_vel_y=(-0.8, 0.8), ang_vel_yaw=(-1.0, 1.0), reward_scales: dict | None = None):
        self._configure(locals())

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """``randomize.domain_randomize``: floor friction U(0.2, 0.6), joint friction ×U(0.9, 1.1),
        armature ×U(1, 1.05), every mass ×U(0.98, 1.02) and the trunk's +U(−1, 1) kg, servo gains
        ×U(0.9, 1.1), the ankles' damping ×U(0.5, 2) (``qpos0``'s jitter left out, as G1's)."""
        m, k = self.model, len(idx)
        rep = {f: np.repeat(m.param(f)[None], k, 0) for f in ("geom_friction", "dof_frictionloss", "dof_armature",
                                                            "body_mass", "actuator_gain", "actuator_bias", "dof_damping")}
        for j, rng in enumerate(rngs):
            rep["geom_friction"][j, 0, 0] = rng.uniform(0.2, 0.6)
            rep["dof_frictionloss"][j, 6:] *= rng.uniform(0.9, 1.1, m.nv - 6)
            rep["dof_armature"][j, 6:] *= rng.uniform(1.0, 1.05, m.nv - 6)
            rep["body_mass"][j] *= rng.uniform(0.98, 1.02, m.nbody)
            rep["body_mass"][j, self.torso] += rng.uniform(-1.0, 1.0)
            kp = rep["actuator_gain"][j, :, 0] * rng.uniform(0.9, 1.1, m.nu)
            rep["actuator_gain"][j, :, 0], rep["actuator_bias"][j, :, 1] = kp, -kp
            rep["dof_damping"][j, ANKLE_DOFS] *= rng.uniform(0.5, 2.0, len(ANKLE_DOFS))
        for field, values in rep.items():
            batch.set_params(field, values, idx)
        self.gain[idx], self.bias[idx] = rep["actuator_gain"][..., 0], rep["actuator_bias"]

    def terminated(self, r) -> np.ndarray:
        """The trunk upside down."""
        return r.sensor("upvector")[:, 2] < 0.0

    def advance_phase(self, idx: np.ndarray) -> None:
        """The gait clock's step; both feet held at phase π while the command is zero."""
        super().advance_phase(idx)
        still = np.linalg.norm(self.command[idx], axis=1) <= 0.01
        self.phase[idx[still]] = np.pi

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        local, gyro, qd = r.sensor("local_linvel"), r.sensor("gyro"), r.qvel[:, 6:]
        rot = site_rot(r, self.model, self.imu)
        yaw = np.arctan2(rot[:, 1, 0], rot[:, 0, 0])
        left, right = (site_world(r, self.model, s)[:, :2] for s in self.feet_sites)
        across = np.abs(np.cos(yaw) * (left[:, 1] - right[:, 1]) - np.sin(yaw) * (left[:, 0] - right[:, 0]))
        return {
            **self._shared_terms(r, a, idx, done, first_contact, contact, foot_z),
            "lin_vel_z": local[:, 2] ** 2,
            "ang_vel_xy": np.sum(gyro[:, :2] ** 2, axis=1),
            "dof_acc": np.sum(r.qacc[:, 6:] ** 2, axis=1) if self.needs_qacc else np.zeros(len(idx)),
            "dof_vel": np.sum(qd ** 2, axis=1),
            "collision": (r.sensor("left_foot_right_foot_found")[:, 0] > 0).astype(np.float64),
            "feet_distance": np.clip(0.2 - across, 0.0, 0.1),
        }

    def _shared_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        """The terms T1's and the Berkeley Humanoid's tasks compute alike."""
        cmd, q, qd, tau = self.command[idx], r.qpos[:, 7:], r.qvel[:, 6:], self.actuator_force(r)
        local, gyro = r.sensor("local_linvel"), r.sensor("gyro")
        feet_vel = np.stack([r.sensor(f"{f}_global_linvel") for f in self.feet], axis=1)
        cmd_norm = np.linalg.norm(cmd, axis=1)
        dq = q - self.default_pose
        air = np.sum(np.minimum((self.feet_air_time[idx] - 0.2) * first_contact, 0.3), axis=1)
        return {
            "tracking_lin_vel": np.exp(-np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1) / self.sigma),
            "tracking_ang_vel": np.exp(-((cmd[:, 2] - gyro[:, 2]) ** 2) / self.sigma),
            "orientation": np.sum(r.sensor("upvector")[:, :2] ** 2, axis=1),
            "base_height": (r.qpos[:, 2] - self.base_height_target) ** 2,
            "torques": np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((a - self.last_act[idx]) ** 2, axis=1),
            "energy": np.sum(np.abs(qd * tau), axis=1),
            "feet_slip": np.linalg.norm(r.sensor("global_linvel")[:, :2], axis=1) * contact.sum(axis=1),
            "feet_clearance": np.sum(np.abs(foot_z - self.max_foot_height) * np.linalg.norm(feet_vel[..., :2], axis=-1) ** 0.5, axis=1),
            "feet_height": np.sum((self.swing_peak[idx] / self.max_foot_height - 1.0) ** 2 * first_contact, axis=1),
            "feet_air_time": air * (cmd_norm > 0.1),
            "feet_phase": np.exp(-np.sum((foot_z - gait_height(self.phase[idx], self.max_foot_height)) ** 2, axis=1) / 0.01),
            "alive": np.ones(len(idx)),
            "termination": done.astype(np.float64),
            "stand_still": np.sum(np.abs(dq), axis=1) * (cmd_norm < 0.1),
            "joint_deviation_hip": np.sum(np.abs(dq[:, self.hips]), axis=1) * (np.abs(cmd[:, 1]) > 0.1),
            "joint_deviation_knee": np.sum(np.abs(dq[:, self.knees]), axis=1),
            "dof_pos_limits": limit_cost(q, self.soft_lo, self.soft_hi),
            "pose": np.sum(dq ** 2 * self.pose_weights, axis=1),
        }


class T1JoystickRough(T1Joystick):
    """``T1JoystickRoughTerrain``: the same task on Playground's height-field terrain."""

    xml = f"{T1}/scene_mjx_feetonly_rough_terrain.xml"


TASKS = {"T1JoystickFlatTerrain": T1Joystick, "T1JoystickRoughTerrain": T1JoystickRough}
