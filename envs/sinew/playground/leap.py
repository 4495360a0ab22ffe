"""The LEAP hand's Playground tasks (``mujoco_playground/_src/manipulation/leap_hand``): spin a cube
about the vertical in the hand without dropping it, and turn it to goal orientations, written from
Playground's ``rotate_z.py``, ``reorient.py`` and ``base.py``, with their domain randomization."""

from __future__ import annotations

import numpy as np

from sinew.playground.task import Task, servo_force, uniform_noise

LEAP = "mujoco_playground/_src/manipulation/leap_hand/xmls"
JOINTS = ("if_mcp", "if_rot", "if_pip", "if_dip", "mf_mcp", "mf_rot", "mf_pip", "mf_dip", "rf_mcp", "rf_rot", "rf_pip", "rf_dip",
          "th_cmc", "th_axl", "th_mcp", "th_ipl")
TIPS = ("th_tip", "if_tip", "mf_tip", "rf_tip")
#: The hand's bodies whose masses the randomization scales.
HAND_BODIES = ("palm", "if_bs", "if_px", "if_md", "if_ds", "mf_bs", "mf_px", "mf_md", "mf_ds", "rf_bs", "rf_px", "rf_md", "rf_ds",
               "th_mp", "th_bs", "th_px", "th_ds")
