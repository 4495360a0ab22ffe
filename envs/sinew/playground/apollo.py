"""Apptronik Apollo's Playground task (``mujoco_playground/_src/locomotion/apollo``): joystick
velocity tracking with a gait clock on flat terrain, written from Playground's ``joystick.py`` and
``base.py`` (no domain randomization: Playground has none for Apollo)."""

from __future__ import annotations

import numpy as np

from sinew.playground.t1 import T1Joystick
from sinew.playground.task import gait_height, redraw_commands

APOLLO = "mujoco_playground/_src/locomotion/apollo/xmls"

#: Reward scales of Playground's ``joystick.default_config()``.
JOYSTICK_SCALES = dict(tracking=1.0, lin_vel_z=0.0, ang_vel_xy=-0.15, orientation=-1.0, torques=0.0, action_rate=0.0,
                       energy=0.0, feet_phase=1.0, alive=0.0, termination=0.0, pose=-1.0, collision=-1.0)
#: The pose cost's ``_weights``: torso, neck, arms, legs (the hip rolls, 21 and 27, lightened
#: under a lateral command).
POSE_WEIGHTS = np.array([5.0, 5.0, 5.0, 1.0, 1.0, 1.0, *[1.0, 1.0, 0.1, 1.0, 1.0, 1.0, 1.0] * 2, *[1.0, 1.0, 0.01, 0.01, 1.0, 1.0] * 2])
#: The contact sensors whose reading is a self-collision: hands on thighs, feet, shins, thighs.
COLLISIONS = ("collision_l_hand_plate_collision_capsule_body_l_thigh_found",
              "collision_r_hand_plate_collision_capsule_body_r_thigh_found", "collision_l_sole_collision_r_sole_found",
              "collision_capsule_body_l_shin_collision_capsule_body_r_shin_found",
              "collision_capsule_body_l_thigh_collision_capsule_body_r_thigh_found")


