"""The Berkeley Humanoid's Playground tasks (``mujoco_playground/_src/locomotion/berkeley_humanoid``):
joystick velocity tracking with a gait clock on flat and rough terrain, written from Playground's
``joystick.py``, ``base.py`` and ``randomize.py``: T1's task with this robot's legs, noise,
rewards and randomization."""

from __future__ import annotations

import numpy as np

from sinew.playground.t1 import T1Joystick

BERKELEY = "mujoco_playground/_src/locomotion/berkeley_humanoid/xmls"

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(
    tracking_lin_vel=1.0, tracking_ang_vel=0.5, lin_vel_z=0.0, ang_vel_xy=-0.15, orientation=-1.0, base_height=0.0,
    torques=-2.5e-5, action_rate=-0.01, energy=0.0, feet_clearance=0.0, feet_air_time=2.0, feet_slip=-0.25,
    feet_height=0.0, feet_phase=1.0, stand_still=0.0, alive=0.0, termination=-1.0, joint_deviation_knee=-0.1,
    joint_deviation_hip=-0.25, dof_pos_limits=-1.0, pose=-1.0)


class BerkeleyHumanoidJoystick(T1Joystick):
    """``BerkeleyHumanoidJoystickFlatTerrain`` / ``...RoughTerrain``: T1's joystick task on the
    12-joint Berkeley Humanoid (its clock keeps running at a zero command)."""

    xml = f"{BERKELEY}/scene_mjx_feetonly_flat_terrain.xml"
    camera = dict(distance=2.0, elevation=-15.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.45]))
    feet = ("l_foot", "r_foot")
    foot_contacts = (("l_foot1_floor_found",), ("r_foot1_floor_found",))
    sensors = ("gyro", "local_linvel", "accelerometer", "upvector", "global_linvel", "global_angvel",
               *(f"{f}_global_linvel" for f in feet), *(s for foot in foot_contacts for s in foot))
    obs_sizes = (52, 114)
    reward_scales = JOYSTICK_SCALES
    torso_body = "torso"
    hip_joints = ("LL_HR", "LL_HAA", "LR_HR", "LR_HAA")
    knee_joints = ("LL_KFE", "LR_KFE")
    gait_frequency = (1.25, 1.5)
    pose_weights = np.array([1.0, 1.0, 0.01, 0.01, 1.0, 1.0] * 2)

    def __init__(self, action_scale: float = 0.5, noise_level: float = 1.0, soft_joint_pos_limit_factor: float = 0.95,
                 tracking_sigma: float = 0.5, max_foot_height: float = 0.1, base_height_target: float = 0.5,
                 push_enable: bool = True, push_interval_range=(5.0, 10.0), push_magnitude_range=(0.1, 2.0),
                 lin_vel_x=(-1.0, 1.0), lin_vel_y=(-1.0, 1.0), ang_vel_yaw=(-1.0, 1.0), reward_scales: dict | None = None):
        self._configure(locals())

    def joint_pos_noise(self, nu: int) -> np.ndarray:
        """Per joint, each leg's: hips 0.03, knee 0.05, ankle flexion 0.08, ankle roll 0.03 rad."""
        return np.array([0.03, 0.03, 0.03, 0.05, 0.08, 0.03] * 2)

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """``randomize.domain_randomize``: floor friction U(0.4, 1), joint friction ×U(0.9, 1.1),
        armature ×U(1, 1.05), every mass ×U(0.9, 1.1) and the torso's +U(−1, 1) kg (``qpos0``'s
        jitter left out, as G1's)."""
        m, k = self.model, len(idx)
        rep = {f: np.repeat(m.param(f)[None], k, 0) for f in ("geom_friction", "dof_frictionloss", "dof_armature", "body_mass")}
        for j, rng in enumerate(rngs):
            rep["geom_friction"][j, 0, 0] = rng.uniform(0.4, 1.0)
            rep["dof_frictionloss"][j, 6:] *= rng.uniform(0.9, 1.1, m.nv - 6)
            rep["dof_armature"][j, 6:] *= rng.uniform(1.0, 1.05, m.nv - 6)
            rep["body_mass"][j] *= rng.uniform(0.9, 1.1, m.nbody)
            rep["body_mass"][j, self.torso] += rng.uniform(-1.0, 1.0)
        for field, values in rep.items():
            batch.set_params(field, values, idx)

    def advance_phase(self, idx: np.ndarray) -> None:
        """The gait clock's step, wrapped to [−π, π) (running at a zero command too)."""
        super(T1Joystick, self).advance_phase(idx)

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        v, w = r.sensor("global_linvel"), r.sensor("global_angvel")
        return {**self._shared_terms(r, a, idx, done, first_contact, contact, foot_z),
                "lin_vel_z": v[:, 2] ** 2, "ang_vel_xy": np.sum(w[:, :2] ** 2, axis=1)}


class BerkeleyHumanoidJoystickRough(BerkeleyHumanoidJoystick):
    """``BerkeleyHumanoidJoystickRoughTerrain``: the same task on Playground's height-field terrain."""

    xml = f"{BERKELEY}/scene_mjx_feetonly_rough_terrain.xml"


TASKS = {"BerkeleyHumanoidJoystickFlatTerrain": BerkeleyHumanoidJoystick,
         "BerkeleyHumanoidJoystickRoughTerrain": BerkeleyHumanoidJoystickRough}