#: Reward scales of Playground's ``rotate_z.default_config()`` and ``reorient.default_config()``.
ROTATE_SCALES = dict(angvel=1.0, linvel=0.0, pose=0.0, torques=0.0, energy=0.0, termination=-100.0, action_rate=0.0)
REORIENT_SCALES = dict(orientation=5.0, position=0.5, termination=-100.0, hand_pose=-0.5, action_rate=-0.001, joint_vel=0.0,
                       energy=-1e-3)


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of quaternions (rows: w, x, y, z)."""
    w1, x1, y1, z1 = a.T
    w2, x2, y2, z2 = b.T
    return np.stack([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2], axis=1)


def quat_conj(q: np.ndarray) -> np.ndarray:
    return q * [1.0, -1.0, -1.0, -1.0]


def newest_first(history: np.ndarray, new: np.ndarray) -> np.ndarray:
    """A history (rows) with ``new`` put first and its oldest entries dropped."""
    return np.hstack([new, history[:, :history.shape[1] - new.shape[1]]])


def linear_tolerance(x: np.ndarray, upper: float, margin: float) -> np.ndarray:
    """``reward.tolerance(x, (0, upper), margin, sigmoid="linear")``: 1 within the bounds, falling
    linearly to 0.1 at ``margin`` beyond them (and to 0 at 10/9 of it)."""
    d = np.maximum(x - upper, 0.0) / margin * 0.9
    return np.where(x <= upper, 1.0, np.where(d < 1.0, 1.0 - d, 0.0))


def uniform_quat(rng) -> np.ndarray:
    """``uniform_quat``: a rotation drawn uniformly (Shoemake's method), as Playground orders its
    components."""
    u, v, w = rng.random(3)
    return np.array([np.sqrt(1 - u) * np.sin(2 * np.pi * v), np.sqrt(1 - u) * np.cos(2 * np.pi * v),
                     np.sqrt(u) * np.sin(2 * np.pi * w), np.sqrt(u) * np.cos(2 * np.pi * w)])


class LeapCubeRotateZAxis(Task):
    """``LeapCubeRotateZAxis``: spin the cube about the world's z axis as fast as possible (the
    reward is its angular velocity about z, the episode ends with a −100 cost when it falls below
    the palm); the servo targets are the home pose + 0.6 a; the state holds the noisy joint angles
    and last action, the privileged state the hand's joints, velocities, servo forces, fingertips
    and the cube's pose and velocities."""

    xml = f"{LEAP}/scene_mjx_cube.xml"
    sim_dt, ctrl_dt, episode_length, action_scale = 0.01, 0.05, 500, 0.6
    camera = dict(distance=0.5, elevation=-30.0, azimuth=120.0, trackbodyid=-1, lookat=np.array([0.15, 0.0, 0.0]))
    pixels_camera = "side"
    sensors = ("cube_position", "cube_orientation", "cube_linvel", "cube_angvel", "palm_position",
               *(f"{t}_position" for t in TIPS))
    obs_sizes = (32, 105)
    reward_scales = ROTATE_SCALES
    state = ("last_act", "last_last_act", "history", "gain", "bias")
    #: The hand's joints, fingertips (sites and geoms of these names) and links.
    joints, tips, hand_bodies = JOINTS, TIPS, HAND_BODIES
    #: The cube's friction's range, when the randomization draws it.
    cube_friction: tuple | None = None

    def __init__(self, action_scale: float = 0.6, history_len: int = 1, noise_level: float = 1.0, joint_pos_noise: float = 0.05,
                 reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(ROTATE_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(ROTATE_SCALES)}")
        self.reward_scales = {**ROTATE_SCALES, **(reward_scales or {})}
        self.action_scale, self.history_len = float(action_scale), int(history_len)
        self.noise = float(noise_level) * float(joint_pos_noise)
        self.obs_sizes = (32 * self.history_len, 73 + 32)

    def setup(self, model, n: int) -> None:
        self.model = model
        adr = {name: (model.jnt_qposadr[k], model.jnt_dofadr[k]) for k, name in enumerate(model.joint_names)}
        self.q_ids = np.array([adr[j][0] for j in self.joints])
        self.v_ids = np.array([adr[j][1] for j in self.joints])
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[self.q_ids]
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.forces = tuple(model.actuator_forcerange.T)
        #: The range a reset's hand pose is clamped to.
        self.pose_range = (self.lowers, self.uppers)
        # the cube's free joint, the file's only one
        self.cube_q = next(a for t, a in zip(model.joint_types, model.jnt_qposadr) if t == "free")
        self.cube, self.cube_geom = model.body_names.index("cube"), model.geom_names.index("cube")
        self.tip_geoms = [model.geom_names.index(t) for t in self.tips]
        self.hand_body_ids = [model.body_names.index(b) for b in self.hand_bodies]
        # each world's servo gains (the randomization scales them)
        self.gain = np.tile(model.param("actuator_gain")[:, 0], (n, 1))
        self.bias = np.tile(model.param("actuator_bias"), (n, 1, 1))
        nu = model.nu
        self.last_act, self.last_last_act = np.zeros((n, nu)), np.zeros((n, nu))
        self.history = np.zeros((n, 32 * self.history_len))

    def randomize(self, batch, idx: np.ndarray, rngs: list) -> None:
        """``rotate_z.domain_randomize``: fingertip friction U(0.5, 1), the cube's mass and inertia
        ×U(0.8, 1.2) and centre of mass +U(±5 mm), the hand's joint friction ×U(0.5, 2), armature
        ×U(1, 1.05), link masses ×U(0.9, 1.1) (their inertias kept, as Playground keeps them),
        servo gains ×U(0.8, 1.2) and joint damping ×U(0.8, 1.2) (Playground's jitter of ``qpos0``
        changes nothing the task reads, and is left out)."""
        m, k = self.model, len(idx)
        rows = {f: np.repeat(m.param(f)[None], k, axis=0) for f in
                ("geom_friction", "body_mass", "body_ipos", "dof_frictionloss", "dof_armature", "dof_damping", "actuator_gain",
                 "actuator_bias", "body_inertia")}
        for j, rng in enumerate(rngs):
            rows["geom_friction"][j, self.tip_geoms, 0] = rng.uniform(0.5, 1.0)
            scale = rng.uniform(0.8, 1.2)
            rows["body_mass"][j, self.cube] *= scale
            rows["body_inertia"][j, self.cube] *= scale
            rows["body_ipos"][j, self.cube] += rng.uniform(-5e-3, 5e-3, 3)
            nh = len(self.v_ids)
            if self.cube_friction:
                rows["geom_friction"][j, self.cube_geom, 0] = rng.uniform(*self.cube_friction)
            rows["dof_frictionloss"][j, self.v_ids] *= rng.uniform(0.5, 2.0, nh)
            rows["dof_armature"][j, self.v_ids] *= rng.uniform(1.0, 1.05, nh)
            rows["body_mass"][j, self.hand_body_ids] *= rng.uniform(0.9, 1.1, len(self.hand_body_ids))
            kp = rows["actuator_gain"][j, :, 0] * rng.uniform(0.8, 1.2, m.nu)
            rows["actuator_gain"][j, :, 0], rows["actuator_bias"][j, :, 1] = kp, -kp
            rows["dof_damping"][j, self.v_ids] *= rng.uniform(0.8, 1.2, nh)
        # a new mass scales a body's inertia with it: the inertias are set after the masses
        for field in ("geom_friction", "body_mass", "body_inertia", "body_ipos", "dof_frictionloss", "dof_armature", "dof_damping",
                      "actuator_gain", "actuator_bias"):
            batch.set_params(field, rows[field], idx)
        self.gain[idx] = rows["actuator_gain"][:, :, 0]
        self.bias[idx] = rows["actuator_bias"]

    def reset(self, idx: np.ndarray, rngs: list):
        """The hand at its home pose + 0.1 N(0, 1) (clamped to the servos' ranges), the cube at
        (0.1, 0, 0.05) + U(±0.01) m in a uniformly drawn orientation, all at rest."""
        k = len(idx)
        qpos = np.tile(self.init_q, (k, 1))
        for j, rng in enumerate(rngs):
            qpos[j, self.q_ids] = np.clip(self.default_pose + 0.1 * rng.normal(size=len(self.q_ids)), *self.pose_range)
            qpos[j, self.cube_q:self.cube_q + 3] = np.array([0.1, 0.0, 0.05]) + rng.uniform(-0.01, 0.01, 3)
            qpos[j, self.cube_q + 3:self.cube_q + 7] = uniform_quat(rng)
        for a in (self.last_act, self.last_last_act, self.history):
            a[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The drawn joint angles."""
        return qpos[:, self.q_ids]

    def actuator_force(self, r) -> np.ndarray:
        gain, bias = self.gain[r.rows], self.bias[r.rows]
        target = np.clip(r.ctrl, self.lowers, self.uppers)
        q, qd = r.qpos[:, self.q_ids], r.qvel[:, self.v_ids]
        return np.clip(gain * target + bias[..., 0] + bias[..., 1] * q + bias[..., 2] * qd, *self.forces)

    def observe(self, r, idx: np.ndarray, rngs: list):
        q = r.qpos[:, self.q_ids]
        state = np.hstack([q + uniform_noise(rngs, 16, self.noise), self.last_act[idx]])
        self.history[idx] = newest_first(self.history[idx], state)
        tips = np.hstack([r.sensor(f"{t}_position") for t in self.tips])
        priv = np.hstack([state, q, r.qvel[:, self.v_ids], self.actuator_force(r), tips,
                          r.sensor("palm_position") - r.sensor("cube_position"), r.sensor("cube_orientation"),
                          r.sensor("cube_angvel"), r.sensor("cube_linvel")])
        return self.history[idx].astype(np.float32), priv.astype(np.float32)

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        state, priv = self.observe(r, idx, rngs)
        done = r.sensor("cube_position")[:, 2] < -0.05
        q, qd, tau = r.qpos[:, self.q_ids], r.qvel[:, self.v_ids], self.actuator_force(r)
        terms = {
            "angvel": r.sensor("cube_angvel")[:, 2],
            "linvel": np.sum(np.abs(r.sensor("cube_linvel")), axis=1),
            "termination": done.astype(np.float64),
            "action_rate": np.sum((actions - self.last_act[idx]) ** 2, axis=1),
            "pose": np.sum((q - self.default_pose) ** 2, axis=1),
            "torques": np.sum(tau ** 2, axis=1),
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = sum(terms.values()) * self.dt
        self.last_last_act[idx] = self.last_act[idx]
        self.last_act[idx] = actions
        return state, priv, reward, done, terms


class LeapCubeReorient(LeapCubeRotateZAxis):
    """``LeapCubeReorient``: turn the cube to a goal orientation (drawn uniformly per episode;
    after each success, within 0.1 rad, the goal spins off at a decaying random rate) and keep it
    in the palm; the servo targets step by 0.5 a from the last; the state holds noisy joint angles,
    servo errors, the noisy cube's offset from the palm and its rotation relative to the goal."""

    sim_dt, ctrl_dt, episode_length, action_scale = 0.01, 0.05, 1000, 0.5
    sensors = ("cube_position", "cube_orientation", "cube_linvel", "cube_angvel", "palm_position",
               *(f"{t}_position" for t in TIPS))
    reward_scales = REORIENT_SCALES
    state = ("last_act", "last_last_act", "qpos_error_history", "cube_pos_error_history", "cube_ori_error_history", "goal_quat",
             "goal_quat_dquat", "steps_since_last_success", "success_count", "gain", "bias")

    def __init__(self, action_scale: float = 0.5, history_len: int = 1, noise_level: float = 1.0, joint_pos_noise: float = 0.05,
                 cube_pos_noise: float = 0.02, cube_ori_noise: float = 0.1, success_threshold: float = 0.1,
                 success_reward: float = 100.0, reward_scales: dict | None = None):
        self.kwargs = {k: v for k, v in locals().items() if k not in ("self", "__class__", "reward_scales")}
        unknown = set(reward_scales or {}) - set(REORIENT_SCALES)
        if unknown:
            raise ValueError(f"unknown reward terms {sorted(unknown)}; this task's: {list(REORIENT_SCALES)}")
        self.reward_scales = {**REORIENT_SCALES, **(reward_scales or {})}
        self.action_scale, self.history_len = float(action_scale), int(history_len)
        level = float(noise_level)
        self.noise, self.pos_noise, self.ori_noise = level * float(joint_pos_noise), level * float(cube_pos_noise), level * float(cube_ori_noise)
        self.threshold, self.success_reward = float(success_threshold), float(success_reward)
        h = self.history_len
        self.obs_sizes = (32 + 25 * h, 32 + 25 * h + 71)

    def setup(self, model, n: int) -> None:
        super().setup(model, n)
        h = self.history_len
        self.qpos_error_history, self.cube_pos_error_history = np.zeros((n, 16 * h)), np.zeros((n, 3 * h))
        self.cube_ori_error_history = np.zeros((n, 6 * h))
        self.goal_quat, self.goal_quat_dquat = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)), np.zeros((n, 3))
        self.steps_since_last_success, self.success_count = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)

    def reset(self, idx: np.ndarray, rngs: list):
        """A goal drawn uniformly, then the hand and cube as ``LeapCubeRotateZAxis`` draws them."""
        for j, rng in enumerate(rngs):
            self.goal_quat[idx[j]] = uniform_quat(rng)
        qpos, qvel = super().reset(idx, rngs)
        for a in (self.qpos_error_history, self.cube_pos_error_history, self.cube_ori_error_history, self.goal_quat_dquat,
                  self.steps_since_last_success, self.success_count):
            a[idx] = 0
        return qpos, qvel

    def motor_targets(self, actions, qpos, ctrl, idx):
        return np.clip(ctrl + actions * self.action_scale, self.lowers, self.uppers)

    def relative_rotation(self, quat: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The last six entries of the rotation matrix of quat ⊗ goal⁻¹."""
        w, x, y, z = quat_mul(quat, quat_conj(self.goal_quat[idx])).T
        return np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1)

    def observe(self, r, idx: np.ndarray, rngs: list):
        q = r.qpos[:, self.q_ids]
        noisy_q = q + uniform_noise(rngs, 16, self.noise)
        push = newest_first
        self.qpos_error_history[idx] = push(self.qpos_error_history[idx], noisy_q - r.ctrl)
        cube_pos, cube_quat, palm = r.sensor("cube_position"), r.sensor("cube_orientation"), r.sensor("palm_position")
        noisy_quat = cube_quat + np.array([rng.normal(size=4) for rng in rngs]).reshape(-1, 4) * self.ori_noise
        noisy_quat /= np.linalg.norm(noisy_quat, axis=1, keepdims=True)
        noisy_pos = cube_pos + uniform_noise(rngs, 3, self.pos_noise)
        self.cube_pos_error_history[idx] = push(self.cube_pos_error_history[idx], palm - noisy_pos)
        self.cube_ori_error_history[idx] = push(self.cube_ori_error_history[idx], self.relative_rotation(noisy_quat, idx))
        state = np.hstack([noisy_q, self.qpos_error_history[idx], self.cube_pos_error_history[idx], self.cube_ori_error_history[idx],
                           self.last_act[idx]])
        tips = np.hstack([r.sensor(f"{t}_position") for t in self.tips])
        # no perturbation (Playground's are off by default): its direction and force are zero
        priv = np.hstack([state, q, r.qvel[:, self.v_ids], tips, palm - cube_pos, self.relative_rotation(cube_quat, idx),
                          r.sensor("cube_linvel"), r.sensor("cube_angvel"), np.zeros((len(idx), 12))])
        return state.astype(np.float32), priv.astype(np.float32)

    def orientation_error(self, r, idx: np.ndarray) -> np.ndarray:
        """The angle between the cube's orientation and the goal's."""
        d = quat_mul(r.sensor("cube_orientation"), quat_conj(self.goal_quat[idx]))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        return 2.0 * np.arcsin(np.minimum(np.linalg.norm(d[:, 1:], axis=1), 1.0))

    def after_step(self, r, actions: np.ndarray, idx: np.ndarray, rngs: list):
        error = self.orientation_error(r, idx)
        success = error < self.threshold
        self.steps_since_last_success[idx] = np.where(success, 0, self.steps_since_last_success[idx] + 1)
        self.success_count[idx] += success
        done = r.sensor("cube_position")[:, 2] < -0.05
        state, priv = self.observe(r, idx, rngs)
        q, qd, tau = r.qpos[:, self.q_ids], r.qvel[:, self.v_ids], self.actuator_force(r)
        last, last_last = self.last_act[idx], self.last_last_act[idx]
        terms = {
            "orientation": linear_tolerance(error, 0.2, np.pi),
            "position": linear_tolerance(np.linalg.norm(r.sensor("palm_position") - r.sensor("cube_position"), axis=1), 0.02, 0.05),
            "termination": done.astype(np.float64),
            "hand_pose": np.sum((q - self.default_pose) ** 2, axis=1),
            "action_rate": np.sum((actions - last) ** 2, axis=1) + np.sum((actions - 2 * last + last_last) ** 2, axis=1),
            "joint_vel": np.sum((qd / 4.0) ** 2, axis=1),
            "energy": np.sum(np.abs(qd) * np.abs(tau), axis=1),
        }
        terms = {k: v * self.reward_scales[k] for k, v in terms.items()}
        reward = sum(terms.values()) * self.dt + success * self.success_reward
        # a reached goal spins off at 3 + U(±2) rad/s about each of its axes, a rate that decays by
        # 0.8 a step
        for j, rng in enumerate(rngs):
            draw = 3.0 + rng.uniform(-2.0, 2.0, 3)
            i = idx[j]
            self.goal_quat_dquat[i] = draw if success[j] else 0.8 * self.goal_quat_dquat[i]
            w = self.goal_quat_dquat[i]
            angle = np.linalg.norm(w) * 2 * self.dt
            if angle > 0.0:
                axis = w / np.linalg.norm(w)
                turn = np.array([[np.cos(angle / 2), *(np.sin(angle / 2) * axis)]])
                g = quat_mul(self.goal_quat[i:i + 1], turn)[0]
                self.goal_quat[i] = g / np.linalg.norm(g)
        self.last_last_act[idx] = last
        self.last_act[idx] = actions
        return state, priv, reward, done, terms


TASKS = {"LeapCubeRotateZAxis": LeapCubeRotateZAxis, "LeapCubeReorient": LeapCubeReorient}