class ApolloJoystick(T1Joystick):
    """``ApolloJoystickFlatTerrain``: track a commanded planar velocity and yaw rate, redrawn
    after exponentially distributed waits of mean 5 s as Go1's, with a gait clock held still at a
    zero command, through random pushes; targets about the keyframe's controls."""

    xml = f"{APOLLO}/scene_mjx_feetonly_flat_terrain.xml"
    sim_dt = 0.005
    camera = dict(distance=3.0, elevation=-15.0, azimuth=120.0, trackbodyid=1, lookat=np.array([0.0, 0.0, 0.8]))
    feet = ("l_foot", "r_foot")
    foot_contacts = (("collision_l_sole_floor_found",), ("collision_r_sole_floor_found",))
    sensors = ("gyro", "local_linvel", "upvector", *(s for foot in foot_contacts for s in foot), *COLLISIONS)
    obs_sizes = (112, 224)
    reward_scales = JOYSTICK_SCALES
    state = (*T1Joystick.state, "steps_until_next_cmd")
    keyframe, torso_body = "knees_bent", "torso_link"
    hip_joints, knee_joints = (), ()
    gait_frequency, clip_reward = (1.25, 1.75), False

    def __init__(self, action_scale: float = 0.5, noise_level: float = 1.0, tracking_sigma: float = 0.25,
                 max_foot_height: float = 0.12, push_enable: bool = True, push_interval_range=(5.0, 10.0),
                 push_magnitude_range=(0.1, 2.0), command_min=(-1.5, -0.8, -1.5), command_max=(1.5, 0.8, 1.5),
                 command_zero_prob=(0.9, 0.25, 0.5), reward_scales: dict | None = None):
        self._configure({**locals(), "soft_joint_pos_limit_factor": 1.0, "base_height_target": 0.0,
                         "lin_vel_x": (command_min[0], command_max[0]), "lin_vel_y": (command_min[1], command_max[1]),
                         "ang_vel_yaw": (command_min[2], command_max[2])})
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        self.zero_prob = np.asarray(command_zero_prob, dtype=np.float64)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        self.default_ctrl = np.asarray(model.keyframe(self.keyframe)["ctrl"], dtype=np.float64)
        self.torque_limits = model.jnt_actfrcrange[1:, 1]
        self.steps_until_next_cmd = np.zeros(n, dtype=np.int64)

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """None: Playground's Apollo has no domain randomization."""

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """Zero, as Playground's reset leaves it."""
        return np.zeros((len(qpos), self.model.nu))

    def motor_targets(self, actions, qpos, ctrl, idx):
        return self.default_ctrl + actions * self.action_scale

    def sample_command(self, rng, x: np.ndarray | None = None) -> np.ndarray:
        """A first command U(min, max); later ones by Go1's rule (each component kept with
        probability ½, else redrawn and zeroed with probability 1 − ``command_zero_prob``)."""
        y = rng.uniform(self.cmd_lo, self.cmd_hi)
        if x is None:
            return y
        z = rng.random(3) < self.zero_prob
        w = rng.random(3) < 0.5
        return x - w * (x - y * z)

    def reset(self, idx: np.ndarray, rngs: list):
        qpos, qvel = super().reset(idx, rngs)
        for j, rng in enumerate(rngs):
            self.steps_until_next_cmd[idx[j]] = round(rng.exponential() * 5.0 / self.dt)
        return qpos, qvel

    def next_commands(self, idx: np.ndarray, rngs: list, done: np.ndarray) -> None:
        """Go1's: a redraw when the wait is over, a new wait then or after a fall."""
        redraw_commands(self, idx, rngs, done)

    def terminated(self, r) -> np.ndarray:
        return r.sensor("upvector")[:, 2] < 0.0

    def observe(self, r, idx: np.ndarray, rngs: list):
        state, gyro, linvel, gravity = self.noisy_state(r, idx, rngs)
        q, qd = r.qpos[:, 7:], r.qvel[:, 6:]
        priv = np.hstack([state, gyro, gravity, linvel, q - self.default_pose, qd, self.actuator_force(r), r.qpos[:, :7]])
        return state.astype(np.float32), priv.astype(np.float32)

    def reward_terms(self, r, a, idx, done, first_contact, contact, foot_z) -> dict:
        cmd, q, qd, tau = self.command[idx], r.qpos[:, 7:], r.qvel[:, 6:], self.actuator_force(r)
        local, gyro = r.sensor("local_linvel"), r.sensor("gyro")
        weights = np.where(np.linalg.norm(cmd, axis=1)[:, None] < 0.01, 1.0, POSE_WEIGHTS)
        weights[:, [21, 27]] = np.where(np.abs(cmd[:, 1:2]) > 0.3, 0.01, 1.0)
        collided = np.hstack([r.sensor(s) for s in COLLISIONS]) > 0
        lin_err, ang_err = np.sum((cmd[:, :2] - local[:, :2]) ** 2, axis=1), (cmd[:, 2] - gyro[:, 2]) ** 2
        return {
            "termination": done.astype(np.float64),
            "alive": 1.0 - done,
            "tracking": np.exp(-lin_err / self.sigma) + 0.5 * np.exp(-ang_err / self.sigma),
            "lin_vel_z": local[:, 2] ** 2,
            "ang_vel_xy": np.sum(gyro[:, :2] ** 2, axis=1),
            "orientation": np.sum(r.sensor("upvector")[:, :2] ** 2, axis=1),
            "feet_phase": np.exp(-np.sum((foot_z - gait_height(self.phase[idx], self.max_foot_height)) ** 2, axis=1) / 0.01),
            "torques": np.sum(np.abs(tau), axis=1),
            "action_rate": np.sum((a - self.last_act[idx]) ** 2, axis=1),
            "energy": np.sum(np.abs(qd * tau / self.torque_limits), axis=1),
            "collision": collided.any(axis=1).astype(np.float64),
            "pose": np.sum((q - self.default_pose) ** 2 * weights, axis=1),
        }


TASKS = {"ApolloJoystickFlatTerrain": ApolloJoystick}
