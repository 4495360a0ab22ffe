"""The LEAP hand's Playground task (``mujoco_playground/_src/manipulation/leap_hand``): spin a cube
about the vertical in the hand without dropping it, written from Playground's ``rotate_z.py`` and
``base.py``, with its domain randomization."""

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
#: Reward scales of Playground's ``rotate_z.default_config()``.
ROTATE_SCALES = dict(angvel=1.0, linvel=0.0, pose=0.0, torques=0.0, energy=0.0, termination=-100.0, action_rate=0.0)


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
    state = ("last_act", "last_last_act", "history")

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
        self.q_ids = np.array([adr[j][0] for j in JOINTS])
        self.v_ids = np.array([adr[j][1] for j in JOINTS])
        self.init_q = np.asarray(model.keyframe("home")["qpos"], dtype=np.float64)
        self.default_pose = self.init_q[self.q_ids]
        self.lowers, self.uppers = model.actuator_ctrlrange.T
        self.forces = tuple(model.actuator_forcerange.T)
        # the cube's free joint, the file's only one
        self.cube_q = next(a for t, a in zip(model.joint_types, model.jnt_qposadr) if t == "free")
        self.cube = model.body_names.index("cube")
        self.tips = [model.geom_names.index(t) for t in TIPS]
        self.hand_bodies = [model.body_names.index(b) for b in HAND_BODIES]
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
            rows["geom_friction"][j, self.tips, 0] = rng.uniform(0.5, 1.0)
            scale = rng.uniform(0.8, 1.2)
            rows["body_mass"][j, self.cube] *= scale
            rows["body_inertia"][j, self.cube] *= scale
            rows["body_ipos"][j, self.cube] += rng.uniform(-5e-3, 5e-3, 3)
            rows["dof_frictionloss"][j, self.v_ids] *= rng.uniform(0.5, 2.0, 16)
            rows["dof_armature"][j, self.v_ids] *= rng.uniform(1.0, 1.05, 16)
            rows["body_mass"][j, self.hand_bodies] *= rng.uniform(0.9, 1.1, len(self.hand_bodies))
            kp = rows["actuator_gain"][j, :, 0] * rng.uniform(0.8, 1.2, m.nu)
            rows["actuator_gain"][j, :, 0], rows["actuator_bias"][j, :, 1] = kp, -kp
            rows["dof_damping"][j, self.v_ids] *= rng.uniform(0.8, 1.2, 16)
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
            qpos[j, self.q_ids] = np.clip(self.default_pose + 0.1 * rng.normal(size=16), self.lowers, self.uppers)
            qpos[j, self.cube_q:self.cube_q + 3] = np.array([0.1, 0.0, 0.05]) + rng.uniform(-0.01, 0.01, 3)
            qpos[j, self.cube_q + 3:self.cube_q + 7] = uniform_quat(rng)
        for a in (self.last_act, self.last_last_act, self.history):
            a[idx] = 0
        return qpos, np.zeros((k, self.model.nv))

    def initial_ctrl(self, qpos: np.ndarray) -> np.ndarray:
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
        self.history[idx] = np.hstack([state, self.history[idx][:, :-32]])
        tips = np.hstack([r.sensor(f"{t}_position") for t in TIPS])
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


TASKS = {"LeapCubeRotateZAxis": LeapCubeRotateZAxis}
